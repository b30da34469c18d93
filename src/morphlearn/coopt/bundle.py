"""The coopt stage's committed bundle (``results/coopt``): re-render its figure from the bundle
alone and check every file against ``bundle.json``, as :mod:`morphlearn.bundles.scenario` does for
the scenario set.

The bundle holds the stage's outputs (``summary.csv``, ``runs.csv``, ``landscape.csv``,
``position_map.csv``, ``summary.md``, the restart runs), the figure (``coopt.png``, ``.pdf``,
``.caption.md``, drawn by notebooks/coopt.ipynb, the registered figure ``coopt``), a README and
``bundle.json``. Usage::

    python -m morphlearn.coopt.bundle render results/coopt   # re-render, then check
    python -m morphlearn.coopt.bundle seal results/coopt     # rewrite the digests (after a rebuild)
"""

from __future__ import annotations

import argparse
import json
import shutil
import sys
from pathlib import Path
from typing import Any

from morphlearn import provenance, store
from morphlearn.bundles import check as bundle_check
from morphlearn.bundles import render as bundle_render
from morphlearn.bundles.make import MANIFEST

NOTEBOOK = "notebooks/coopt.ipynb"
#: The figure's files in the bundle.
FIGURE = ("coopt.png", "coopt.pdf", "coopt.caption.md")
#: The step size of the evolution strategies the figure draws (config/coopt.yaml's first sigma).
SIGMA = 0.5


def _render(out_dir: Path, root: str | Path | None, sigma: float = SIGMA) -> float:
    """Run the figure notebook on a bundle's files, in place, the bundle passed as ``results_dir``'s
    ``coopt`` folder, so the caption names ``coopt/<file>`` as a workflow run's caption does
    (:func:`morphlearn.bundles.render.figure_in_place`)."""

    def params(rel: Path, style: str) -> dict[str, Any]:
        return {
            "results_dir": str(rel.parent),
            "coopt_dir": str(rel),
            "coopt_sigma": sigma,
            "style": style,
            **{k: str(rel / f) for k, f in zip(("png", "pdf", "caption"), FIGURE, strict=True)},
        }

    return bundle_render.figure_in_place(out_dir, root, NOTEBOOK, "coopt.ipynb", params)


def render(out_dir: str | Path, root: str | Path | None = None) -> tuple[float, list[str]]:
    """Re-render the figure of a coopt bundle in place; returns the wall seconds and the problems
    :func:`morphlearn.bundles.check.check` then finds (empty: byte-identical to ``bundle.json``)."""
    seconds = _render(Path(out_dir), root)
    return seconds, bundle_check.check(out_dir)


def seal(out_dir: str | Path) -> dict[str, str]:
    """Rewrite the ``files`` digests of ``bundle.json`` (every file but the logs; ``made_by`` kept)."""
    out_dir = Path(out_dir)
    mpath = out_dir / MANIFEST
    manifest = json.loads(mpath.read_text())
    listed = [
        p
        for p in sorted(out_dir.rglob("*"))
        if p.is_file() and p.name != MANIFEST and "logs" not in p.relative_to(out_dir).parts
    ]
    manifest["files"] = {p.relative_to(out_dir).as_posix(): provenance.sha256_file(p) for p in listed}
    mpath.write_text(json.dumps(manifest, indent=1, sort_keys=True) + "\n")
    return manifest["files"]


def build(
    tables: list[str | Path], figure: list[str | Path], out_dir: str | Path, configs: list[str]
) -> dict[str, Any]:
    """The bundle from a workflow run (rule coopt_bundle): the stage's tables and the figure's
    files (``figure``: png, pdf, caption, in :data:`FIGURE` order) copied into ``out_dir``, then
    ``bundle.json``: every file's SHA-256 (a README already there is kept and listed; logs are
    not), the command (from ``configs``, the config files given), commit and library versions."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    pairs = [(Path(t), Path(t).name) for t in tables] + [
        (Path(f), name) for f, name in zip(figure, FIGURE, strict=True)
    ]
    for src, name in pairs:
        with store.atomic_path(out_dir / name) as tmp:
            shutil.copyfile(src, tmp)
    extra = [c for c in configs if Path(c).name != "config.yaml"]  # config.yaml is always loaded
    # the target before --configfile, which takes every following word as a config file
    command = f"snakemake {out_dir.as_posix()}/{MANIFEST} --cores 2 --configfile {' '.join(extra)}"
    manifest = {
        "files": {},
        "made_by": {
            "command": command,
            "git_commit": provenance.git_commit(),
            "libraries": provenance.library_versions(),
        },
    }
    with store.atomic_path(out_dir / MANIFEST) as tmp:
        tmp.write_text(json.dumps(manifest, indent=1, sort_keys=True) + "\n")
    return seal(out_dir)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m morphlearn.coopt.bundle", description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    for name, what in (("render", "re-render the figure and check the bundle"), ("seal", "rewrite bundle.json")):
        sub.add_parser(name, help=what).add_argument("bundle_dir")
    a = ap.parse_args(argv)
    if a.cmd == "seal":
        print(f"{a.bundle_dir}: {len(seal(a.bundle_dir))} files sealed")
        return 0
    return bundle_render.report_in_place(a.bundle_dir, *render(a.bundle_dir))


if __name__ == "__main__":
    sys.exit(main())
