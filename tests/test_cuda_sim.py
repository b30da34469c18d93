"""The CUDA kernel against the CPU kernel without a GPU: numba's CUDA simulator runs the kernel's
Python source (refill loop, atomic counter, device cells from ``cells.build``) thread by thread.

``NUMBA_ENABLE_CUDASIM`` must be set before ``numba.cuda`` is first imported, so the simulated run
happens in a subprocess. The simulator evaluates the model in Python float64 arithmetic, as the
CPU kernel does; on a real GPU fused multiply-adds may still flip trajectories within rounding
of the success radius (``benchmarks/bench_theory.py`` counts those when a GPU is present).
"""

from __future__ import annotations

import dataclasses
import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from morphlearn import grid
from morphlearn.theory import TheoryParams, cpu, evaluate, resolve_backend

# 2 designs x 4 envs x 3 x 3 weights, short horizon, light close (r = 1) so that some trajectories
# succeed, and a low step cap so that the design with a sensor at (0, -0.5) also gives flagged
# (step-cap) trajectories: every outcome kind occurs, and the simulator (Python per thread) stays fast.
DESIGNS = np.array([[-0.5, 0.5, -0.125, -0.5], [-0.125, 0.375, 0.0, -0.5]])
WEIGHTS = grid.weights(3)
SMALL = dict(r=1.0, horizon=50.0, max_steps=3000)
CASES = [("dp5", TheoryParams(**SMALL)), ("rk4", TheoryParams(**SMALL, integrator="rk4", dt=0.05))]
# The four-synapse launcher: 16 points (cheap in the simulator), grid and off-grid bodies, every
# environment, uncrossed weights zero and not, so that successes, failures and step caps occur.
_rng = np.random.default_rng(27)
P4_COORDS = np.vstack([np.repeat(DESIGNS, 4, axis=0), _rng.uniform(-0.5, 0.5, (8, 4))])
P4_ENVS = np.tile(np.arange(4), 4)
P4_W = np.hstack([_rng.choice(WEIGHTS, (16, 2)), np.where(np.arange(16)[:, None] % 2, _rng.uniform(-1, 1, (16, 2)), 0)])

SCRIPT = textwrap.dedent(
    """
    import json, sys
    import numpy as np
    from numba import cuda
    from morphlearn import grid
    from morphlearn.theory import TheoryParams, evaluate, resolve_backend
    from morphlearn.theory import cuda as gpu

    assert cuda.is_available()  # the simulator counts as a device
    args = json.loads(sys.argv[1])
    d, w = np.array(args["designs"]), np.array(args["weights"])
    out = {"auto": resolve_backend("auto")}
    for name, fields in args["cases"].items():
        p = TheoryParams(**fields)
        ft, dm, st, n = gpu.sweep(d, w, grid.env_starts(p.r), **p.kernel_kwargs())
        np.savez(sys.argv[2] + "/" + name + ".npz", ft=ft, dm=dm, st=st, n=n)
    # the four-synapse launcher, both integrators
    for name, fields in args["cases"].items():
        p = TheoryParams(**fields)
        ft, dm, st = gpu.points4(np.array(args["p4_coords"]), grid.env_starts(p.r), np.array(args["p4_envs"]),
                                 np.array(args["p4_w"]), **p.kernel_kwargs())
        np.savez(sys.argv[2] + "/points4_" + name + ".npz", ft=ft, dm=dm, st=st)
    # the evaluate() path with backend "cuda"
    r = evaluate(d[:1], w, TheoryParams(**{**args["cases"]["dp5"], "backend": "cuda"}))[0]
    np.savez(sys.argv[2] + "/evaluate.npz", ft=r.first_time, dm=r.min_dist, st=r.status)
    print(json.dumps(out))
    """
)


@pytest.fixture(scope="module")
def simulated(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, dict]:
    tmp = tmp_path_factory.mktemp("cudasim")
    args = {
        "designs": DESIGNS.tolist(),
        "weights": WEIGHTS.tolist(),
        "cases": {name: dataclasses.asdict(p) for name, p in CASES},
        "p4_coords": P4_COORDS.tolist(),
        "p4_envs": P4_ENVS.tolist(),
        "p4_w": P4_W.tolist(),
    }
    env = dict(os.environ, NUMBA_ENABLE_CUDASIM="1")
    r = subprocess.run(
        [sys.executable, "-c", SCRIPT, json.dumps(args), str(tmp)], env=env, capture_output=True, text=True, timeout=600
    )
    assert r.returncode == 0, r.stderr[-4000:]
    return tmp, json.loads(r.stdout.strip().splitlines()[-1])


@pytest.mark.parametrize("name,p", CASES, ids=[c[0] for c in CASES])
def test_cuda_kernel_matches_cpu_kernel_in_simulator(simulated: tuple[Path, dict], name: str, p: TheoryParams) -> None:
    tmp, _ = simulated
    g = np.load(tmp / f"{name}.npz")
    c = cpu.sweep(DESIGNS, WEIGHTS, grid.env_starts(p.r), **p.kernel_kwargs())
    ok_g, ok_c = ~np.isnan(g["ft"]), ~np.isnan(c[0])
    both = ok_g & ok_c
    dt = np.abs(g["ft"][both] - c[0][both])
    dd = np.abs(g["dm"] - c[1])
    report = {
        "trajectories": int(ok_c.size),
        "successes_cpu": int(ok_c.sum()),
        "success_flags_differ": int((ok_g != ok_c).sum()),
        "status_differ": int((g["st"] != c[2]).sum()),
        "steps_differ": int((g["n"] != c[3]).sum()),
        "first_time_not_bit_equal": int((g["ft"][both] != c[0][both]).sum()),
        "min_dist_not_bit_equal": int((g["dm"] != c[1]).sum()),
        "max_abs_dfirst_time": float(dt.max()) if dt.size else 0.0,
        "max_abs_dmin_dist": float(dd.max()),
    }
    print(f"cuda simulator vs cpu, {name}: {report}")
    assert ok_c.any() and (~ok_c).any()  # successes and failures
    if name == "dp5":  # the adaptive integrator hits the step cap near the singular sensor
        assert (c[2] != 0).any()
    assert report["success_flags_differ"] == 0
    assert report["status_differ"] == 0
    assert report["max_abs_dfirst_time"] <= 1e-9
    assert report["max_abs_dmin_dist"] <= 1e-9


@pytest.mark.parametrize("name,p", CASES, ids=[c[0] for c in CASES])
def test_cuda_four_synapse_launcher_is_bit_identical_to_cpu_in_simulator(
    simulated: tuple[Path, dict], name: str, p: TheoryParams
) -> None:
    """cuda.points4 (the refill kernel over the four-synapse device model) against cpu.points4:
    the same source, so under the simulator every output is equal bit for bit."""
    tmp, _ = simulated
    g = np.load(tmp / f"points4_{name}.npz")
    c = cpu.points4(P4_COORDS, grid.env_starts(p.r), P4_ENVS, P4_W, **p.kernel_kwargs())
    ok = np.isfinite(c[0])
    print(f"points4 {name}: {int(ok.sum())} of {ok.size} succeed, {int((c[2] != 0).sum())} flagged")
    assert ok.any() and (~ok).any()  # successes and failures
    if name == "dp5":  # and step caps, as in the sweep's case
        assert (c[2] != 0).any()
    assert g["st"].tolist() == c[2].tolist()
    np.testing.assert_array_equal(g["ft"], c[0])  # NaN == NaN here, all else exactly equal
    np.testing.assert_array_equal(g["dm"], c[1])


def test_evaluate_with_cuda_backend_in_simulator(simulated: tuple[Path, dict]) -> None:
    tmp, info = simulated
    assert info["auto"] == "cuda"  # auto picks the (simulated) device
    g = np.load(tmp / "evaluate.npz")
    c = evaluate(DESIGNS[:1], WEIGHTS, CASES[0][1])[0]
    np.testing.assert_allclose(g["ft"], c.first_time, rtol=0, atol=1e-6)
    np.testing.assert_allclose(g["dm"], c.min_dist, rtol=0, atol=1e-6)
    np.testing.assert_array_equal(g["st"], c.status)


def test_backend_selection_without_gpu() -> None:
    from morphlearn.theory import cuda

    if cuda.available():
        pytest.skip("a CUDA GPU is visible")
    assert resolve_backend("auto") == "cpu"
    assert resolve_backend("cpu") == "cpu"
    with pytest.raises(RuntimeError, match="no CUDA GPU"):
        resolve_backend("cuda")
    with pytest.raises(RuntimeError, match="no CUDA GPU"):
        evaluate(DESIGNS[:1], WEIGHTS, TheoryParams(backend="cuda"))
    with pytest.raises(ValueError, match="backend"):
        resolve_backend("opencl")


def test_backend_comes_from_config_but_not_the_science_digest() -> None:
    from morphlearn.settings import FigureSettings, GridSettings, Shared, SweepSettings
    from morphlearn.theory.plugin import Theory

    th = {
        "r": 4.0,
        "horizon": 500.0,
        "success_radius": 0.2,
        "integrator": "dp5",
        "rtol": 1e-8,
        "atol": 1e-8,
        "dt": 0.01,
        "max_steps": 100000,
        "backend": "auto",
    }
    assert TheoryParams.from_config(th).backend == "auto"
    shared = Shared(
        GridSettings(9, 121),
        SweepSettings(shards=1, mirror_symmetry=True, threads=1),
        FigureSettings(False, 1.0, 35, "best_M_L", (45, 135)),
    )
    parsed = Theory().parse({**th, "enabled": True}, shared)
    assert parsed.params.backend == "auto" and "backend" not in json.dumps(dict(parsed.science))
