"""The reduced model's SIMD kernel (reduced.backend cpu-simd, morphlearn.reduced.simd): outcomes
identical to the scalar kernel's to the bit (success step, closest approach, steps run, finite) on
every cell checked, its tanh libm's to the bit, its batches independent of their size and order, and
the config key (bounded, not in the science record, a GPU asked for cuda only)."""

from __future__ import annotations

import math
from pathlib import Path

import numba
import numpy as np
import pytest

from morphlearn import config, configure, models
from morphlearn.grid import weights
from morphlearn.physics.params import load_params
from morphlearn.reduced import simd
from morphlearn.reduced.core import BACKENDS, run
from morphlearn.reduced.plugin import BACKENDS as KEY_VALUES

ROOT = Path(__file__).resolve().parents[1]
BODY = load_params(ROOT / "config/authors_body.yaml")
#: the issue's design (a small generalist island) and the canonical one
DESIGNS = [((-0.5, -0.375), (0.125, -0.25)), ((0.5, 0.5), (0.5, -0.5))]
FIELDS = ("first_step", "min_dist", "steps", "finite")

pytestmark = pytest.mark.skipif(not simd.available(), reason="the C kernel morphlearn.reduced._lanes is not built")


def _cells(m: int) -> tuple[np.ndarray, np.ndarray]:
    w = weights(m)
    e, i, j = np.meshgrid(np.arange(4), np.arange(m), np.arange(m), indexing="ij")
    return np.stack([w[i.ravel()], w[j.ravel()]], 1), e.ravel()


def _same(d: tuple, w: np.ndarray, env: np.ndarray, stop: bool = True) -> None:
    a = run(BODY, *d, w, env, stop_at_success=stop)[0]
    b = run(BODY, *d, w, env, stop_at_success=stop, backend="cpu-simd")[0]
    for f in FIELDS:
        x, y = np.asarray(getattr(a, f)), np.asarray(getattr(b, f))
        assert x.dtype == y.dtype and x.tobytes() == y.tobytes(), (d, f, int((x != y).sum()))


@pytest.mark.parametrize("stop", [True, False])
def test_outcomes_are_the_scalar_kernels_to_the_bit(stop: bool) -> None:
    w, env = _cells(15)
    for d in DESIGNS:
        _same(d, w, env, stop)


@pytest.mark.slow
def test_outcomes_are_the_scalar_kernels_on_two_designs_at_121_x_121() -> None:
    """Every cell of two designs at the paper's resolution: 117,128 episodes a kernel."""
    w, env = _cells(121)
    for d in DESIGNS:
        _same(d, w, env)


@pytest.mark.parametrize("n", [0, 1, 7, 8, 9, 17, 33])
def test_a_batch_of_any_size_and_order_gives_each_episode_its_own_outcome(n: int) -> None:
    """Lanes are refilled as episodes end: an episode's outcome must not depend on its neighbours."""
    w, env = _cells(9)
    rng = np.random.default_rng(n)
    pick = rng.choice(len(w), n, replace=False)
    _same(DESIGNS[0], w[pick], env[pick])
    a = run(BODY, *DESIGNS[0], w[pick], env[pick], backend="cpu-simd")[0]
    b = run(BODY, *DESIGNS[0], w[pick[::-1]], env[pick[::-1]], backend="cpu-simd")[0]
    assert np.array_equal(a.min_dist, b.min_dist[::-1]) and np.array_equal(a.first_step, b.first_step[::-1])


@numba.njit(cache=False)
def _numba_tanh(x: np.ndarray) -> np.ndarray:  # the scalar kernel's tanh (math.tanh under numba: libm's)
    out = np.empty_like(x)
    for i in range(x.size):
        out[i] = math.tanh(x[i])
    return out


def test_tanh_is_the_scalar_kernels_to_the_bit() -> None:
    """The kernel's tanh against numba's math.tanh on 400,000 arguments over every branch (and the
    special values libm takes lane by lane); and the check set discriminates: at least one other
    mode the kernel could run differs somewhere (else the check would prove nothing)."""
    from morphlearn.reduced import _lanes

    rng = np.random.default_rng(7)
    mags = 2.0 ** rng.uniform(-60, 6, 400_000)
    x = np.concatenate(
        [mags * rng.choice([-1.0, 1.0], mags.size), [0.0, -0.0, np.inf, -np.inf, np.nan, 22.0, -22.0, 1.0]]
    )
    ref = _numba_tanh(x)
    out = np.empty_like(x)
    _lanes.tanh(x, out, -1)
    assert out.tobytes() == ref.tobytes(), int((out.view(np.int64) != ref.view(np.int64)).sum())
    others = [m for m in range(len(simd.TANH_MODES)) if simd.TANH_MODES[m] not in (simd.mode()[1], "libm")]
    differs = []
    for m in others:
        try:
            _lanes.tanh(x, out, m)
        except ValueError:  # the FMA build's mode on a CPU without AVX-512
            continue
        differs.append(out.tobytes() != ref.tobytes())
    assert not differs or any(differs)


def _base() -> dict:
    return config.load(ROOT / "config.yaml", [ROOT / "config/smoke.yaml"])


def _settings(reduced: dict) -> object:
    sec = {"enabled": True, "designs": [list(map(list, DESIGNS[1]))], "weights": 3, **reduced}
    return configure.parse(config.deep_merge(_base(), {"reduced": sec}))


def test_backend_key_is_bounded_and_cpu_simd_keeps_the_science_record() -> None:
    assert KEY_VALUES == BACKENDS
    m = models.get("reduced")
    cpu, lanes, gpu = (_settings({"backend": b}) for b in ("cpu", "cpu-simd", "cuda"))
    assert m.settings(lanes).backend == "cpu-simd"
    # identical outcomes: the same science record, so the same digests, caches and stores as cpu
    assert m.science(lanes) == m.science(cpu) and "backend" not in m.science(cpu)
    assert m.science(gpu) == {**m.science(cpu), "backend": "cuda"}
    assert [m.resources(s).gpu for s in (cpu, lanes, gpu)] == [0, 0, 1]
    assert m.backend(lanes)["backend"].startswith("reduced-simd (")
    with pytest.raises(config.ConfigError) as e:
        _settings({"backend": "simd"})
    msg = str(e.value)
    assert "reduced.backend" in msg and "'simd'" in msg and "cpu-simd" in msg and "\n" not in msg, msg


def test_the_sweep_on_cpu_simd_is_the_sweep_on_cpu() -> None:
    """A design's whole sweep (adaptive grid and all) through the section's evaluator."""
    from morphlearn.reduced.episode import evaluator

    a = evaluator("cpu")(*DESIGNS[0], weights(11), BODY)
    b = evaluator("cpu-simd")(*DESIGNS[0], weights(11), BODY)
    for v in ("first_time", "min_dist"):
        assert np.asarray(getattr(a, v)).tobytes() == np.asarray(getattr(b, v)).tobytes()
