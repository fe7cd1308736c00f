"""The local-pool path never imports dask; a run without plots never imports matplotlib."""

import json
import subprocess
import sys

SCRIPT = """
import json
import sys

import sso

if __name__ == "__main__":
    result = sso.sweep({"design": {"beta_deg": [20.0, 30.0], "phase_deg": [90.0]},
                        "solver": {"starts": 1, "solvers": ["slsqp"]}},
                       {"design.beta_deg[0]": [10.0, 20.0, 30.0, 40.0]},
                       out_dir=sys.argv[1], workers=2, chunk_size=1, plots=False)
    tolerance = sso.tolerance_study(sso.ShaftSeries([20.0, 30.0]), samples=40, chunk_size=10,
                              workers=2)
    loaded = sorted(name for name in sys.modules
                    if name.split(".")[0] in ("dask", "distributed", "matplotlib"))
    print(json.dumps({"loaded": loaded, "statuses": [row["status"] for row in result.rows],
                      "samples": tolerance.samples}))
"""


def test_the_local_pool_path_leaves_dask_and_matplotlib_unimported(tmp_path):
    script = tmp_path / "run_sweep.py"
    script.write_text(SCRIPT)
    completed = subprocess.run([sys.executable, str(script), str(tmp_path / "out")],
                               capture_output=True, text=True, check=True, timeout=300)
    report = json.loads(completed.stdout.strip().splitlines()[-1])
    assert report == {"loaded": [], "statuses": ["ok"] * 4, "samples": 40}
