"""The paper's trial designs, whose starts lie outside the bounds of its own cases.

The shipped case files ``cases/paper_option*.toml`` start inside their bounds (the
paper's start clipped onto them), so they run without a warning. The checks with
known answers in ``docs/model.md`` ("Checks with known answers") are about the
paper's trial designs themselves; :func:`paper_trial_case` writes a copy of a shipped
case with the paper's start restored.
"""

import re
from pathlib import Path

CASES = Path(__file__).resolve().parents[1] / "cases"
PAPER_TRIAL_BETA_DEG = {2: (10.0, 15.0, 30.0), 3: (30.0, 40.0, 50.0)}
"""The paper's starts of options 2 and 3 (docs/model.md, "The paper's three cases")."""
PAPER_BETA_BOUNDS_DEG = {2: (7.0, 25.0), 3: (10.0, 40.0)}
"""The bounds its results imply (same table)."""


def paper_trial_case(option: int, model: str, folder: Path) -> Path:
    """Write ``paper_option<option>_<model>.toml`` with the paper's start into ``folder``."""
    text = (CASES / f"paper_option{option}_{model}.toml").read_text(encoding="utf-8")
    trial = ", ".join(f"{beta:.1f}" for beta in PAPER_TRIAL_BETA_DEG[option])
    text, count = re.subn(r"^beta_deg = \[[^\]]*\]", f"beta_deg = [{trial}]", text, count=1,
                          flags=re.MULTILINE)
    assert count == 1, "the case file has no [design] beta_deg line"
    path = folder / f"paper_option{option}_{model}.toml"
    path.write_text(text, encoding="utf-8")
    return path
