"""One cell of a kernel call, one source for both backends: trajectory ``k``'s inputs read from the
call's arrays, the model's trajectory run, its outputs written back.

Like the trajectory itself (:func:`morphlearn.theory.model.build`), the cells are plain Python
compiled with the backend's decorator: :func:`build` returns them, and each backend keeps only what
is its own: the CPU kernel calls a cell inside its ``prange`` loop, the CUDA kernel inside its
refill loop (scipy's ``integrate/_ivp`` in the same spirit: a method is data, its step is written
once). ``params`` is the tuple :func:`params` makes: the trajectory's trailing arguments.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, NamedTuple

from morphlearn.theory import model

#: A placeholder for the source's global: each compiled cell sees its controller's trajectory here.
trajectory: Any = None


def sweep(k, designs, w, starts, params, out_t, out_d, out_s, out_n):
    """Cell ``k`` of a sweep: the flat index over (design, environment, w1 index, w2 index), in the
    outputs' row-major order; the uncrossed weights are zero (the two-synapse model)."""
    m = w.shape[0]
    mm = m * m
    per_design = starts.shape[0] * mm
    # the remainders by subtraction, not ``%``: one integer division fewer per index on the GPU
    di = k // per_design
    r = k - di * per_design
    e = r // mm
    r2 = r - e * mm
    i = r2 // m
    j = r2 - i * m
    ft, dm, st, n = trajectory(
        starts[e, 0], starts[e, 1], designs[di, 0], designs[di, 1], designs[di, 2], designs[di, 3],
        w[i], w[j], 0.0, 0.0, *params,
    )  # fmt: skip
    out_t[di, e, i, j] = ft
    out_d[di, e, i, j] = dm
    out_s[di, e, i, j] = st
    out_n[di, e, i, j] = n


def points(k, coords, starts, ei, w, params, out_t, out_d, out_s):
    """Cell ``k`` of a points call: body ``coords[k]``, environment ``ei[k]``, weights ``w[k] =
    (w1, w2, u1, u2)`` (the two-synapse trajectory ignores ``u1, u2``)."""
    e = ei[k]
    ft, dm, st, _ = trajectory(
        starts[e, 0], starts[e, 1], coords[k, 0], coords[k, 1], coords[k, 2], coords[k, 3],
        w[k, 0], w[k, 1], w[k, 2], w[k, 3], *params,
    )  # fmt: skip
    out_t[k] = ft
    out_d[k] = dm
    out_s[k] = st


class Cells(NamedTuple):
    """One controller's compiled cells: ``sweep(k, designs, w, starts, params, out_t, out_d, out_s,
    out_n)`` and ``points(k, coords, starts, ei, w, params, out_t, out_d, out_s)``."""

    sweep: Callable[..., None]
    points: Callable[..., None]


def build(jit: Callable[[Any], Any], synapses: int = 2) -> Cells:
    """The cells compiled with ``jit`` (``numba.njit(...)`` or ``cuda.jit(device=True)``) over the
    trajectory ``model.build(jit, synapses)``, each in a fresh namespace as model.build does."""
    ns: dict[str, Any] = dict(globals())
    ns["trajectory"] = model.build(jit, synapses)
    return Cells(*(jit(model.twin(f, ns, synapses)) for f in (sweep, points)))


def params(
    radius: float, horizon: float, method: int, rtol: float, atol: float, dt: float, max_steps: int
) -> tuple[float, float, int, float, float, float, int]:
    """The launchers' keywords (``TheoryParams.kernel_kwargs()``) as the tuple the cells pass on
    to the trajectory, in its order: float64 and int64 on both backends, whatever the caller gave."""
    return float(radius), float(horizon), int(method), float(rtol), float(atol), float(dt), int(max_steps)
