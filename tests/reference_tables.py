"""Where the tests find the published tables they compare against.

The tables are CSV copies of the mechanism papers' numeric tables, kept in this
repository under ``tests/data/reference/``; their provenance and the verdict on
each column (OK or DEFECT) are in ``tests/data/reference/README.md``.
"""

from pathlib import Path

REFERENCE = Path(__file__).resolve().parent / "data" / "reference"
"""Folder holding the reference CSV tables and their README."""
