"""The package's layers (pyproject.toml's import-linter contract): kept on the real tree, broken
by a planted upward import, no import cycle, and the registry imports no model plug-in."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import grimp

ROOT = Path(__file__).resolve().parents[1]
LINT = Path(sys.executable).with_name("lint-imports")


def _lint(src: Path) -> subprocess.CompletedProcess[str]:
    # the package found first on the path is the one analysed (the copy's, not the editable install's)
    env = {**os.environ, "PYTHONPATH": str(src)}
    return subprocess.run(
        [str(LINT), "--config", str(ROOT / "pyproject.toml"), "--no-cache"],
        capture_output=True,
        text=True,
        env=env,
        cwd=src.parent,
        timeout=300,
    )


def _copy(tmp_path: Path) -> Path:
    src = tmp_path / "src"
    skip = shutil.ignore_patterns("__pycache__", "*.so")
    shutil.copytree(ROOT / "src" / "morphlearn", src / "morphlearn", ignore=skip)
    return src


def test_contracts_kept_on_the_tree(tmp_path: Path) -> None:
    r = _lint(_copy(tmp_path))
    assert r.returncode == 0 and "0 broken" in r.stdout, r.stdout + r.stderr


def test_a_planted_upward_import_breaks_the_contract(tmp_path: Path) -> None:
    src = _copy(tmp_path)
    grid = src / "morphlearn" / "grid.py"  # the core ...
    late = "\n\ndef _late() -> None:\n    from morphlearn.apps import cli  # noqa\n"  # ... up to the CLI
    grid.write_text(grid.read_text() + late)
    r = _lint(src)
    assert r.returncode != 0 and "BROKEN" in r.stdout and "morphlearn.grid -> morphlearn.apps.cli" in r.stdout, r.stdout


def test_an_engine_importing_another_breaks_the_contract(tmp_path: Path) -> None:
    src = _copy(tmp_path)
    ode = src / "morphlearn" / "ode" / "plugin.py"
    ode.write_text(ode.read_text() + "\nfrom morphlearn.mujoco import model as _mj  # noqa\n")
    r = _lint(src)
    assert r.returncode != 0 and "morphlearn.ode.plugin -> morphlearn.mujoco.model" in r.stdout, r.stdout


def _cycles(graph: grimp.ImportGraph) -> list[set[str]]:
    """Strongly connected components of more than one module (Tarjan, iterative)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    on, stack, out = set(), [], []
    for root in sorted(graph.modules):
        if root in index:
            continue
        work = [(root, iter(sorted(graph.find_modules_directly_imported_by(root))))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on.add(root)
        while work:
            v, it = work[-1]
            for w in it:
                if w not in index:
                    index[w] = low[w] = len(index)
                    stack.append(w)
                    on.add(w)
                    work.append((w, iter(sorted(graph.find_modules_directly_imported_by(w)))))
                    break
                if w in on:
                    low[v] = min(low[v], index[w])
            else:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[v])
                if low[v] == index[v]:
                    comp = set()
                    while True:
                        w = stack.pop()
                        on.discard(w)
                        comp.add(w)
                        if w == v:
                            break
                    if len(comp) > 1:
                        out.append(comp)
    return out


def test_no_import_cycle() -> None:
    graph = grimp.build_graph("morphlearn", cache_dir=None)
    assert _cycles(graph) == []
    # the detector finds one where there is one (a two-module loop added to the graph)
    graph.add_import(importer="morphlearn.grid", imported="morphlearn.apps.cli")
    assert any({"morphlearn.grid", "morphlearn.apps.cli"} <= c for c in _cycles(graph))


def test_the_registry_imports_no_plugin() -> None:
    code = (
        "import sys, morphlearn.models as m; "
        "print(sorted(k for k in sys.modules if k.split('.')[1:2] and k.split('.')[1] in m.PLUGINS))"
    )
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=120)
    assert r.stdout.strip() == "[]"
