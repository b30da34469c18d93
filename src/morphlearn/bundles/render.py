"""Re-render a committed results bundle with the current code and re-seal what the render wrote;
the one place a bundle is rendered.

A bundle's figures and tables are rendered by the commit that made it; when a figure's code
changes (a title, a caption), ``render_only`` re-renders them and ``check-bundle`` then reports the
new bytes as changed. :func:`rerender` does that render in place with the bundle's own configs and
updates ``bundle.json`` for exactly the rendered files that changed, after checking that the bundle
was whole before and that nothing else changed (the data, the README: never re-sealed here). The
manifest records the commit that rendered them (``rendered_by``) beside the one that made the run.

A workflow bundle renders through Snakemake (``render_only``: :func:`rendered_copy`); a stage
bundle whose figure no workflow render makes (the scenario set's, :mod:`morphlearn.bundles.scenario`;
coopt's, :mod:`morphlearn.coopt.bundle`) renders its figure's notebook on its own files in place
(:func:`figure_in_place`), as its rule does.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path, PurePosixPath
from typing import Any

import yaml

from morphlearn import provenance, store
from morphlearn.bundles import check as bundle_check
from morphlearn.bundles import make as bundle

#: The figures' style sheet (a stage bundle's notebook takes it as ``style``).
STYLE = "notebooks/style.mplstyle"
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


def failed_log(bundle_path: Path) -> Path:
    """Where the log of a failed render of ``bundle_path`` is kept: beside the bundle, hidden like
    its working copy (git ignores it under results/), replaced by the next failure."""
    return bundle_path.parent / f".render-failed-{bundle_path.name}.log"


def _failure(stderr: str, root: Path) -> tuple[str, list[Path], str]:
    """The failing rule of Snakemake's ``stderr`` (its first "Error in rule"), the log files that
    rule names (relative to ``root``) and the cause: the last line of the first of those logs that
    has one (the exception the notebook or script raised), else Snakemake's own error line."""
    lines = stderr.splitlines()
    start = next((i for i, t in enumerate(lines) if re.match(r"\s*Error in rule \S+:", t)), None)
    rule, logs = "", []
    if start is not None:
        rule = lines[start].split("Error in rule", 1)[1].strip().rstrip(":")
        for t in lines[start + 1 :]:
            if not t.strip():
                break
            key, _, value = t.strip().partition(": ")
            if key == "log":
                value = value.split(" (check log file", 1)[0]
                logs = [root / v.strip() for v in value.split(", ") if v.strip()]
    cause = ""
    for log in logs:
        try:
            text = log.read_text(errors="replace") if log.is_file() and log.suffix != ".ipynb" else ""
        except OSError:
            text = ""
        last = [t.strip() for t in text.splitlines() if t.strip()]
        if last:
            cause = last[-1]
            break
    refusal = next((i for i, t in enumerate(lines) if t.startswith("morphlearn:")), None)
    if not cause and refusal is not None:  # the workflow refused to start: its line and first detail
        detail = lines[refusal + 1].strip() if refusal + 1 < len(lines) and lines[refusal + 1].startswith("  ") else ""
        cause = " ".join(filter(None, (lines[refusal].strip(), detail)))
    if not cause:  # no rule log: Snakemake's own words (a missing input, a syntax error)
        own = [t.strip() for t in lines if re.search(r"(Error|Exception)\b", t) and "Error in rule" not in t]
        cause = own[0] if own else (lines[-1].strip() if lines else "no error output")
    return rule, logs, cause


def _kept_log(root: Path, target: str | Path) -> Path | None:
    """Where the log of a failed render into the working copy ``target`` is kept: the
    :func:`failed_log` of the bundle it copies (None for a target that is no working copy)."""
    m = re.fullmatch(re.escape(WORK_PREFIX) + r"(.+)-\d+-[a-z0-9_]{8}", Path(target).name)
    return failed_log(root / Path(target).parent / m.group(1)) if m else None


def _render(cmd: list[str], root: Path, target: str | Path) -> None:
    """Run the render command in ``root`` (it renders into ``target``); BundleError if it fails,
    naming the failing rule and its own error, with Snakemake's output and that rule's logs kept
    beside the bundle (:func:`failed_log`; the working copy that holds them is removed after)."""
    proc = subprocess.run(cmd, cwd=root, capture_output=True, text=True, env=dict(os.environ))
    if proc.returncode == 0:
        return
    keep = _kept_log(root, target)
    rule, logs, cause = _failure(proc.stderr, root)
    kept = ""
    if keep is not None:
        parts = [f"$ {' '.join(cmd)}\n(exit {proc.returncode})\n\n== Snakemake's output\n{proc.stderr}"]
        for log in logs:
            try:
                name = log.relative_to(root) if log.is_relative_to(root) else log
                parts.append(f"\n== {name}\n{log.read_text(errors='replace')}")
            except OSError:
                parts.append(f"\n== {log}: not written")
        try:
            keep.write_text("".join(parts))
            kept = f"; the whole log: {keep}"
        except OSError as e:
            kept = f"; its log could not be kept ({e.strerror})"
    where = f" in rule {rule}" if rule else ""
    raise bundle.BundleError(f"{target}: the render failed (exit {proc.returncode}){where}: {cause[:300]}{kept}")


#: A render's working copy: ``.rerender-<bundle name>-<pid>-<random>`` beside the bundle.
WORK_PREFIX = ".rerender-"


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OverflowError):  # another user's process (alive), a bad number
        return True
    return True


def remove_stale(bundle_path: Path) -> list[Path]:
    """Remove the working copies of renders of ``bundle_path`` whose process is gone (a render
    killed with kill -9 leaves its copy, with a bundle.json, behind); a live render's copy is kept.
    The removed folders."""
    gone = []
    for d in bundle_path.parent.glob(f"{WORK_PREFIX}{bundle_path.name}-*"):
        # <pid>-<mkdtemp's 8 characters>, or the 8 alone (made before the pid was in the name);
        # anything else is another bundle's (.rerender-survey-mujoco-* is not survey's)
        m = re.fullmatch(re.escape(f"{WORK_PREFIX}{bundle_path.name}-") + r"(?:(\d+)-)?[a-z0-9_]{8}", d.name)
        if m is None or not d.is_dir() or d.is_symlink():
            continue
        if m.group(1) is None or not _alive(int(m.group(1))):
            shutil.rmtree(d, ignore_errors=True)
            gone.append(d)
    return gone


def _copy_as_committed(src: Path, dst: Path, listed: dict[str, str]) -> None:
    """``bundle.json`` and the files it lists, as a fresh clone holds them (mtimes kept); a listed
    file that is missing stays missing (the render's start check names it)."""
    for rel in [bundle.MANIFEST, *listed]:
        if (src / rel).is_file():
            (dst / rel).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src / rel, dst / rel)


@contextmanager
def rendered_copy(bundle_dir: str | Path, root: str | Path, cores: int = 2) -> Iterator[tuple[Path, dict, dict]]:
    """Render a copy of the whole bundle ``bundle_dir`` (relative to ``root``) beside it
    (``.rerender-<name>-<pid>-*``, removed after, or at the next start when this process was
    killed): yields the copy, the bundle's manifest and the listed files whose digests the render
    changed (relative path -> new digest). The bundle itself is not touched. BundleError if it is
    not whole or the render fails (naming the failing rule's error; its log kept beside the
    bundle, :func:`failed_log`).

    Whole means what the render's own start check says (``rules.check_render_inputs``: the copy
    against its manifest, file by file and row by row): one check, the one a render run by hand
    gets, not a second one here first. Before the copy, only what the copy needs: the manifest's
    shape, and every name it lists inside the bundle (nothing outside it is read or written)."""
    root = Path(root)
    path = root / bundle_dir
    try:
        manifest = bundle_check.read_manifest(path / bundle.MANIFEST)
    except bundle.BundleError as e:
        raise bundle.BundleError(f"{bundle_dir}: not re-rendered: {e}") from None
    outside = [r for r in manifest["files"] if not bundle_check.inside(path, r)]
    if outside:
        raise bundle.BundleError(
            f"{bundle_dir}: not re-rendered: {bundle.MANIFEST} lists {bundle_check.shown(outside[0])}, a path "
            "outside the bundle or a name no file can have (not read)"
        )
    remove_stale(path)
    # the pid in the name: the next start knows whether this copy's render is still running
    work = Path(tempfile.mkdtemp(prefix=f"{WORK_PREFIX}{path.name}-{os.getpid()}-", dir=path.parent))
    try:
        _copy_as_committed(path, work, manifest["files"])
        rel = work.relative_to(root) if work.is_relative_to(root) else work
        try:
            _render(render_command(rel, manifest, cores), root, rel)
        except bundle.BundleError as e:  # said of the bundle, not of its working copy
            said = str(e).replace(str(rel), str(bundle_dir))
            raise bundle.BundleError(f"{bundle_dir}: not re-rendered: {said}") from e
        missing = [r for r in manifest["files"] if not (work / r).is_file()]
        if missing:  # a render that checks nothing at start (no figures) leaves them missing
            raise bundle.BundleError(
                f"{bundle_dir}: not re-rendered: {missing[0]}: listed in {bundle.MANIFEST} but missing"
            )
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


def render_notebook(root: Path, notebook: str, cwd: Path, executed: Path, params: dict[str, Any]) -> float:
    """Run a figure notebook of the project at ``root`` with papermill from ``cwd`` (the folder
    that holds ``results/``, so captions name paths relative to it), the project's ``src``
    importable; the executed copy goes to ``executed`` (relative to ``cwd``). The stage bundles
    re-render their figure this way (:func:`figure_in_place`). Returns the wall seconds."""
    (cwd / executed).parent.mkdir(exist_ok=True)
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(filter(None, [str(root / "src"), os.environ.get("PYTHONPATH")])))
    papermill = Path(sys.executable).with_name("papermill")
    t0 = time.perf_counter()
    proc = subprocess.run(
        [
            str(papermill),
            str(root / notebook),
            str(executed),
            "-y",
            yaml.safe_dump(params, default_flow_style=True, width=10**6).strip(),
        ],
        cwd=cwd,
        capture_output=True,
        text=True,
        env=env,
    )
    if proc.returncode:
        raise RuntimeError(f"papermill {notebook} failed ({proc.returncode}):\n{proc.stderr[-3000:]}")
    return time.perf_counter() - t0


def figure_in_place(
    out_dir: str | Path,
    root: str | Path | None,
    notebook: str,
    executed: str,
    params: Callable[[Path, str], dict[str, Any]],
) -> float:
    """A stage bundle's figure rendered from the bundle's own files, in place: ``notebook`` run
    from the folder that holds ``results/`` with ``params(rel, style)`` (``rel``: the bundle
    relative to that folder, so the caption names ``<name>/<file>`` wherever the project is;
    ``style``: the figures' style sheet), the executed copy to ``logs/<executed>``. ``root``: the
    project (default: this code's). The wall seconds."""
    out_dir = Path(out_dir).resolve()
    root = Path(root).resolve() if root else bundle_check.ROOT
    cwd = out_dir.parents[1]  # <project>/results/<name>
    rel = out_dir.relative_to(cwd)
    return render_notebook(root, notebook, cwd, rel / "logs" / executed, params(rel, str(root / STYLE)))


def report_in_place(bundle_dir: str | Path, seconds: float, problems: list[str]) -> int:
    """What a stage bundle's ``render`` command prints after :func:`figure_in_place` and the check
    (the scenario set's and coopt's), and its exit status: 0 when every file matches bundle.json."""
    print(
        f"{bundle_dir}: figure re-rendered in {seconds:.1f} s; "
        + ("every file matches bundle.json" if not problems else f"{len(problems)} problem(s):")
    )
    for p in problems:
        print(f"  {p}")
    return 1 if problems else 0
