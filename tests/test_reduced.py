"""The reduced model (morphlearn.reduced): the authors' robot's planar motion with ODE's contacts
and motors. Checked against the authors' facts (the canonical design's 11 x 11 overlap, its only
generalist), against the committed exhaustive ODE results cell by cell, and for the properties the
workflow relies on (mirror symmetry to the bit, batch independence, the motor solve, bad input)."""

from __future__ import annotations

import itertools
from pathlib import Path

import numpy as np
import pytest
from conftest import CANONICAL_O_11

from morphlearn import metrics, store
from morphlearn.grid import DesignGrid, weights
from morphlearn.physics.params import load_params
from morphlearn.reduced import body as bodymod
from morphlearn.reduced.core import run
from morphlearn.reduced.episode import evaluate_design

ROOT = Path(__file__).resolve().parents[1]

BODY = load_params("config/authors_body.yaml")
CANONICAL = ((0.5, 0.5), (0.5, -0.5))
PAPER_BEST = ((-0.5, 0.125), (0.5, -0.375))


def _cells(m: int) -> tuple[np.ndarray, np.ndarray]:
    w = weights(m)
    e, i, j = np.meshgrid(np.arange(4), np.arange(m), np.arange(m), indexing="ij")
    return np.stack([w[i.ravel()], w[j.ravel()]], 1), e.ravel()


def test_canonical_design_on_11_x_11_is_the_authors_overlap() -> None:
    res = evaluate_design(*CANONICAL, weights(11), BODY)
    o = metrics.overlap(np.isfinite(res.first_time))
    want = np.array([[int(v) for v in r.split(",")] for r in CANONICAL_O_11.split()])
    assert (o == want).mean() >= 0.98  # ODE's own matrix; the reduced model may differ in a cell or two
    assert int((o == 4).sum()) == 1 and o[-1, -1] == 4  # the only generalist is (1, 1), as in the paper


def test_canonical_generalist_reaches_the_light_when_ode_does() -> None:
    """w = (1, 1), every light: ODE (this engine's facts, measured with morphlearn.ode) first reaches
    the success radius at steps 472 (lights 1, 4) and 2465 (2, 3), 0.95409 and 0.94013 from the
    light at that step; the reduced model within 1 % of both. (Past success ODE's robot touches the
    light, a body here absent: closest approaches are compared up to success, as outcomes are.)"""
    ep, _ = run(BODY, *CANONICAL, [[1.0, 1.0]] * 4, np.arange(4))
    assert ep.success.all()
    assert np.allclose(ep.first_step, [472, 2465, 2465, 472], rtol=0.01)
    assert np.allclose(ep.min_dist, [0.95409, 0.94013, 0.94013, 0.95409], rtol=0.01)


def test_agrees_with_the_committed_exhaustive_ode_results_cell_by_cell() -> None:
    """The paper's best design, every w1 row from 100 (its generalists lie in rows 101-120), all 121
    columns and 4 lights: the ODE arrays of results/ode-paper against the reduced model's."""
    from morphlearn.figures.data import load_results

    ode = load_results("results/ode-paper", "ode")
    assert ode is not None
    pos = ode.position(*PAPER_BEST)
    want = ode.success(pos)[:, 100:, :]
    w = ode.weights
    e, i, j = np.meshgrid(np.arange(4), np.arange(100, 121), np.arange(121), indexing="ij")
    ep, _ = run(BODY, *PAPER_BEST, np.stack([w[i.ravel()], w[j.ravel()]], 1), e.ravel())
    got = ep.success.reshape(want.shape)
    assert (got == want).mean() >= 0.995
    assert abs(int((got.sum(0) == 4).sum()) - int((want.sum(0) == 4).sum())) <= 2  # ODE: 57


@pytest.mark.parametrize("design", [478, 160, 3000])
def test_mirror_image_is_exact_to_the_bit(design: int) -> None:
    g = DesignGrid(9)
    w = weights(9)
    c, mc = g.coords(design), g.coords(int(g.mirror(design)))
    a = evaluate_design((c[0], c[1]), (c[2], c[3]), w, BODY)
    b = evaluate_design((mc[0], mc[1]), (mc[2], mc[3]), w, BODY)
    derived = store.mirror_arrays({"first_time": a.first_time, "min_dist": a.min_dist})
    assert np.array_equal(derived["min_dist"], b.min_dist)
    assert np.array_equal(derived["first_time"], b.first_time, equal_nan=True)


def test_an_episode_does_not_depend_on_its_batch() -> None:
    w, env = _cells(5)
    whole, _ = run(BODY, *PAPER_BEST, w, env)
    rev, _ = run(BODY, *PAPER_BEST, w[::-1], env[::-1])
    one, _ = run(BODY, *PAPER_BEST, w[7:8], env[7:8])
    assert np.array_equal(whole.min_dist, rev.min_dist[::-1]) and whole.min_dist[7] == one.min_dist[0]
    # the path-recording episode is the same arithmetic
    ep, track = run(BODY, *PAPER_BEST, w[:6], env[:6], path=True)
    assert np.array_equal(ep.min_dist, whole.min_dist[:6]) and track is not None
    d = np.hypot(*(track[0, : ep.steps[0] + 1] - np.array([0.0, 0.0])).T)
    assert d[0] == 0.0


def test_motor_solve_is_the_box_constrained_solution() -> None:
    """The projected Gauss-Seidel fixed point against brute force over the nine active sets."""
    from morphlearn.reduced.cpu import _k

    b = bodymod.body(BODY, *PAPER_BEST)
    k00, k01, k11 = b.kk[:3]
    rng = np.random.default_rng(1)
    for r0, r1 in rng.normal(0, 0.2, (500, 2)):
        a, c = _k.motors(b.kk, r0, r1, BODY.max_torque)
        best = min(
            (0.5 * (k00 * x * x + 2 * k01 * x * y + k11 * y * y) - r0 * x - r1 * y, x, y)
            for x, y in _candidates(k00, k01, k11, r0, r1, BODY.max_torque)
        )
        assert abs(a - best[1]) < 1e-9 and abs(c - best[2]) < 1e-9


def test_motor_solve_is_exact_where_the_wheels_couple_strongly() -> None:
    """A body whose wheels couple almost rigidly (|k01| / k00 = 0.999, as with masses x 1e-6): the
    sweeps do not settle in their budget, and the active-set solve gives the brute-force solution."""
    from morphlearn.reduced.cpu import _k

    k00, k01, k11 = 555.96, 555.40, 555.96
    inv = np.linalg.inv(np.array([[k00, k01], [k01, k11]]))
    kk = np.array([k00, k01, k11, inv[0, 0], inv[0, 1], inv[1, 1], 1 / k00, 1 / k11])
    rng = np.random.default_rng(2)
    t = BODY.max_torque
    capped = 0
    for r0, r1 in rng.normal(0, 5000.0, (500, 2)):
        a, c = _k.motors(kk, r0, r1, t)
        best = min(
            (0.5 * (k00 * x * x + 2 * k01 * x * y + k11 * y * y) - r0 * x - r1 * y, x, y)
            for x, y in _candidates(k00, k01, k11, r0, r1, t)
        )
        assert abs(a - best[1]) < 1e-9 * t and abs(c - best[2]) < 1e-9 * t
        capped += abs(a) == t or abs(c) == t
    assert capped > 100  # the capped cases, where the sweeps alone fall short, were exercised


def _candidates(k00: float, k01: float, k11: float, r0: float, r1: float, t: float) -> list[tuple[float, float]]:
    out = []
    for sa, sb in itertools.product((None, -t, t), repeat=2):
        if sa is None and sb is None:
            det = k00 * k11 - k01 * k01
            x, y = (k11 * r0 - k01 * r1) / det, (k00 * r1 - k01 * r0) / det
        elif sa is None:
            y = sb
            x = (r0 - k01 * y) / k00
        elif sb is None:
            x = sa
            y = (r1 - k01 * x) / k11
        else:
            x, y = sa, sb
        if abs(x) <= t + 1e-12 and abs(y) <= t + 1e-12:
            out.append((x, y))
    return out


def test_body_constants_follow_the_ode_set_up() -> None:
    m, s = bodymod.mass_matrix(BODY, *CANONICAL)
    total = BODY.body_mass + 2 * BODY.wheel_mass + BODY.castor_mass + 2.0
    assert m[0, 0] == pytest.approx(total) and m[1, 1] == pytest.approx(total)
    # the wheels set back 0.025, the sensors at x = 0.5, the castor at 0.5
    assert s[0] == pytest.approx(-2 * BODY.wheel_mass * 0.025 + BODY.castor_mass * 0.5 + 2 * 0.5)
    assert s[1] == pytest.approx(0.0)
    yaw = BODY.body_mass / 6 + 2 * (0.4 * BODY.wheel_mass * BODY.wheel_radius**2 + BODY.wheel_mass * (0.25 + 0.025**2))
    assert m[2, 2] == pytest.approx(
        yaw + BODY.castor_mass * (0.4 * BODY.wheel_radius**2 + 0.25) + 2 * (0.001 + 0.5), rel=1e-9
    )


@pytest.mark.parametrize(
    ("l1", "w", "env", "msg"),
    [
        ((0.6, 0.0), [[0.0, 0.0]], [0], "off the body"),
        ((0.0, 0.0), [[1.5, 0.0]], [0], "weight 1.5"),
        ((0.0, 0.0), [[np.nan, 0.0]], [0], "weight nan"),
        ((0.0, 0.0), [[0.0, 0.0]], [4], "env [4]"),
    ],
)
def test_bad_input_is_one_line(l1: tuple[float, float], w: list[list[float]], env: list[int], msg: str) -> None:
    with pytest.raises(ValueError, match=msg.replace("[", r"\[").replace("]", r"\]")):
        run(BODY, l1, (0.0, 0.0), w, env)


_CUDA_SCRIPT = """
import sys
import numpy as np
from numba import cuda
from morphlearn.physics.params import load_params
from morphlearn.reduced.core import run
assert cuda.is_available()  # the simulator counts as a device
body = load_params("config/authors_body.yaml").replace(steps=int(sys.argv[2]))
w = np.array([[1.0, 1.0], [1.0, 1.0], [-0.6, 0.8], [0.3, -1.0], [1.0, 0.9], [0.0, 0.0]])
env = np.array([0, 1, 2, 3, 0, 1])
ep, _ = run(body, (0.5, 0.5), (0.5, -0.5), w, env, backend="cuda")
np.savez(sys.argv[1], first=ep.first_step, dmin=ep.min_dist, steps=ep.steps, finite=ep.finite)
"""


def test_cuda_kernel_under_the_simulator_matches_the_cpu_kernel(tmp_path: object) -> None:
    """The CUDA path (one thread an episode, the same episode source) run by numba's CUDA simulator
    in a subprocess (NUMBA_ENABLE_CUDASIM must be set before numba.cuda is imported): every output
    equals the CPU kernel's on six episodes (600 steps: the simulator runs Python per thread)."""
    import os
    import subprocess
    import sys
    from pathlib import Path

    out = Path(str(tmp_path)) / "cuda.npz"
    env = {**os.environ, "NUMBA_ENABLE_CUDASIM": "1"}
    r = subprocess.run([sys.executable, "-c", _CUDA_SCRIPT, str(out), "600"], env=env, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr[-2000:]
    got = np.load(out)
    body = BODY.replace(steps=600)
    w = np.array([[1.0, 1.0], [1.0, 1.0], [-0.6, 0.8], [0.3, -1.0], [1.0, 0.9], [0.0, 0.0]])
    ep, _ = run(body, *CANONICAL, w, np.array([0, 1, 2, 3, 0, 1]))
    assert np.array_equal(got["first"], ep.first_step) and np.array_equal(got["steps"], ep.steps)
    assert np.allclose(got["dmin"], ep.min_dist, rtol=0, atol=1e-12) and got["finite"].all()
    assert ep.success.any() and not ep.success.all()  # both outcomes occur in the six


def test_unknown_backend_is_one_line() -> None:
    with pytest.raises(ValueError, match="backend = 'gpu' is invalid; allowed: 'cpu', 'cpu-simd', 'cuda'"):
        run(BODY, *CANONICAL, [[1.0, 1.0]], [0], backend="gpu")


def test_the_workflow_runs_the_reduced_model_to_the_same_outcomes(tmp_path: object) -> None:
    """`reduced` in a config: its shard, merge and metrics rules (the physics base's), with mirror
    derivation; a design's row equals the model's direct sweep."""
    from pathlib import Path

    import pandas as pd
    import yaml
    from conftest import copy_workflow, snakemake

    from morphlearn import metrics as met

    wd = copy_workflow(Path(str(tmp_path)) / "wf")
    cfg = {
        "results_dir": "results/red",
        "grid": {"positions_per_axis": 3, "weights": 3},
        "theory": {"enabled": False},
        "figures": {"enabled": False},
        "empirical": {"enabled": False},
        "reduced": {"enabled": True, "weights": 3, "designs": "all", "mirror_derive": True, "shards": 2},
    }
    (wd / "config/red.yaml").write_text(yaml.safe_dump(cfg))
    snakemake(wd, "results/red/reduced/metrics.csv", "--cores", "2", "--configfile", "config/red.yaml")
    t = pd.read_csv(wd / "results/red/reduced/metrics.csv", comment="#")
    assert len(t) == 81 and (t.model == "reduced").all()
    g = DesignGrid(3)
    d = int(g.index_of((0.5, 0.5), (0.5, -0.5)))
    res = evaluate_design(*CANONICAL, weights(3), BODY)
    succ = np.isfinite(res.first_time)
    row = t[t.design == d].iloc[0]
    assert [row.n_45, row.n_135, row.n_225, row.n_315] == succ.sum(axis=(1, 2)).tolist()
    assert row.generalists == int((met.overlap(succ) == 4).sum())


def test_the_6561_design_map_holds_the_surveys_metrics_on_its_sub_grid() -> None:
    """results/reduced-paper (every design of the 9-point grid) and results/reduced-survey (the
    5-point grid's 625), the same model and levers, made apart: at the 625 designs they share, every
    metric is equal; and the map's best design by both metrics is the paper's (or its mirror image)."""
    import pandas as pd

    def table(b: str) -> pd.DataFrame:
        return pd.read_csv(ROOT / b / "reduced/metrics.csv", comment="#")

    big, small = table("results/reduced-paper"), table("results/reduced-survey")
    assert len(big) == 6561 and len(small) == 625
    keys = ["l1x", "l1y", "l2x", "l2y"]
    both = small.merge(big, on=keys, suffixes=("_s", "_p"))
    assert len(both) == 625
    for c in ("n_45", "n_135", "n_225", "n_315", "generalists", "at_least_one", "M_L", "M_CF"):
        assert (both[f"{c}_s"] == both[f"{c}_p"]).all(), c
    g = DesignGrid(9)
    paper = g.index_of((-0.5, 0.125), (0.5, -0.375))
    for by in ("M_L", "M_CF"):
        assert int(metrics.rank_designs(big, by).design.iloc[0]) in (paper, int(g.mirror(paper)))
