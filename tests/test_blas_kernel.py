"""The workflow pins one OpenBLAS kernel for its child processes, only where the CPU can run it."""

from __future__ import annotations

import platform
from pathlib import Path

import pytest

from morphlearn.workflow import blas_kernel


def _cpuinfo(tmp_path: Path, flags: str) -> Path:
    p = tmp_path / "cpuinfo"
    p.write_text(f"processor\t: 0\nflags\t\t: {flags}\n\nprocessor\t: 1\nflags\t\t: {flags}\n")
    return p


@pytest.mark.parametrize(
    ("machine", "flags", "pinned"),
    [
        ("x86_64", "fpu sse2 avx avx2 fma avx512f", "Haswell"),
        ("x86_64", "fpu sse2 avx", None),  # forcing a kernel the CPU cannot run would crash numpy
        ("aarch64", "fp asimd", None),
    ],
)
def test_pin_only_where_the_kernel_runs(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, machine: str, flags: str, pinned: str | None
) -> None:
    monkeypatch.setattr(platform, "machine", lambda: machine)
    env = {"OPENBLAS_CORETYPE": "SkylakeX"}
    assert blas_kernel.pin(env, _cpuinfo(tmp_path, flags)) == pinned
    # a user's own choice is overridden only when the pinned kernel can run
    assert env["OPENBLAS_CORETYPE"] == (pinned or "SkylakeX")


def test_missing_cpuinfo_pins_nothing(tmp_path: Path) -> None:
    env: dict[str, str] = {}
    assert blas_kernel.pin(env, tmp_path / "absent") is None and env == {}


def test_snakefile_pins_before_any_rule() -> None:
    text = (Path(__file__).resolve().parents[1] / "Snakefile").read_text()
    assert text.index("blas_kernel.pin()") < text.index("include:")
