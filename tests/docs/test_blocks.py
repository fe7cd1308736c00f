"""The code-block runner itself: what it reads, runs and compares."""

from __future__ import annotations

import pytest

from doctools.blocks import (
    OutputMismatch,
    PageRun,
    _merge,
    classify,
    line_matches,
    output_matches,
    read_blocks,
    run_block,
)

PAGE = """# A page

```python
value = 6 * 7
print(value)
```

```output
42
```

```python
print(value + 1)
```

```output
99
```

```text
sso run CASE.toml [--out DIR]
```
"""


def test_blocks_outputs_and_their_languages(tmp_path):
    page = tmp_path / "page.md"
    page.write_text(PAGE)
    blocks = read_blocks(page)
    assert [(block.language, block.runs) for block in blocks] == [
        ("python", True), ("python", True), ("text", False)]
    assert blocks[0].output is not None and blocks[0].output.text == "42"


def test_a_changed_output_fails_and_state_carries_over(tmp_path):
    page = tmp_path / "page.md"
    page.write_text(PAGE)
    first, second, _ = read_blocks(page)
    run = PageRun(page, tmp_path / "work")
    assert run_block(first, run) == "42\n"
    with pytest.raises(OutputMismatch, match="the page shows\n99\n--- the code printed\n43"):
        run_block(second, run)


def test_ellipsis_matches_within_a_line_only():
    assert line_matches("took ... s", "took 1.25 s")
    assert not line_matches("took 1.2 s", "took 1.25 s")
    assert output_matches("a\n...", "a\nb")
    assert not output_matches("a\n...", "a\nb\nc")
    assert _merge("time ...\n\nb", "\ntime 3\nc") == "\ntime ...\nc"


@pytest.mark.parametrize(("command", "kind"), [
    ("sso run cases/x.toml", "sso"),
    (".venv/bin/sso validate x.toml", "sso"),
    ("python -m sso --help", "sso"),
    ('.venv/bin/pip install -e ".[test,dask]"', "install"),
    ("python3 -m venv .venv", "install"),
    (".venv/bin/python -m pytest -q", "tests"),
    (".venv/bin/python -m benchmarks.work_precision --quick", "benchmark"),
    ("mkdocs build --strict", "docs"),
    ("rm -rf results", "unknown"),
])
def test_shell_commands_are_classified(command, kind):
    assert classify(command) == kind


def test_an_unknown_shell_command_fails(tmp_path):
    page = tmp_path / "page.md"
    page.write_text("```bash\nrm -rf results\n```\n")
    (block,) = read_blocks(page)
    with pytest.raises(AssertionError, match="unknown command 'rm -rf results'"):
        run_block(block, PageRun(page, tmp_path / "work"))


def test_a_varying_column_matches_whatever_its_width():
    shown = "case  solved  0.00193       ...       results/case"
    assert line_matches(shown, "case  solved  0.00193       0.32      results/case")
    assert line_matches(shown, "case  solved  0.00193       12.5      results/case")
    assert not line_matches(shown, "case  solved  0.00194       0.32      results/case")


def test_regenerated_output_elides_wall_times():
    from doctools.blocks import with_wall_times_elided

    assert with_wall_times_elided("case  solved  0.0104  0.00193       0.32      results/case") == (
        "case  solved  0.0104  0.00193       ...       results/case")
    assert with_wall_times_elided("sweep: 2 points (2 computed in 3.3 s, 0.6 points/s; 0 from") == (
        "sweep: 2 points (2 computed in ... points/s; 0 from")
