"""Re-render a committed results bundle with the current code and re-seal what the render wrote.

A bundle's figures and tables are rendered by the commit that made it; when a figure's code
changes (a title, a caption), ``render_only`` re-renders them and ``check-bundle`` then reports the
new bytes as changed. :func:`rerender` does that render in place with the bundle's own configs and
updates ``bundle.json`` for exactly the rendered files that changed, after checking that the bundle
was whole before and that nothing else changed (the data, the README: never re-sealed here). The
manifest records the commit that rendered them (``rendered_by``) beside the one that made the run.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path, PurePosixPath

from morphlearn import bounded, bundle, bundle_check, provenance, store

#: Files of a bundle that a render writes (figures and the reproduction tables).
RENDERED_SUFFIXES = (".png", ".pdf", ".caption.md")
#: The reproduction rule writes its sealed record too: the digests of the tables it wrote, so a
#: table that changes changes its record (the inputs it names are checked unchanged by check-bundle).
RENDERED_TABLES = (
    "reproduction.csv",
    "reproduction.md",
    "reproduction.html",
    "persistence.csv",
    "reproduction.provenance.json",
)


def is_rendered(rel: str) -> bool:
    p = PurePosixPath(rel)
    return rel in RENDERED_TABLES or (p.parts[0] == "figures" and rel.endswith(RENDERED_SUFFIXES))


def render_command(bundle_dir: str | Path, manifest: dict, cores: int) -> list[str]:
    """The README's render-only command for this bundle, with the configs that made it."""
    configs = [c for c in manifest.get("made_by", {}).get("configs", []) if Path(c).name != "config.yaml"]
    snakemake = str(Path(sys.executable).with_name("snakemake"))
    cmd = [snakemake, "--cores", str(cores), *(["--configfile", *configs] if configs else [])]
    return [*cmd, "--config", "render_only=True", f"results_dir={bundle_dir}", "--forceall"]


def _render(cmd: list[str], root: Path, target: str | Path) -> None:
    """Run the render command in ``root`` (it renders into ``target``); BundleError if it fails."""
    proc = subprocess.run(cmd, cwd=root, capture_output=True, text=True, env=dict(os.environ))
    if proc.returncode != 0:
        raise bundle.BundleError(f"{target}: the render failed (exit {proc.returncode}): {proc.stderr[-1500:]}")


def _copy_as_committed(src: Path, dst: Path, listed: dict[str, str]) -> None:
    """``bundle.json`` and the files it lists, as a fresh clone holds them (mtimes kept)."""
    for rel in [bundle.MANIFEST, *listed]:
        (dst / rel).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(src / rel, dst / rel)


@contextmanager
def rendered_copy(bundle_dir: str | Path, root: str | Path, cores: int = 2) -> Iterator[tuple[Path, dict, dict]]:
    """Render a copy of the whole bundle ``bundle_dir`` (relative to ``root``) beside it
    (``.rerender-<name>-*``, removed after): yields the copy, the bundle's manifest and the listed
    files whose digests the render changed (relative path -> new digest). The bundle itself is not
    touched. BundleError if it is not whole first or the render fails."""
    root = Path(root)
    path = root / bundle_dir
    problems = bundle_check.check(path)
    if problems:
        raise bundle.BundleError(f"{bundle_dir}: not re-rendered: {len(problems)} problem(s) first, {problems[0]}")
    manifest = bounded.json_file(path / bundle.MANIFEST)  # checked just above: a JSON object with its files
    work = Path(tempfile.mkdtemp(prefix=f".rerender-{path.name}-", dir=path.parent))
    try:
        _copy_as_committed(path, work, manifest["files"])
        rel = work.relative_to(root) if work.is_relative_to(root) else work
        _render(render_command(rel, manifest, cores), root, rel)
        changed = {r: provenance.sha256_file(work / r) for r in manifest["files"]}
        yield work, manifest, {r: d for r, d in changed.items() if d != manifest["files"][r]}
    finally:
        shutil.rmtree(work, ignore_errors=True)


def rerender(bundle_dir: str | Path, root: str | Path, cores: int = 2) -> list[str]:
    """Re-render ``bundle_dir`` (relative to the project ``root``) and re-seal its rendered files;
    the files whose digests changed. Raises BundleError (nothing re-sealed) if the bundle is not
    whole before, the render fails, or anything but a rendered file changed.

    Atomic (issue 38): the render runs on a copy beside the bundle (``.rerender-<name>-*`` in
    its parent folder, ignored by git like every folder of results/ that is not a bundle); only
    when it succeeded and changed nothing but rendered files are those files moved into the bundle
    and ``bundle.json`` rewritten last. A failure anywhere before leaves the bundle as it was."""
    path = Path(root) / bundle_dir
    mpath = path / bundle.MANIFEST
    commit = provenance.git_commit()  # before the render writes anything
    with rendered_copy(bundle_dir, root, cores) as (work, manifest, changed):
        other = sorted(r for r in changed if not is_rendered(r))
        if other:
            raise bundle.BundleError(
                f"{bundle_dir}: the render changed {other[0]}, which it does not make; nothing re-sealed"
            )
        # what the render writes beside the listed files (notebooks' HTML, logs, benchmarks): kept
        # in the bundle, as an in-place render leaves them (check-bundle allows exactly these)
        # (a listed one, like the reproduction record of a bundle that lists it, moves once: above)
        extra = [
            r
            for r in sorted(bundle_check.rendered_files(manifest["files"]))
            if r not in changed and (work / r).is_file()
        ]
        kept = {r: (path / r).read_bytes() for r in changed}  # put back if a move fails (a full disk)
        try:
            for r in [*changed, *extra]:
                (path / r).parent.mkdir(parents=True, exist_ok=True)
                os.replace(work / r, path / r)
        except OSError:
            for r, b in kept.items():
                (path / r).write_bytes(b)
            raise
    if changed:
        manifest["files"].update(changed)
        before = manifest.get("rendered_by", {}).get("files", [])
        manifest["rendered_by"] = {
            "git_commit": commit,
            "command": " ".join(["snakemake", *render_command(bundle_dir, manifest, cores)[1:]]),
            "files": sorted({*before, *changed}),
        }
        with store.atomic_path(mpath) as tmp:
            tmp.write_text(json.dumps(manifest, indent=1, sort_keys=True) + "\n")
    left = bundle_check.check(path)
    if left:
        raise bundle.BundleError(f"{bundle_dir}: after the render: {left[0]}")
    return sorted(changed)
