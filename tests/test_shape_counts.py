"""Issue 58's shape counts that must not rise: engine-name string constants outside the engine
packages and the registry (at most the goal), and raw settings reads below the edge (none).
Each count is also shown to see what it claims to count (a planted line is found)."""

from __future__ import annotations

import importlib.util
import shutil
import sys
from pathlib import Path
from types import ModuleType

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def counts() -> ModuleType:
    spec = importlib.util.spec_from_file_location("shape_counts", ROOT / "tools/shape_counts.py")
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    sys.modules.setdefault("shape_counts", mod)
    spec.loader.exec_module(mod)
    return mod


def test_engine_name_constants_stay_within_the_goal(counts: ModuleType) -> None:
    engines, _ = counts.engine_constants()
    assert len(engines) <= counts.ENGINE_CONSTANTS_GOAL, "\n".join(engines)


def test_no_raw_settings_read_below_the_edge(counts: ModuleType) -> None:
    below, _, _ = counts.raw_reads()
    assert below == []


def _planted(tmp_path: Path, rel: str, text: str) -> Path:
    """A copy of the package and rule files with one more file."""
    shutil.copytree(ROOT / "src/morphlearn", tmp_path / "src/morphlearn")
    shutil.copytree(ROOT / "workflow/rules", tmp_path / "workflow/rules")
    (tmp_path / rel).write_text(text)
    return tmp_path


def test_a_planted_engine_name_is_counted_but_not_in_its_package_or_a_docstring(
    counts: ModuleType, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    before, _ = counts.engine_constants()
    planted = '"""The ode engine."""\nENGINE = "mujoco"\nLABEL = "M_L_ode"\n'
    root = _planted(tmp_path, "src/morphlearn/planted.py", planted)
    (root / "src/morphlearn/ode/planted.py").write_text('E = "ode"\n')
    monkeypatch.setattr(counts, "ROOT", root)
    after, _ = counts.engine_constants()
    assert [h for h in after if h not in before] == ["src/morphlearn/planted.py:2: 'mujoco'"]


def test_a_planted_settings_read_is_counted(
    counts: ModuleType, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    root = _planted(tmp_path, "workflow/rules/planted.smk", 'x = S.source["theory"]\n')
    (root / "src/morphlearn/planted.py").write_text('def f(s):\n    return s.source["engines"]\n')
    monkeypatch.setattr(counts, "ROOT", root)
    below, _, _ = counts.raw_reads()
    assert {h.split(":")[0] for h in below} >= {"workflow/rules/planted.smk", "src/morphlearn/planted.py"}
