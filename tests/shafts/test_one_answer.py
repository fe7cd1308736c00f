"""One design, one answer: ``"lm"`` gives the same bits wherever and whenever it runs.

36 random designs (3 to 6 joints, options 1, 2 and 3, three of each shape) are solved by
``sso.optimise(series, option, solvers=("lm",), starts=1)``: in a fresh process (a real
subprocess) each at its shape's first call (the process's shapes dropped before each),
in another fresh process after 200 other solves of the same shapes, in this process
(after whatever the other tests ran), in ``sso.optimise_batch`` (amid other designs), in
a sweep on two worker processes and in a sweep on a Dask cluster (a real
``LocalCluster``). Reference: the answer in the first fresh process. Each answer is
compared as ``float.hex`` of the design's angles, of RE and the iteration count (a
sweep's row holds no iteration count: its design and the solver's RE are compared).
"""

import json
import subprocess
import sys

import numpy as np
import pytest

import sso
from sso._studies.element_columns import gathered

# The designs and the single solve, one source for this process and the subprocesses.
SOURCE = '''
import json, sys, warnings
import numpy as np
import sso
from sso._solvers.nlp import cached_shapes

BOUNDS = (5.0, 35.0)
SHAPES = [(joints, option) for joints in (3, 4, 5, 6) for option in (1, 2, 3)]


def designs(seed=20261202, per_shape=3):
    rng = np.random.default_rng(seed)
    return [(joints, option, rng.uniform(5.0, 35.0, joints).tolist(),
             rng.uniform(0.0, 180.0, joints - 1).tolist())
            for joints, option in SHAPES for _ in range(per_shape)]


def answer_of(best):
    return [[value.hex() for value in best.series.beta_deg],
            [value.hex() for value in best.series.phase_deg], best.fun.hex(), best.nit]


def solve(design):
    joints, option, beta_deg, phase_deg = design
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sso.StartMovedWarning)
        return sso.optimise(sso.ShaftSeries(beta_deg, phase_deg), option, solvers=("lm",),
                            starts=1, beta_bounds_deg=BOUNDS).best


def main(mode):
    if mode == "after":
        for design in designs(seed=7, per_shape=17)[:200]:
            solve(design)
    answers = []
    for design in designs():
        if mode == "first":
            cached_shapes().clear()
        answers.append(answer_of(solve(design)))
    print(json.dumps(answers))
'''
NAMES: dict = {}
exec(SOURCE, NAMES)  # noqa: S102 - the same source the subprocesses run


def _in_fresh_process(mode):
    completed = subprocess.run([sys.executable, "-c", SOURCE + f"\nmain({mode!r})\n"],
                               capture_output=True, text=True, timeout=600, check=False)
    assert completed.returncode == 0, completed.stderr
    return json.loads(completed.stdout)


@pytest.fixture(scope="module")
def reference():
    answers = _in_fresh_process("first")
    assert len(answers) == 36
    return answers


def _groups():
    # Designs by shape, with their places in the list.
    groups = {}
    for index, design in enumerate(NAMES["designs"]()):
        groups.setdefault(design[:2], []).append((index, design))
    return groups


def test_the_designs_reach_several_ends(reference):
    # The comparison bites only if the designs do different things: zero and nonzero
    # minima, short and long solves.
    nits = {answer[3] for answer in reference}
    zeros = sum(float.fromhex(answer[2]) <= 1e-20 for answer in reference)
    assert len(nits) >= 5
    assert 5 <= zeros <= 31


def test_after_200_other_solves_in_a_fresh_process(reference):
    assert _in_fresh_process("after") == reference


def test_in_this_process_after_whatever_ran_before(reference):
    assert [NAMES["answer_of"](NAMES["solve"](design)) for design in NAMES["designs"]()] == (
        reference)


@pytest.mark.filterwarnings("ignore::sso.StartMovedWarning")
def test_in_optimise_batch_amid_other_designs(reference):
    rng = np.random.default_rng(5)
    for (joints, option), members in _groups().items():
        # Two other designs before each of the shape's designs.
        beta_deg = [row for _, design in members
                    for row in (*rng.uniform(5.0, 35.0, (2, joints)), design[2])]
        phase_deg = [row for _, design in members
                     for row in (*rng.uniform(0.0, 180.0, (2, joints - 1)), design[3])]
        batch = sso.optimise_batch(beta_deg, phase_deg, option=option,
                                   beta_bounds_deg=NAMES["BOUNDS"])
        for place, (index, _) in enumerate(members):
            row = 3 * place + 2
            assert [[value.hex() for value in batch.beta_deg[row].tolist()],
                    [value.hex() for value in batch.phase_deg[row].tolist()],
                    float(batch.fun[row]).hex(), int(batch.nit[row])] == reference[index]


def _sweep_answers(**where):
    # One sweep per shape, its designs as listed points; the design and the solver's RE.
    answers = {}
    for (joints, option), members in _groups().items():
        base = {"design": {"beta_deg": members[0][1][2], "phase_deg": members[0][1][3]},
                "option": option, "bounds": {"beta_deg": list(NAMES["BOUNDS"])},
                "solver": {"starts": 1, "solvers": ["lm"]}}
        axes = {**{f"design.beta_deg[{k}]": [design[2][k] for _, design in members]
                   for k in range(joints)},
                **{f"design.phase_deg[{k}]": [design[3][k] for _, design in members]
                   for k in range(joints - 1)}}
        result = sso.sweep(base, axes, mode="listed", chunk_size=1, progress=False,
                           plots=False, **where)
        for (index, _), row in zip(members, sorted(result.rows, key=lambda row: row["point"]),
                                   strict=True):
            answers[index] = [[value.hex() for value in gathered(row, "design_beta_deg")],
                              [value.hex() for value in gathered(row, "design_phase_deg")],
                              row["lm_residual_error"].hex()]
    return [answers[index] for index in range(len(answers))]


def test_in_a_sweep_on_two_worker_processes(reference):
    assert _sweep_answers(workers=2) == [answer[:3] for answer in reference]


def test_in_a_sweep_on_a_dask_cluster(reference):
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  host="127.0.0.1", dashboard_address=":0") as cluster:
        with distributed.Client(cluster) as client:
            answers = _sweep_answers(client=client)
    assert answers == [answer[:3] for answer in reference]
