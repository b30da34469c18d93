"""Write envs/*.yaml (per-rule conda environments) from requirements.lock, so they agree.

Run after changing the lock: ``python tools/make_envs.py``; tests/test_envs.py checks agreement.
"""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CORE = ["numpy", "scipy", "numba", "xarray", "zarr", "pandas", "pyyaml", "jsonschema", "tqdm"]
# What each environment's rules import (tests/test_envs.py runs the rules in a virtual environment
# built from exactly these packages). CORE: the package's import-time needs (config, grid, store,
# rules, theory); pybullet and pymoo load only inside the empirical rules (lazy imports).
ENVS = {
    "theory": [*CORE, "numba-cuda"],  # numba-cuda: the GPU backend (theory.backend)
    "analysis": CORE,  # merge, metrics, summary
    # learners_shard, learners_analysis (CMA-ES of the cma package); the coopt rules (matplotlib:
    # coopt_analysis draws its figure)
    "learners": [*CORE, "cma", "matplotlib"],
    # empirical_shard; optimise_morphology (pymoo's NSGA-II, matplotlib for its Pareto plot)
    # mujoco: the second empirical model (morphlearn.mujoco), beside pybullet
    "empirical": [*CORE, "pybullet", "mujoco", "pymoo", "matplotlib"],
    # the figure notebooks (papermill + nbconvert + a kernel), Fig. 1C's pybullet render
    "figures": [*CORE, "pybullet", "matplotlib", "seaborn", "papermill", "nbconvert", "ipykernel"],
    # no rule: the interactive explorer (notebooks/explore.ipynb; docs/explorer.md), for conda users
    # (anywidget: the page bridge of morphlearn.apps.explore_app: width, URL, downloads, drawn)
    "explorer": [*CORE, "matplotlib", "ipywidgets", "ipympl", "anywidget", "voila", "papermill", "ipykernel"],
}


def lock() -> dict[str, str]:
    pins = {}
    for line in (ROOT / "requirements.lock").read_text().splitlines():
        m = re.match(r"^([A-Za-z0-9_.\-]+)==([^\s;]+)", line)
        if m:
            pins[m.group(1).lower()] = m.group(2)
    return pins


def render(name: str, pkgs: list[str], pins: dict[str, str]) -> str:
    lines = [
        f"# Conda environment for the {name} rules (snakemake --sdm conda)."
        if name != "explorer"
        else "# Conda environment for the interactive explorer (docs/explorer.md); no rule uses it.",
        "# Generated from requirements.lock by tools/make_envs.py: do not edit by hand.",
        f"name: morphlearn-{name}",
        "channels:",
        "  - conda-forge",
        "dependencies:",
        "  - python=3.11",
        "  - pip",
        "  - pip:",
    ]
    lines += [f"      - {p}=={pins[p]}" for p in pkgs]
    return "\n".join(lines) + "\n"


def main() -> None:
    pins = lock()
    for name, pkgs in ENVS.items():
        (ROOT / "envs" / f"{name}.yaml").write_text(render(name, pkgs, pins))


if __name__ == "__main__":
    main()
