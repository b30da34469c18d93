"""The figures: one notebook each (``notebooks/<name>.ipynb``), listed here with what they read.

This is the one place the workflow learns about figures (workflow/rules/figures.smk makes one
rule per entry). To add a figure: write ``notebooks/<name>.ipynb`` (copy one; keep its
``parameters`` cell) and add one :class:`Figure` line below; if it takes a new option, add that
key to the ``figures`` section of ``config_schema.yaml`` and name it in ``options``.

A figure's rule re-runs when its notebook, the shared style file, its results or any package
module its notebook imports (directly or through other package modules, see
:func:`notebook_modules`, or by a name its options give, :func:`named_modules`) change, so no code
edit can leave a stale figure.

Light imports only: the Snakefile imports this module at parse time.
"""

from __future__ import annotations

import ast
import functools
import json
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path

from morphlearn.figures.reproduction import stage_registry

PACKAGE = "morphlearn"


#: The ``reads`` token for every registered physics model (:func:`morphlearn.models.physics`).
PHYSICS = "physics"
#: The ``reads`` token for the reference physics engine (:func:`morphlearn.models.reference_physics`:
#: pybullet, the workflow's ``empirical`` results): the notebook's parameters name that model.
REFERENCE_PHYSICS = "reference physics"


@dataclass(frozen=True)
class Figure:
    """What a figure's notebook reads besides its own code."""

    #: Models whose results (metrics.csv, merged.zarr) it reads: a model's name (a model other
    #: than the reference only when enabled, its notebook then gets ``<name>_enabled = True``), or
    #: :data:`PHYSICS`: every registered physics model that is enabled, in registry order (the
    #: notebook gets ``physics``, name -> thresholds, and loops over them).
    reads: tuple[str, ...] = ("theory",)
    #: Notebook parameters taken from the config (morphlearn.figures.options.figure_options): a key of the config's
    #: ``figures`` section, or one of figures.options.DERIVED_FIGURE_OPTIONS.
    options: tuple[str, ...] = ()
    #: A config section whose ``enabled`` the figure needs (drawn only then), a condition of
    #: figures.options.FIGURE_CONDITIONS or STAGES, or None (always).
    needs: str | None = None
    #: Further results it reads, relative to results_dir.
    files: tuple[str, ...] = ()
    #: It reads the physics survey of ``survey_from`` when the config sets one (notebook
    #: parameter ``survey``: its model and thresholds): to draw it instead of the run's own physics
    #: results (Fig. 7 C-D, the survey figure), or to check the run's best designs against it
    #: (Figs. 3 and 6: morphlearn.figures.caption.subset_best).
    survey: bool = False


FIGURES: dict[str, Figure] = {
    "fig1": Figure(reads=(), options=("figure_robot",)),
    "fig2": Figure(options=("fig2_design", "fig2_envs")),
    "fig3": Figure(reads=("theory", PHYSICS), survey=True),
    "fig4": Figure(options=("trajectory_settings", "near_distance")),
    "fig5": Figure(options=("trajectory_settings", "near_distance")),
    "fig6": Figure(reads=("theory", PHYSICS), survey=True),
    "fig7": Figure(reads=("theory", PHYSICS), survey=True),
    # beyond the paper: real learners against M_L and M_CF (issue 15; config/learners.yaml)
    "learners": Figure(needs="learners", files=("learners/runs.csv", "learners/correlations.csv")),
    # beyond the paper: co-optimising the body against a four-synapse controller (issue 27;
    # config/coopt.yaml); also re-rendered from the committed bundle (morphlearn.coopt.bundle)
    "coopt": Figure(
        reads=(),
        needs="coopt",
        options=("coopt_sigma",),
        files=("coopt/summary.csv", "coopt/runs.csv", "coopt/position_map.csv"),
    ),
    # beyond the paper: the two physics engines design by design, and where they disagree most
    # (issue 25; config/engines.yaml; their data: rules engines_numbers, engines_disagreement)
    "engines": Figure(reads=(), needs="engines", files=("engines.csv", "engines.json", "engines.provenance.json")),
    "disagreement": Figure(
        reads=(),
        needs="engines",
        options=("morphology",),
        files=(
            "disagreement.json",
            "disagreement_success.npy",
            "disagreement_paths.npy",
            "disagreement.provenance.json",
        ),
    ),
    # beyond the paper: each engine and robot against ODE with the authors' robot (issue 42;
    # config/agreement.yaml; its data: rule agreement)
    "agreement": Figure(
        reads=(), needs="agreement", files=("agreement.csv", "agreement.json", "agreement.provenance.json")
    ),
    # a run without the theory (a researcher's own designs in a physics model): each design's map
    "maps": Figure(reads=(PHYSICS,), needs="physics_only"),
    # beyond the paper: theory against physics per design (issue 12; config/survey.yaml)
    "survey": Figure(reads=("theory", REFERENCE_PHYSICS), needs="physics_survey", options=("top",), survey=True),
}

#: Every figure rule's input: the one matplotlib style all figures use.
STYLE = "notebooks/style.mplstyle"


def notebook_path(name: str) -> str:
    return f"notebooks/{name}.ipynb"


def code_of(path: str | Path) -> str:
    """Python source of a notebook's code cells (IPython magics and shell lines dropped), or of a
    ``.py`` file."""
    p = Path(path)
    if p.suffix != ".ipynb":
        return p.read_text()
    cells = json.loads(p.read_text())["cells"]
    lines = []
    for c in cells:
        if c["cell_type"] != "code":
            continue
        src = "".join(c["source"]) if isinstance(c["source"], list) else c["source"]
        lines += [ln for ln in src.splitlines() if not ln.lstrip().startswith(("%", "!"))]
        lines.append("")
    return "\n".join(lines)


def _module_file(src: Path, module: str) -> Path | None:
    base = src.joinpath(*module.split("."))
    for p in (base.with_suffix(".py"), base / "__init__.py"):
        if p.is_file():
            return p
    return None


def _imported(code: str, current: str | None) -> Iterable[str]:
    """Dotted names this code may import (for ``from a import b`` both ``a`` and ``a.b``); every
    import, also those inside functions: a lazy import still changes what the figure draws."""
    for node in ast.walk(ast.parse(code)):
        if isinstance(node, ast.Import):
            yield from (a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            mod = node.module or ""
            if node.level and current:  # relative: from the current module's package
                parent = current.split(".")[: -node.level]
                mod = ".".join([*parent, mod] if mod else parent)
            yield mod
            yield from (f"{mod}.{a.name}" for a in node.names)


def notebook_modules(path: str | Path, src: str | Path = "src") -> list[str]:
    """The package's source files that ``path`` (a notebook or script) imports, directly or
    through other package modules, with the ``__init__.py`` of every package on the way.

    Paths are ``src``-prefixed as given (relative to the workflow root for rule inputs), sorted.
    """
    return _closure(_imported(code_of(path), None), src)


def named_modules(modules: Iterable[str], src: str | Path = "src") -> list[str]:
    """The package's source files of ``modules`` (dotted names a figure imports by name at run
    time, which no import statement shows: Fig. 1C's body, named by its option,
    :func:`morphlearn.figures.options.imported_modules`) and of what they import, as
    :func:`notebook_modules` gives them; a module outside the package adds none."""
    return _closure(modules, src)


def _closure(names: Iterable[str], src: str | Path) -> list[str]:
    src = Path(src)
    seen: dict[str, Path] = {}
    todo: list[tuple[str, ...]] = [tuple(names)]
    while todo:
        for name in todo.pop():
            if name != PACKAGE and not name.startswith(PACKAGE + "."):
                continue
            parts = name.split(".")
            for k in range(1, len(parts) + 1):  # importing a.b.c runs a/__init__, a/b/__init__
                mod = ".".join(parts[:k])
                if mod in seen:
                    continue
                f = _module_file(src, mod)
                if f is None:
                    continue  # a name imported from a module, not a module
                seen[mod] = f
                todo.append(_imports_of(f, mod if f.name != "__init__.py" else mod + ".__init__"))
    return sorted(str(p) for p in seen.values())


@functools.cache
def _file_imports(path: Path, current: str, mtime_ns: int, size: int) -> tuple[str, ...]:
    # Parsed once per process: the Snakefile asks for every figure's modules, and the figures
    # reach mostly the same package modules (8 full walks were ~3 CPU-s of every Snakemake start).
    # Keyed by mtime and size too, so an edited module is parsed again.
    return tuple(_imported(path.read_text(), current))


def _imports_of(path: Path, current: str) -> tuple[str, ...]:
    st = path.stat()
    return _file_imports(path, current, st.st_mtime_ns, st.st_size)


def reproduction_code(script: str | Path, src: str | Path = "src") -> list[str]:
    """The package files the reproduction rule runs: what ``script`` imports and every registered
    stage module (found by name, so :func:`notebook_modules` alone would not see them) with what it
    imports. Here, not in the table's modules: this module is the workflow's, and editing it must
    not re-render the table."""
    files = set(notebook_modules(script, src))
    for name in stage_registry.STAGES:
        stage = Path(src).joinpath(*stage_registry.PACKAGE.split("."), f"{name}.py")
        files |= {str(stage), *notebook_modules(stage, src)}
    return sorted(files)
