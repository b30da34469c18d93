"""The MuJoCo model on MuJoCo Warp (``mujoco-warp``): the same MJCF, many worlds at once on a GPU.

An optional backend (``mujoco.backend: warp``; install with ``pip install -e '.[gpu]'``, the exact
pins in pyproject.toml). Nothing else in the project imports ``warp`` or ``mujoco_warp``: both are
imported here, lazily, so the CPU path and CI never need them.

:class:`WarpBatchRunner` has the interface of :class:`morphlearn.mujoco.episode.BatchRunner`
(``run(l1, l2, w, env, margin=...) -> Episodes``, ``params``), so
:func:`morphlearn.mujoco.episode.evaluate_design` takes it as its ``runner``. Per episode one
MuJoCo Warp *world* (``nworld`` = episodes of a chunk): worlds share no state (each has its own
contacts and constraint rows), so, as on the CPU, an episode does not depend on its neighbours.

Per step, on the device: one Warp kernel (:func:`_kernel`) does the CPU batch's per-step work for
every world at once (pose check, closest approach, tilt and lift, the contact test, the horizon,
the controller ``tanh(w s) * max_speed`` written into ``ctrl``), then ``mujoco_warp.step``. The host
sees the state only every ``CHECK_EVERY`` steps (the reach bound, computed in numpy as on the
CPU, and "is any episode still running"); on CUDA those ``CHECK_EVERY`` steps are one captured
graph. Stopped worlds keep stepping (with zero wheel targets) until the whole chunk is done: their
outcomes are frozen at the stop, as on the CPU.

Where it differs from the CPU batch (so outcomes agree closely but not bit for bit; measured in
docs/mujoco.md):

- MuJoCo Warp computes in float32 (MuJoCo in float64). The bookkeeping (distances, tilt, the
  controller) is done in float64 from the float32 state.
- The model's ``autoreset`` flag is cleared before ``put_model``: MuJoCo Warp refuses it and never
  resets a world (a non-finite state is detected by the kernel and stops the episode, as on the CPU).
- ``path`` (per-step positions for drawing) is not offered: draw with the CPU batch.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np

from morphlearn.grid import light_positions
from morphlearn.mujoco.episode import BatchRunner, Episodes, lower_times
from morphlearn.mujoco.model import MujocoSettings, build_model
from morphlearn.physics.options import SweepOptions
from morphlearn.physics.params import EmpiricalParams
from morphlearn.physics.reach import CHECK_EVERY, ReachBound, sensor_reach
from morphlearn.physics.sweep import sweep_designs

if TYPE_CHECKING:
    from morphlearn.results import DesignResult

#: The optional dependency group and its pins (pyproject.toml ``[project.optional-dependencies] gpu``).
INSTALL = "pip install mujoco-warp==4.0.0 warp-lang==1.19.0 (pyproject.toml's optional group gpu)"
#: Worlds per MuJoCo Warp ``Data`` (a chunk); results do not depend on it.
NWORLD = 16384


class WarpUnavailableError(RuntimeError):
    """MuJoCo Warp was asked for but cannot be used (not installed, or no CUDA device)."""


def import_warp() -> tuple[Any, Any]:
    """``(warp, mujoco_warp)``, or :class:`WarpUnavailableError` saying how to install them."""
    try:
        import mujoco_warp
        import warp
    except ImportError as e:
        raise WarpUnavailableError(
            f"mujoco.backend = 'warp' needs MuJoCo Warp, which is not installed ({e}); "
            f"install it with {INSTALL}, or set mujoco.backend to 'cpu'"
        ) from None
    warp.config.log_level = warp.LOG_WARNING  # no banner or per-module load lines in the rule logs
    return warp, mujoco_warp


def resolve_device(device: str | None) -> str:
    """Warp device for the backend: ``device`` as given, else the first CUDA GPU (the backend's
    purpose; Warp's CPU device runs it too, slowly, for checks: pass ``"cpu"``)."""
    wp, _ = import_warp()
    if device is not None:
        return device
    if wp.get_cuda_device_count() < 1:
        raise WarpUnavailableError(
            "mujoco.backend = 'warp' but Warp sees no CUDA GPU (warp.get_cuda_device_count() == 0): "
            "run it on a GPU node (the mujoco_shard rule asks for one, docs/mujoco.md) "
            "or set mujoco.backend to 'cpu'"
        )
    return "cuda:0"


def device_name(device: str) -> str:
    """The device as records name it (``backend()``)."""
    wp, _ = import_warp()
    d = wp.get_device(device)
    return f"{d.alias} ({d.name})"


class WarpBatchRunner:
    """Batches of episodes of one body on MuJoCo Warp (see the module docstring).

    ``device``: a Warp device (``"cuda:0"``, ``"cpu"``); None: the first CUDA GPU, else
    :class:`WarpUnavailableError`. ``nworld``: worlds per chunk. ``graph``: replay each stretch of
    ``CHECK_EVERY`` steps as a captured graph (None: on CUDA only)."""

    def __init__(
        self,
        params: EmpiricalParams | None = None,
        settings: MujocoSettings | None = None,
        *,
        device: str | None = None,
        nworld: int = NWORLD,
        graph: bool | None = None,
    ) -> None:
        import mujoco

        self.wp, self.mjw = import_warp()
        self.params = params or EmpiricalParams()
        self.settings = settings or MujocoSettings()
        self.device = resolve_device(device)
        self.nworld = int(nworld)
        if self.nworld < 1:
            raise ValueError(f"nworld = {nworld!r} is invalid; allowed: an integer >= 1")
        self.graph = self.wp.get_device(self.device).is_cuda if graph is None else bool(graph)
        self.mjm = build_model(self.params, self.settings)
        # MuJoCo Warp refuses the flag and never resets a world; the kernel stops non-finite ones
        self.mjm.opt.disableflags &= ~int(mujoco.mjtDisableBit.mjDSBL_AUTORESET)
        self.lights = light_positions(self.params.light_distance)
        self._bounds: dict[tuple[float, float, float], ReachBound] = {}
        with self.wp.ScopedDevice(self.device):
            self.model = self.mjw.put_model(self.mjm)
        # stable contact and constraint order and invariant atomics: the same bytes on a rerun
        self.model.opt.deterministic = True

    bound = BatchRunner.bound  # the CPU batch's reach-bound cache (same params, same ``_bounds``)

    def run(
        self,
        l1: Any,
        l2: Any,
        w: Any,
        env: Any,
        *,
        margin: float | None = None,
        stop_at_contact: bool = True,
        stop_hopeless: bool = True,
        path: list[np.ndarray] | None = None,
    ) -> Episodes:
        """As :meth:`morphlearn.mujoco.episode.BatchRunner.run` (``path`` is refused)."""
        if path is not None:
            raise ValueError("path is not recorded by the warp backend; draw trajectories with the cpu backend")
        w = np.atleast_2d(np.asarray(w, dtype=np.float64))
        n = len(w)
        env = np.broadcast_to(np.asarray(env, dtype=np.int64), (n,))
        l1 = np.broadcast_to(np.asarray(l1, dtype=np.float64), (n, 2))
        l2 = np.broadcast_to(np.asarray(l2, dtype=np.float64), (n, 2))
        if w.shape != (n, 2) or np.any((env < 0) | (env > 3)):
            raise ValueError(f"weights must be (n, 2) and env in 0..3; got {w.shape}, env {np.unique(env)}")
        c = self.nworld
        parts = [
            self._run(
                l1[a : a + c], l2[a : a + c], w[a : a + c], env[a : a + c], margin, stop_at_contact, stop_hopeless
            )
            for a in range(0, n, c)
        ]
        if len(parts) == 1:
            return parts[0]
        if not parts:
            return self._run(l1, l2, w, env, margin, stop_at_contact, stop_hopeless)
        return Episodes(*(np.concatenate([getattr(q, f) for q in parts]) for f in Episodes.__dataclass_fields__))

    def _run(
        self,
        l1: np.ndarray,
        l2: np.ndarray,
        w: np.ndarray,
        env: np.ndarray,
        margin: float | None,
        stop_at_contact: bool,
        stop_hopeless: bool,
    ) -> Episodes:
        wp, mjw, p = self.wp, self.mjw, self.params
        n = len(w)
        if n == 0:
            z = np.zeros(0)
            return Episodes(z, z, z.astype(np.int64), z.astype(bool), z.astype(np.int64), z, z)
        hopeless = np.full(n, -1, np.int64)
        stopped_hopeless = np.zeros(n, bool)
        group = np.zeros(n, np.int64)
        bounds: list[ReachBound] = []
        if margin is not None:
            rho = [sensor_reach(tuple(a), tuple(b)) for a, b in zip(l1, l2, strict=True)]
            keys = np.stack([np.maximum(np.abs(w[:, 0]), np.abs(w[:, 1])), np.array(rho)], 1)
            uniq, group = np.unique(keys, axis=0, return_inverse=True)
            group = group.reshape(-1)
            bounds = [self.bound(wm, r, margin) for wm, r in uniq]
        from morphlearn.mujoco._warp_kernels import advance, observe_control

        with wp.ScopedDevice(self.device):
            d = mjw.make_data(self.mjm, nworld=n)
            f64 = wp.float64
            kstep = wp.zeros(1, dtype=wp.int32)
            active = wp.ones(n, dtype=wp.int32)
            first_k = wp.full(n, -1, dtype=wp.int32)
            min_d2 = wp.full(n, math.inf, dtype=f64)
            tilt_c = wp.ones(n, dtype=f64)
            lift = wp.zeros(n, dtype=f64)
            steps = wp.zeros(n, dtype=wp.int32)
            finite = wp.ones(n, dtype=wp.int32)
            light = wp.array(self.lights[env], dtype=f64)
            sens = wp.array(np.concatenate([l1, l2], 1), dtype=f64)
            weight = wp.array(w, dtype=f64)
            args = [
                kstep,
                int(p.steps),
                int(stop_at_contact),
                float(p.contact_distance**2),
                float(p.wheel_radius),
                float(p.max_speed),
                d.qpos,
                light,
                sens,
                weight,
                active,
                first_k,
                min_d2,
                tilt_c,
                lift,
                steps,
                finite,
                d.ctrl,
            ]

            def observe() -> None:
                wp.launch(observe_control, dim=n, inputs=args)

            def stretch() -> None:  # CHECK_EVERY steps, each followed by the next observation
                for _ in range(CHECK_EVERY):
                    mjw.step(self.model, d)
                    wp.launch(advance, dim=1, inputs=[kstep])
                    observe()

            observe()  # step 0
            graph = None
            k = 0
            while True:
                # the host's turn, at k = 0, CHECK_EVERY, ...: the reach bound and "anyone left?"
                act = active.numpy().astype(bool)
                if not act.any() or k >= p.steps:
                    break
                if bounds:
                    ask = act & (hopeless < 0)
                    if ask.any():
                        q, v = d.qpos.numpy()[ask].astype(np.float64), d.qvel.numpy()[ask].astype(np.float64)
                        idx = np.flatnonzero(ask)
                        dist = np.hypot(q[:, 0] - self.lights[env[idx], 0], q[:, 1] - self.lights[env[idx], 1])
                        u = np.hypot(v[:, 0], v[:, 1])
                        g = group[idx]
                        gone = np.zeros(len(idx), bool)
                        for gi in np.unique(g):
                            sel = g == gi
                            gone[sel] = lower_times(bounds[gi], dist[sel], u[sel]) > (p.steps - k) * p.dt
                        hopeless[idx[gone]] = k
                        if stop_hopeless and gone.any():
                            stopped_hopeless[idx[gone]] = True
                            act[idx[gone]] = False
                            active.assign(act.astype(np.int32))
                if self.graph:
                    if graph is None:
                        with wp.ScopedCapture() as cap:
                            stretch()
                        graph = cap.graph
                    wp.capture_launch(graph)
                else:
                    stretch()
                k += CHECK_EVERY
            fk = first_k.numpy().astype(np.int64)
            st = np.where(stopped_hopeless, hopeless, steps.numpy().astype(np.int64))
            out = Episodes(
                first_time=np.where(fk >= 0, fk * p.dt, np.nan),
                min_dist=np.sqrt(min_d2.numpy()),
                steps=st,
                finite=finite.numpy().astype(bool),
                hopeless_step=hopeless,
                max_tilt=np.arccos(np.clip(tilt_c.numpy(), -1.0, 1.0)),
                max_lift=lift.numpy(),
            )
        return out


def evaluate_designs(
    coords: np.ndarray,
    weights: np.ndarray,
    runner: WarpBatchRunner,
    options: SweepOptions | None = None,
    done: Callable[[int, DesignResult], None] | None = None,
    *,
    designs_per_batch: int | None = None,
) -> list[DesignResult]:
    """:func:`morphlearn.mujoco.episode.evaluate_design` for many designs ``coords`` (D, 4) at once:
    the physics layer's sweep of ``designs_per_batch`` designs together
    (:func:`morphlearn.physics.sweep.sweep_designs`; default: as many as fill ``runner.nworld``
    worlds), so a GPU gets thousands of worlds where one design has only 4 m^2 episodes. Per design
    the same cells and outcomes as ``evaluate_design`` with the same runner (worlds are
    independent). ``done(index, result)`` as each group of designs finishes."""
    options = options or SweepOptions()
    coords = np.asarray(coords, dtype=np.float64).reshape(-1, 4)
    m = len(weights)
    per = designs_per_batch or max(1, runner.nworld // (4 * m * m))
    margin = options.margin if options.early_stop else None
    out: list[DesignResult] = []
    for a in range(0, len(coords), per):
        c = coords[a : a + per]
        # the shard log's progress line (one batch is the unit here, not an episode)
        batch_of = f"one GPU batch of up to {4 * len(c) * m * m} episodes"
        print(f"designs {a + 1}-{a + len(c)}/{len(coords)}: started, {batch_of}", flush=True)

        def batch(d: np.ndarray, w: np.ndarray, env: np.ndarray) -> Episodes:
            return runner.run(c[d, :2], c[d, 2:], w, env, margin=margin)  # noqa: B023

        designs = [((x[0], x[1]), (x[2], x[3])) for x in c]
        for k, r in enumerate(sweep_designs(batch, designs, weights, runner.params, options)):
            out.append(r)
            if done is not None:
                done(a + k, r)
    return out
