"""Counts of the architecture's shape (issue 23): run ``python tools/shape_counts.py``
(``--no-shard``: the static counts only).

1. Model-name comparisons outside the registry: ``== "theory"`` and the like in src/, workflow/
   and notebooks/ (the same pattern as the project's before-stop hook).
2. Raw config reads below the edge: ``cfg[...]``, ``cfg.get(...)``, ``CFG[...]`` and the validated
   mapping's ``.source[...]`` in the package and the workflow's rule files, outside the edge:
   ``config.py`` (the schema), ``settings.py`` (the parse) and the models' ``parse`` methods, which
   configure.parse calls for each model's own section (AST-located).
3. Engine-name string constants outside the engine packages and the registry (issue 58): string
   literals that are exactly an engine's name (registry key or engine: ``"ode"``, ``"pybullet"``,
   ``"empirical"``, ``"mujoco"``, ``"reduced"``) in src/morphlearn, AST-located (docstrings and
   longer strings such as column names are not constants naming an engine). ``"theory"`` (the
   reference model, not an engine) is counted apart. The second results pipeline's modules, which
   issue 58 deleted, were left out while it ran (:data:`LEAVING`, now empty).
4. Per shard, measured by running one: design grids built, body files read, settings parsed.
"""

from __future__ import annotations

import ast
import re
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

NAME_CMP = re.compile(
    r'(==|!=)\s*"(theory|empirical|mujoco)"|"(theory|empirical|mujoco)"\s*(==|!=)'
    r'|startswith\("(theory|empirical|mujoco)'
)
RAW_READ = re.compile(r"\bcfg\[|\bcfg\.get\(|\bCFG\[|\.source\[")
EDGE_FILES = {"config.py", "settings.py"}
#: Modules whose ``cfg`` is a bundle's recorded config checked as data, not this run's settings:
#: their reads are listed apart.
RECORDED_CONFIG_FILES = {"bundles/check.py"}

#: String constants naming an engine: its registry key or its engine name.
ENGINE_NAMES = frozenset({"ode", "pybullet", "empirical", "mujoco", "reduced"})
#: The reference model's name, counted apart (it names a model, not an engine).
REFERENCE_NAME = "theory"
#: Where engine names belong: the model packages and the registry (paths under src/morphlearn).
ENGINE_HOMES = ("theory/", "empirical/", "mujoco/", "ode/", "reduced/", "models.py")
#: Modules left out of the count (none: issue 58 deleted the second results pipeline's writer).
LEAVING: tuple[str, ...] = ()
#: Issue 58's goal for :func:`engine_constants` (tests/test_shape_counts.py holds it).
ENGINE_CONSTANTS_GOAL = 5


def name_comparisons() -> list[str]:
    hits = []
    for folder, globs in (("src", ("*.py",)), ("workflow", ("*.py", "*.smk")), ("notebooks", ("*.ipynb",))):
        for g in globs:
            for p in sorted((ROOT / folder).rglob(g)):
                for i, line in enumerate(p.read_text().splitlines(), 1):
                    if NAME_CMP.search(line):
                        hits.append(f"{p.relative_to(ROOT)}:{i}: {line.strip()}")
    return hits


def _parse_methods(tree: ast.Module) -> list[range]:
    """Line ranges of ``parse`` methods of classes (the models' section parsers)."""
    out = []
    for cls in (n for n in ast.walk(tree) if isinstance(n, ast.ClassDef)):
        for f in cls.body:
            if isinstance(f, ast.FunctionDef) and f.name == "parse":
                out.append(range(f.lineno, (f.end_lineno or f.lineno) + 1))
    return out


def raw_reads() -> tuple[list[str], list[str], list[str]]:
    """(reads below the edge, reads inside model parse methods, reads of a bundle's recorded config)."""
    below, edge, recorded = [], [], []
    files = [*sorted((ROOT / "src/morphlearn").rglob("*.py")), *sorted((ROOT / "workflow/rules").glob("*.smk"))]
    for p in files:
        if p.name in EDGE_FILES and p.parent.name == "morphlearn":
            continue
        text = p.read_text()
        spans = _parse_methods(ast.parse(text)) if p.suffix == ".py" else []
        for i, line in enumerate(text.splitlines(), 1):
            if RAW_READ.search(line):
                where = edge if any(i in r for r in spans) else below
                rel = p.relative_to(ROOT / "src/morphlearn").as_posix() if p.suffix == ".py" else ""
                where = recorded if rel in RECORDED_CONFIG_FILES else where
                where.append(f"{p.relative_to(ROOT)}:{i}: {line.strip()}")
    return below, edge, recorded


def engine_constants() -> tuple[list[str], list[str]]:
    """(engine-name string constants, ``"theory"`` constants) outside the engine packages, the
    registry and the modules :data:`LEAVING`, as ``path:line: 'name'``."""
    engines, reference = [], []
    pkg = ROOT / "src/morphlearn"
    for p in sorted(pkg.rglob("*.py")):
        rel = p.relative_to(pkg).as_posix()
        if rel.startswith(ENGINE_HOMES) or rel.startswith(LEAVING):
            continue
        nodes = [n for n in ast.walk(ast.parse(p.read_text())) if isinstance(n, ast.Constant)]
        for n in sorted(nodes, key=lambda n: (n.lineno, n.col_offset)):
            hit = f"src/morphlearn/{rel}:{n.lineno}: {n.value!r}"
            if n.value in ENGINE_NAMES:
                engines.append(hit)
            elif n.value == REFERENCE_NAME:
                reference.append(hit)
    return engines, reference


def per_shard() -> dict[str, int]:
    """Run one smoke shard of each model with counters on what the redesign builds once."""
    from morphlearn import config, configure, grid, settings
    from morphlearn.physics import params
    from morphlearn.workflow import rules

    counts = {"design grids built": 0, "body files read": 0, "settings parsed": 0}
    real_post, real_load, real_parse = grid.DesignGrid.__post_init__, params.load_params, configure.parse

    def post(self: grid.DesignGrid) -> None:
        counts["design grids built"] += 1
        real_post(self)

    def load(path: str | Path) -> params.EmpiricalParams:
        counts["body files read"] += 1
        return real_load(path)

    def parse(cfg: dict) -> settings.Settings:
        counts["settings parsed"] += 1
        return real_parse(cfg)

    grid.DesignGrid.__post_init__ = post  # type: ignore[method-assign]
    params.load_params = load
    import morphlearn.physics.model as plugin

    plugin.load_params = load
    out = {}
    with tempfile.TemporaryDirectory() as tmp:
        raw = config.deep_merge(
            config.read(ROOT / "config.yaml", [ROOT / "config/smoke.yaml"]), {"results_dir": tmp, "design_cache": False}
        )
        for model in ("theory", "empirical"):
            for k in counts:
                counts[k] = 0
            s = parse(raw)  # as a rule script's entry does
            rules.run_shard(s, model, 0, Path(tmp) / f"{model}.nc")
            out |= {f"{model}: {k}": v for k, v in counts.items()}
    return out


def main() -> int:
    cmp = name_comparisons()
    below, edge, recorded = raw_reads()
    print(f"model-name comparisons outside the registry: {len(cmp)}")
    for h in cmp:
        print(f"  {h}")
    print(f"raw config reads below the edge: {len(below)}")
    for h in below:
        print(f"  {h}")
    print(f"  (inside the models' parse methods, which are the edge for their own sections: {len(edge)})")
    print(f"  (of a bundle's recorded config, checked as data: {len(recorded)})")
    engines, reference = engine_constants()
    print(f"engine-name string constants outside the engine packages and the registry: {len(engines)}")
    for h in engines:
        print(f"  {h}")
    print(f"  (the reference model's name, {REFERENCE_NAME!r}, as a constant there: {len(reference)})")
    if "--no-shard" in sys.argv:  # the static counts only (a shard runs a simulation)
        return 0
    for k, v in per_shard().items():
        print(f"per shard, {k}: {v}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
