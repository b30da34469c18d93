"""List the package's function-local imports and what each defers (a developer utility).

A function-local import is kept where it defers a heavy or optional dependency: this measures,
for every ``import`` inside a function of ``src/morphlearn``, the heavy modules that importing
that name loads beyond what its module already loads at import time (each in a fresh
interpreter). Prints a markdown table (file:line, the import, what it defers); an empty
"defers" column marks one that could move to the top of its module.

    .venv/bin/python tools/local_imports.py [--only-needless]
"""

from __future__ import annotations

import argparse
import ast
import functools
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PKG = ROOT / "src" / "morphlearn"
#: What counts as heavy: third-party libraries that cost a second or more to import or are
#: optional (an engine, a GPU stack, the notebook stack), and the ODE engine's C core.
HEAVY = (
    "xarray", "zarr", "pandas", "scipy", "numba", "pybullet", "mujoco", "warp", "mujoco_warp", "matplotlib",
    "jsonschema", "yaml", "tqdm", "pymoo", "cma", "IPython", "ipywidgets", "papermill", "nbformat",
    "morphlearn.ode._core",
)  # fmt: skip


@functools.cache
def loads(statement: str) -> frozenset[str] | None:
    """The heavy modules loaded by running ``statement`` in a fresh interpreter (None: it fails)."""
    code = f"import sys\n{statement}\nprint(','.join(h for h in {HEAVY!r} if h in sys.modules))"
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT)
    return frozenset(x for x in r.stdout.strip().split(",") if x) if r.returncode == 0 else None


def module_name(path: Path) -> str:
    parts = path.relative_to(PKG.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def local_imports() -> list[tuple[str, int, str, str]]:
    """(file, line, importing module, the import statement) of every import inside a function."""
    out = []
    for p in sorted(PKG.rglob("*.py")):
        mod = module_name(p)
        for fn in ast.walk(ast.parse(p.read_text())):
            if isinstance(fn, ast.FunctionDef | ast.AsyncFunctionDef):
                for node in ast.walk(fn):
                    if isinstance(node, ast.ImportFrom) and node.level:  # relative: make it absolute
                        base = mod.split(".")[: -node.level] if p.name != "__init__.py" else mod.split(".")
                        node = ast.ImportFrom(".".join([*base, *([node.module] if node.module else [])]), node.names, 0)
                    if isinstance(node, ast.Import | ast.ImportFrom):
                        out.append((str(p.relative_to(ROOT)), node.lineno, mod, ast.unparse(node)))
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only-needless", action="store_true", help="only those that defer nothing heavy")
    a = ap.parse_args()
    rows = []
    for path, line, mod, stmt in local_imports():
        here = loads(f"import {mod}") or frozenset()
        there = loads(stmt)
        defers = "(fails alone)" if there is None else ", ".join(sorted(there - here))
        if not a.only_needless or not defers:
            rows.append(f"| `{path}:{line}` | `{stmt}` | {defers} |")
    print("| where | import | defers |\n|---|---|---|")
    print("\n".join(rows))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
