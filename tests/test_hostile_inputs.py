"""The inputs that broke v0.1, each refused with exit 2 and a message
naming the field, and work too large for memory refused before it starts."""

from __future__ import annotations

from pathlib import Path

import pytest
from fuzzing import run_sso

import sso

STEERING = (Path(__file__).resolve().parents[1] / "cases" / "steering_column.toml").read_text()


@pytest.mark.parametrize(("line", "message"), [
    ("input_speed_rpm = 1e308", "input_speed_rpm = 1e+308 is outside the allowed range"),
    ("kind = []", "kind = [] is not one of"),
    ("input_speed_rpm = " + "9" * 5000, "a number cannot be read"),
    ("input_speed_rpm = " + "9" * 400,
     "input_speed_rpm = <integer of 400 digits> is too large for a float"),
    ("input_speed_rpm = " + "[" * 3000 + "]" * 3000, "nested too deeply"),
])
def test_hostile_values_are_refused_naming_the_field(tmp_path, line, message):
    case = tmp_path / "case.toml"
    # the hostile line replaces the case's own speed (keys may appear once)
    case.write_text(line + "\n" + STEERING.replace("input_speed_rpm = 60.0\n", ""))
    code, text = run_sso(["validate", str(case)])
    assert code == 2, text
    assert message in text
    assert "Traceback" not in text


def test_a_name_derived_from_the_file_name_is_checked_like_a_given_one(tmp_path):
    # "...toml" has the stem of two dots: v0.1 wrote its report one folder above --out
    case = tmp_path / "...toml"
    case.write_text(STEERING.replace('name = "steering_column"\n', ""))
    code, text = run_sso(["run", str(case), "--out", str(tmp_path / "out")])
    assert code == 2
    assert "name = '" + "." * 2 + "' must be 1 to 100 letters" in text
    assert "comes from the file name" in text
    assert sorted(path.name for path in tmp_path.iterdir()) == ["...toml"]


def test_a_sweep_step_too_small_to_count_is_refused(tmp_path):
    sweep = tmp_path / "sweep.toml"
    sweep.write_text('case = "case.toml"\n[axes]\n'
                     '"input_speed_rpm" = { start = 10.0, stop = 20.0, step = 5e-324 }\n')
    (tmp_path / "case.toml").write_text(STEERING)
    code, text = run_sso(["sweep", str(sweep), "--out", str(tmp_path / "out")])
    assert code == 2, text
    assert "step = 4.94066e-324 from 10 to 20 spans more values than the allowed range" in text


def test_a_tolerance_study_too_large_for_memory_is_refused_before_drawing():
    # 1e8 samples of 64 joints: v0.1 tried to allocate 47.7 GiB. Each sample holds
    # 4 arrays of 127 angles (4 kB), 3 metrics and ~3.3 kB of CSV text.
    series = sso.ShaftSeries([10.0] * 64, [90.0] * 63)
    with pytest.raises(ValueError, match=r"tolerance study \(100,000,000 samples of 64 joints\): "
                                         r"about [\d,]+ MB .* above the memory limit of 4,096 MB; "
                                         r"lower samples"):
        sso.tolerance_study(series, samples=100_000_000, memory_limit_mb=4096)


def test_the_memory_limit_is_configurable_and_checked():
    series = sso.ShaftSeries([10.0, 20.0], [90.0], "paper")
    small = sso.tolerance_study(series, samples=100, memory_limit_mb=1000)
    assert len(small.residual_error) == 100
    # The paper model evaluates 100 samples in one block of 16 arrays of 100 x 1024
    # angles: 13 MB, on top of the process itself (sso._studies.estimate.PROCESS_MB, 80 MB)
    with pytest.raises(ValueError, match="about 93 MB .* above the memory limit of 90 MB"):
        sso.tolerance_study(series, samples=100, workers=1, memory_limit_mb=90)
    # The exact model's figures are closed forms (no angle grid): the same study fits
    exact = sso.tolerance_study(sso.ShaftSeries([10.0, 20.0], [90.0]), samples=100, workers=1,
                          memory_limit_mb=90)
    assert len(exact.residual_error) == 100
    with pytest.raises(ValueError, match=r"memory_limit_mb = -1 is outside"):
        sso.tolerance_study(series, samples=100, memory_limit_mb=-1)


def test_a_multistart_too_large_for_memory_is_refused_before_building():
    # 64 joints, option 3 (127 free angles), the paper model (a quadrature graph): the
    # exact Hessian alone is estimated at 10 + 0.26 * 64 * 127 = 2,123 MB (0.26 MB per
    # joint and free angle, measured), plus the solving process (60 MB) and 20,000
    # kept runs (200 MB): 2,383 MB; the exact model's closed form is far smaller
    series = sso.ShaftSeries([10.0] * 64, [90.0] * 63, "paper")
    with pytest.raises(ValueError, match=r"multi-start run \(64 joints, 127 free angles, "
                                         r"10000 starts x 2 solvers\): about 2,383 MB and "
                                         r"20,000 solves, above the memory limit of 1,000 MB"):
        sso.optimise(series, starts=10_000, memory_limit_mb=1000)


def test_a_sweep_too_large_for_memory_is_refused_from_the_cli(tmp_path, monkeypatch):
    (tmp_path / "case.toml").write_text(STEERING)
    sweep = tmp_path / "sweep.toml"
    sweep.write_text('case = "case.toml"\naction = "evaluate"\n[axes]\n'
                     '"input_speed_rpm" = { start = 10.0, stop = 20.0, num = 1000000 }\n')
    code, text = run_sso(["sweep", str(sweep), "--memory-limit", "1000", "--out",
                          str(tmp_path / "out")])
    assert code == 2
    assert "sweep (1,000,000 points): about 3,906 MB and 1,000,000 solves, above the " \
           "memory limit of 1,000 MB; use fewer points" in text
    monkeypatch.setenv("SSO_MEMORY_LIMIT_MB", "100")
    code, text = run_sso(["sweep", str(sweep), "--out", str(tmp_path / "out")])
    assert code == 2
    assert "above the memory limit of 100 MB" in text
