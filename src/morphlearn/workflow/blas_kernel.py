"""One OpenBLAS kernel for every process the workflow starts, so figures re-render to the same bytes.

scipy's ``solve_ivp`` (the reference trajectories of Figs. 4-5 and ``persistence.csv``) forms its
Runge-Kutta stages with ``numpy.dot``, which calls OpenBLAS. OpenBLAS picks a kernel per CPU at
start-up, and kernels sum in different orders: on an AVX-512 machine the autodetected SkylakeX
kernel and the Haswell kernel give trajectories that differ in the last digits, so a bundle made on
one machine did not re-render byte for byte on another. The sweeps do not go through BLAS.

Haswell's kernel (AVX2 + FMA) runs on every x86-64 CPU made since 2013-2015, Intel and AMD alike;
it is the kernel the committed bundles were rendered with. Elsewhere (no AVX2, or not x86-64) the
environment is left alone and the reference trajectories may differ from the committed ones in
their last digits.
"""

from __future__ import annotations

import os
import platform
from collections.abc import MutableMapping
from pathlib import Path

#: The kernel pinned for every child process (``OPENBLAS_CORETYPE``); ``Zen`` maps to it too.
KERNEL = "Haswell"
#: CPU flags the kernel needs.
_NEEDS = frozenset({"avx2", "fma"})


def _cpu_flags(cpuinfo: Path = Path("/proc/cpuinfo")) -> frozenset[str]:
    try:
        text = cpuinfo.read_text()
    except OSError:
        return frozenset()
    for line in text.splitlines():
        if line.startswith("flags"):
            return frozenset(line.split(":", 1)[1].split())
    return frozenset()


def supported(cpuinfo: Path = Path("/proc/cpuinfo")) -> bool:
    """Whether this machine can run the pinned kernel (forcing one it cannot run would crash)."""
    return platform.machine() in ("x86_64", "AMD64") and _NEEDS <= _cpu_flags(cpuinfo)


def pin(environ: MutableMapping[str, str] = os.environ, cpuinfo: Path = Path("/proc/cpuinfo")) -> str | None:
    """Set ``OPENBLAS_CORETYPE`` for the processes started from now on; return the kernel or None.

    It must be set before numpy is imported in a process, so it is set where the workflow starts
    (the Snakefile) and inherited by every rule, notebook kernel and SLURM job (sbatch exports the
    submitting environment). A value already set by the user is overridden: the bytes of the
    committed bundles are the contract.
    """
    if not supported(cpuinfo):
        return None
    environ["OPENBLAS_CORETYPE"] = KERNEL
    return KERNEL
