"""The reduced model's SIMD kernel (``reduced.backend: cpu-simd``): kernel.py's episode stepped eight
episodes a core side by side in float64 lanes (AVX-512 where the CPU has it), by the C kernel
``_lanes.c`` built at setup. Same signature and outputs as :func:`morphlearn.reduced.cpu.run_batch`,
and the same outcomes to the last bit: every lane does the scalar kernel's arithmetic in its order
without contraction, and tanh is libm's algorithm evaluated across lanes with the operations of the
libm this process runs (checked against libm when the module loads; libm itself lane by lane where
the check fails). One core a call (the caller parallelises over designs or shards)."""

from __future__ import annotations

import numpy as np

#: tanh modes of the kernel: libm lane by lane, fdlibm's baseline build, fdlibm's FMA build
TANH_MODES = ("libm", "fdlibm", "fdlibm-fma")


def available() -> bool:
    """True when the C kernel was built (setup compiles it with the package)."""
    try:
        from morphlearn.reduced import _lanes  # noqa: F401
    except ImportError:
        return False
    return True


def mode() -> tuple[str, str]:
    """(instruction set, tanh mode) the kernel runs with here."""
    from morphlearn.reduced import _lanes

    isa, m = _lanes.mode()
    return isa, TANH_MODES[m]


def run_batch(g, hm, kk, cen, dt, steps, vmax, tmax, radius, dz2, lights, sen, w, stop, first, dmin, nsteps, finite):
    """:func:`morphlearn.reduced.cpu.run_batch` across SIMD lanes (outputs written in place)."""
    from morphlearn.reduced import _lanes

    f64 = [np.ascontiguousarray(a, dtype=np.float64) for a in (g, hm, kk, cen, lights, sen, w)]
    _lanes.run_batch(
        *f64[:4], float(dt), int(steps), float(vmax), float(tmax), float(radius), float(dz2),
        *f64[4:], bool(stop), first, dmin, nsteps, finite.view(np.uint8), -1,
    )  # fmt: skip
