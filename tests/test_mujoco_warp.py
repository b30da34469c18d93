"""mujoco.backend warp (morphlearn.mujoco.mjwarp): the option, its GPU request and its clear error
without MuJoCo Warp (always run), and, where MuJoCo Warp is installed (the optional group gpu; CI
does not install it), agreement with the CPU batch on Warp's CPU device."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from morphlearn import config, configure, models, settings

ROOT = Path(__file__).resolve().parents[1]
CANON = ((0.5, 0.5), (0.5, -0.5))


def _base() -> dict:
    return config.load(ROOT / "config.yaml", [ROOT / "config/smoke.yaml"])


def _settings(mujoco: dict) -> settings.Settings:
    return configure.parse(config.deep_merge(_base(), {"mujoco": {"results_from": None, **mujoco}}))


def test_backend_option_asks_for_a_gpu_and_keeps_cpu_digests() -> None:
    m = models.get("mujoco")
    cpu = _settings({"enabled": True, "designs": [list(map(list, CANON))]})
    warp = _settings({"enabled": True, "designs": [list(map(list, CANON))], "backend": "warp"})
    assert m.settings(cpu).backend == "cpu" and m.resources(cpu).gpu == 0
    assert m.settings(warp).backend == "warp" and m.resources(warp).gpu == 1
    # cpu's science record is the one made before the option existed; warp's says warp
    assert "backend" not in m.science(cpu)
    assert m.science(warp) == {**m.science(cpu), "backend": "warp"}
    assert models.get("empirical").resources(warp).gpu == 0  # pybullet has no such option
    assert m.describe(m.science(warp), 1, 11).endswith("; run on MuJoCo Warp (float32, GPU)")
    assert "Warp" not in m.describe(m.science(cpu), 1, 11)


def test_bad_backend_names_the_key() -> None:
    with pytest.raises(config.ConfigError) as e:
        _settings({"backend": "cuda"})
    msg = str(e.value)
    assert "mujoco.backend" in msg and "'cuda'" in msg and "warp" in msg, msg
    with pytest.raises(config.ConfigError, match=r"unknown key \['backend'\] under 'empirical'"):
        configure.parse(config.deep_merge(_base(), {"empirical": {"backend": "warp"}}))


def test_warp_requested_but_not_installed_says_how_to_install(monkeypatch: pytest.MonkeyPatch) -> None:
    from morphlearn.mujoco import mjwarp

    monkeypatch.setitem(sys.modules, "mujoco_warp", None)  # an import of it now fails, installed or not
    s = _settings({"enabled": True, "designs": [list(map(list, CANON))], "backend": "warp"})
    m = models.get("mujoco")
    for call in (lambda: m.backend(s), lambda: m.evaluate(s, m.designs(s)[:1]), lambda: mjwarp.WarpBatchRunner()):
        with pytest.raises(mjwarp.WarpUnavailableError) as e:
            call()
        msg = str(e.value)
        assert (
            "mujoco.backend = 'warp'" in msg
            and "pip install mujoco-warp==4.0.0 warp-lang==1.19.0" in msg
            and "'cpu'" in msg
        ), msg


# --- on Warp's CPU device, where MuJoCo Warp is installed ----------------------------------------------


@pytest.fixture(scope="module")
def warp_cpu():  # type: ignore[no-untyped-def]
    pytest.importorskip("mujoco_warp", reason="MuJoCo Warp is the optional group gpu; CI does not install it")
    from morphlearn.mujoco.mjwarp import WarpBatchRunner
    from morphlearn.physics.params import load_params

    params = load_params(ROOT / "config/empirical_morphology.yaml")
    return params, WarpBatchRunner(params, device="cpu", nworld=64)


def test_warp_agrees_with_the_cpu_batch(warp_cpu) -> None:  # type: ignore[no-untyped-def]
    """The canonical design on a 5 x 5 weight grid in the 4 environments (100 episodes, early stop):
    the same success in every episode, and first-contact times within one step (dt). Contact is
    checked once per step, so a float32 state (MuJoCo Warp) against a float64 one (MuJoCo) moves a
    contact time by whole steps; one step allows a crossing that float32 rounding pushes past a
    step boundary. Measured here: identical times (docs/mujoco.md; at 11 x 11, 482/484 outcomes
    agree and the 2 that differ are one mirror pair of late, 80 s contacts)."""
    from morphlearn.grid import weights
    from morphlearn.mujoco.episode import BatchRunner

    params, runner = warp_cpu
    w = weights(5)
    e, i, j = np.meshgrid(np.arange(4), np.arange(5), np.arange(5), indexing="ij")
    ww = np.stack([w[i.ravel()], w[j.ravel()]], 1)
    ref = BatchRunner(params).run(*CANON, ww, e.ravel(), margin=2.0)
    got = runner.run(*CANON, ww, e.ravel(), margin=2.0)
    assert ref.success.any() and (~ref.success).any()  # both outcomes are tested
    assert np.array_equal(got.success, ref.success)
    assert np.nanmax(np.abs(got.first_time - ref.first_time)) <= params.dt


def test_many_designs_sweep_gives_each_designs_own_arrays() -> None:
    """The warp backend's many-designs path (evaluate_designs: the physics sweep of several designs
    per batch call) over the CPU batch, which has the warp runner's interface (always run: no MuJoCo
    Warp needed): each design's evaluate_design arrays bit for bit, whatever the designs per batch."""
    from morphlearn.grid import weights
    from morphlearn.mujoco.episode import BatchRunner, evaluate_design
    from morphlearn.mujoco.mjwarp import evaluate_designs
    from morphlearn.physics.options import SweepOptions
    from morphlearn.physics.params import load_params

    pytest.importorskip("mujoco")
    params = load_params(ROOT / "config" / "empirical_morphology.yaml").replace(steps=300)
    runner = BatchRunner(params)
    w = weights(3)
    coords = np.array([[0.5, 0.5, 0.5, -0.5], [-0.5, 0.5, 0.5, -0.5], [0.5, -0.5, 0.5, 0.5]])
    opt = SweepOptions(early_stop=True, adaptive_weights=True, stride=2, near=4.0)
    alone = [evaluate_design((c[0], c[1]), (c[2], c[3]), w, options=opt, runner=runner) for c in coords]
    assert any(np.isfinite(r.first_time).any() for r in alone)
    for per in (1, 2, 3):
        seen: list[int] = []
        done = seen.append  # called as each design's group finishes: (index, result)
        together = evaluate_designs(
            coords,
            w,
            runner,  # type: ignore[arg-type]  # the CPU batch stands in for the warp runner
            opt,
            lambda i, r, done=done: done(i),
            designs_per_batch=per,
        )
        assert seen == [0, 1, 2]
        for k in range(3):
            for f in ("first_time", "min_dist", "status"):
                assert getattr(alone[k], f).tobytes() == getattr(together[k], f).tobytes(), (per, k, f)


def test_warp_episode_does_not_depend_on_its_batch_graph_or_rerun(warp_cpu) -> None:  # type: ignore[no-untyped-def]
    """Many designs per batch (evaluate_designs) give each design's evaluate_design arrays bit for
    bit; the captured-graph path (CUDA's) equals the step-by-step one; a rerun the same bytes."""
    from morphlearn.grid import weights
    from morphlearn.mujoco.episode import evaluate_design
    from morphlearn.mujoco.mjwarp import WarpBatchRunner, evaluate_designs
    from morphlearn.physics.options import SweepOptions

    params, _ = warp_cpu
    params = params.replace(steps=300)  # 15 s episodes: the canonical w = (1, 1) touches 2 lights by then
    runner = WarpBatchRunner(params, device="cpu", nworld=64)
    w = weights(3)
    coords = np.array([[0.5, 0.5, 0.5, -0.5], [-0.5, 0.5, 0.5, -0.5]])
    opt = SweepOptions(early_stop=True, adaptive_weights=True, stride=2, near=4.0)
    together = evaluate_designs(coords, w, runner, opt)
    stepwise = WarpBatchRunner(params, device="cpu", graph=False)
    for k, c in enumerate(coords):
        alone = evaluate_design((c[0], c[1]), (c[2], c[3]), w, options=opt, runner=stepwise)
        for f in ("first_time", "min_dist", "status"):
            assert getattr(alone, f).tobytes() == getattr(together[k], f).tobytes(), (k, f)
    again = evaluate_designs(coords, w, runner, opt, designs_per_batch=1)
    assert all(a.first_time.tobytes() == b.first_time.tobytes() for a, b in zip(together, again, strict=True))
    assert any(np.isfinite(r.first_time).any() for r in together)


def test_plugin_runs_the_warp_backend(warp_cpu, monkeypatch: pytest.MonkeyPatch) -> None:  # type: ignore[no-untyped-def]
    """The model's evaluate (what the mujoco_shard rule calls) with backend warp, on Warp's CPU
    device in place of the GPU: the cpu backend's successes, and the record says mujoco-warp."""
    from morphlearn.mujoco import mjwarp

    monkeypatch.setattr(mjwarp, "resolve_device", lambda device: device or "cpu")
    two = [list(map(list, CANON)), [[-0.5, 0.5], [0.5, -0.5]]]  # and the second's mirror image
    sec = {"enabled": True, "designs": two, "weights": 3, "params": {"steps": 400}}
    m = models.get("mujoco")
    cpu, warp = _settings(sec), _settings({**sec, "backend": "warp"})
    seen: list[int] = []
    got = m.evaluate(warp, m.designs(warp), done=lambda i, r: seen.append(i))
    ref = m.evaluate(cpu, m.designs(cpu))
    assert seen == list(range(len(m.designs(warp)))) and len(got) == len(ref) == len(seen) == 3
    for a, b in zip(ref, got, strict=True):
        assert np.array_equal(np.isnan(a.first_time), np.isnan(b.first_time))
    assert any(np.isfinite(r.first_time).any() for r in ref)
    assert m.backend(warp) == {"backend": "mujoco-warp", "device": "cpu (CPU)"}
