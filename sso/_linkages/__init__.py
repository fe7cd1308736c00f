"""Planar mechanisms: the linkage registry, the linkages, their tables and the four-bar design."""
