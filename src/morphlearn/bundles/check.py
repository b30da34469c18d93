"""Checking a results bundle against its manifest, and reading one model's results out of it
(the bundle itself: :mod:`morphlearn.bundles.make`)."""

from __future__ import annotations

import json
import os
import re
import shlex
import shutil
import stat
from pathlib import Path, PurePosixPath
from typing import Any

import numpy as np
import pandas as pd
import yaml

from morphlearn import bounded, metrics, models, provenance, store
from morphlearn import config as cfgmod
from morphlearn.bundles.make import MANIFEST, BundleError, bundle_files, drawn_designs
from morphlearn.grid import ENV_ANGLES_DEG, DesignGrid


def extract_model(bundle_dir: str | Path, model: str, out: dict[str, str | Path]) -> None:
    """Copy one model's results out of a bundle (``out``: metrics, provenance, merged paths),
    after checking the whole bundle against its checksums; nothing is written if it fails."""
    problems = check(bundle_dir)
    if problems:
        raise BundleError(f"{bundle_dir}: {len(problems)} problem(s), first: {problems[0]}")
    src = Path(bundle_dir) / model
    dst = Path(out["metrics"])
    with store.atomic_path(dst) as tmp:
        shutil.copy2(src / "metrics.csv", tmp)
    # custody carries over: the copied table's record is sealed with its digest (a committed
    # bundle's older record is vouched for by the manifest just checked)
    rec = provenance.read_record(src / "metrics.provenance.json")
    if provenance.SEAL not in rec:
        rec = provenance.seal(rec | {"from_bundle": str(bundle_dir)}, [dst])
    with store.atomic_path(Path(out["provenance"])) as tmp:
        tmp.write_text(json.dumps(rec, indent=1, sort_keys=True) + "\n")
    with store.atomic_path(Path(out["merged"])) as tmp:
        shutil.copytree(src / "merged.zarr", tmp)


def check(out_dir: str | Path, *, rows: bool = True, notes: list[str] | None = None) -> list[str]:
    """Problems of a bundle (empty: every file listed, present and unchanged, nothing extra, no
    link, every metrics row consistent with itself and its store, every chunk of the store
    readable, and bundle.json's commits, configs, command and subsets what made it). Never reads a
    path the manifest names outside the bundle. ``notes``: what it cannot tell is added there
    (commits in a shallow clone)."""
    out_dir = Path(out_dir)
    mpath = out_dir / MANIFEST
    if not mpath.is_file():
        return [f"{mpath}: missing"]
    try:
        manifest = bounded.json_file(mpath)  # size and nesting bounded: one line, never a traceback
    except ValueError as e:
        return [f"{mpath}: unreadable ({e})"]
    listed = manifest.get("files") if isinstance(manifest, dict) else None
    if not isinstance(listed, dict) or not all(isinstance(k, str) and isinstance(v, str) for k, v in listed.items()):
        return [f"{mpath}: wrong shape: an object whose 'files' maps each path in the bundle to its SHA-256"]
    root = out_dir.resolve()
    problems = []
    for rel, digest in listed.items():
        p = out_dir / rel
        odd = odd_name(rel)
        if odd:
            problems.append(f"{mpath}: lists {shown(rel)}, {odd} (not read)")
        elif not _inside(rel, p, root):
            problems.append(f"{mpath}: lists {rel!r}, a path outside the bundle (not read)")
        elif not p.is_file():
            problems.append(f"{p}: listed in {MANIFEST} but missing")
        elif provenance.sha256_file(p) != digest:
            problems.append(f"{p}: checksum differs from {MANIFEST} (changed or damaged)")
    rendered = rendered_files(listed)
    for p in bundle_files(out_dir):
        rel = p.relative_to(out_dir).as_posix()
        if rel not in listed and rel not in rendered and not p.is_symlink():  # links: below, with their target
            problems.append(f"{p}: not listed in {MANIFEST}")
    problems += special_files(out_dir, listed)
    if rows:
        problems += check_rows(out_dir, listed)
        problems += manifest_problems(out_dir, manifest, notes)
    return problems


def special_files(out_dir: Path, listed: dict[str, str]) -> list[str]:
    """Every symbolic link in the bundle, of any kind (to a file, to a folder, to the bundle itself,
    dangling; listed or not: the bundle rule makes none), and every unlisted pipe, socket or device
    (issue 57: ``etcdir -> /etc``, ``loop -> .`` and ``ode2 -> ode`` passed). Links are not followed."""
    out = []
    for top, dirs, files in os.walk(out_dir, followlinks=False):
        for name in sorted([*dirs, *files]):
            p = Path(top) / name
            rel = p.relative_to(out_dir).as_posix()
            try:
                mode = p.lstat().st_mode
            except OSError:
                continue
            if stat.S_ISLNK(mode):
                try:
                    target = os.readlink(p)
                except OSError:
                    target = "?"
                why = "listed in" if rel in listed else "not listed in"
                out.append(f"{p}: a symbolic link (to {shown(target)}), {why} {MANIFEST} (a bundle holds no links)")
            elif not (stat.S_ISREG(mode) or stat.S_ISDIR(mode)) and rel not in listed:
                out.append(f"{p}: neither a file nor a folder (a pipe, socket or device), not listed in {MANIFEST}")
    return out


#: The longest file name, and path, a Linux file system holds (bytes): longer ones raise OSError.
NAME_MAX, PATH_MAX = 255, 4096


#: What a manifest must be (:func:`read_manifest`).
MANIFEST_SHAPE = "a JSON object whose 'files' maps each path in the bundle to its SHA-256"


def read_manifest(mpath: Path) -> dict[str, Any]:
    """A bundle's manifest, a JSON object whose ``files`` maps names to digests (the names not yet
    checked: :func:`inside`), or a BundleError naming the file, the key and what is allowed (a
    manifest that is a list, a string, a number, null or whose files are not a mapping once ended
    in an AttributeError traceback)."""
    try:
        man = bounded.json_file(mpath)
    except (OSError, ValueError) as e:
        raise BundleError(f"{mpath}: unreadable ({e}); allowed: {MANIFEST_SHAPE}") from None
    if not isinstance(man, dict):
        raise BundleError(f"{mpath}: top level is {json.dumps(man)[:40]}, not an object; allowed: {MANIFEST_SHAPE}")
    files = man.get("files")
    if not isinstance(files, dict) or not all(isinstance(k, str) and isinstance(v, str) for k, v in files.items()):
        raise BundleError(f"{mpath}: 'files' = {json.dumps(files)[:40]} is invalid; allowed: {MANIFEST_SHAPE}")
    return man


def inside(out_dir: Path, rel: str) -> bool:
    """Whether a listed name names a path inside the bundle ``out_dir`` that a file can have (what
    :func:`check` reads; a link out of the bundle is outside)."""
    return _inside(rel, out_dir / rel, out_dir.resolve())


def odd_name(rel: str) -> str | None:
    """Why a name a manifest lists cannot name a file (None when it can): a NUL byte, or a name
    longer than the file system allows. Said in the message instead of a traceback (issue 38)."""
    if "\x00" in rel:
        return f"a name with a NUL byte (at character {rel.index(chr(0))})"
    longest = max((len(part.encode("utf-8", "surrogateescape")) for part in rel.split("/")), default=0)
    if longest > NAME_MAX or len(rel.encode("utf-8", "surrogateescape")) > PATH_MAX:
        return f"a name longer than the file system allows ({longest} bytes in one part; at most {NAME_MAX})"
    return None


def shown(rel: str, limit: int = 80) -> str:
    """A listed name as a message shows it: quoted with its odd characters escaped, cut to ``limit``."""
    r = repr(rel)
    return r if len(r) <= limit else f"{r[: limit - 5]}...{r[-1]} ({len(rel)} characters)"


def _inside(rel: str, p: Path, root: Path) -> bool:
    if odd_name(rel):
        return False
    parts = PurePosixPath(rel).parts
    if not rel or PurePosixPath(rel).is_absolute() or ".." in parts or "\\" in rel:
        return False
    try:
        return p.resolve().is_relative_to(root)  # a symbolic link out of the bundle is outside
    except (OSError, RuntimeError):
        return False


def rendered_files(listed: dict[str, str]) -> set[str]:
    """What re-rendering a bundle in place writes beside its files, exactly: for each figure
    listed (``D/N.png``) its executed notebook's HTML, its notebook log and benchmark, and the
    reproduction table's log and benchmark. Anything else not listed is a stray."""
    out = {".snakemake_timestamp"}
    for rel in listed:
        if not rel.endswith(".png"):
            continue
        pp = PurePosixPath(rel)
        stem = pp.with_suffix("")
        out |= {f"{stem}.html", f"logs/{stem}.ipynb", f"logs/{stem}.log", f"benchmarks/{stem}.tsv"}
    if "reproduction.csv" in listed:
        out |= {"logs/reproduction.log", "benchmarks/reproduction.tsv", "reproduction.provenance.json"}
    return out


def check_rows(out_dir: str | Path, listed: dict[str, str]) -> list[str]:
    """Every metrics row of the bundle consistent in itself: counts within the controllers,
    generalists <= every environment's count <= at least one <= their sum, M_L = generalists /
    controllers and M_CF = generalists / at least one (as the table stores floats). A forger who
    edits a row and its digest in the manifest must now keep all of these, and re-simulation
    (``--resimulate``) checks the counts themselves."""
    out_dir = Path(out_dir)
    problems = []
    for rel in sorted(
        r for r in listed if PurePosixPath(r).name == "metrics.csv" and _inside(r, out_dir / r, out_dir.resolve())
    ):
        path = out_dir / rel
        if not path.is_file():
            continue
        try:
            table = pd.read_csv(path)
        except (ValueError, UnicodeDecodeError) as e:
            problems.append(f"{path}: unreadable ({e})")
            continue
        found = [*row_problems(table, _controllers(path)), *meaning_problems(path, table)]
        problems += [f"{path}: {p}" for p in dict.fromkeys(found)]  # a missing column: said once
    return problems


#: The coordinate columns of a metrics table, in the order of ``DesignGrid.coords``.
COORDS = ("l1x", "l1y", "l2x", "l2y")
#: The columns the outcome arrays determine (counts recomputed from them, flagged included).
ARRAY_COLUMNS = (*(f"n_{a}" for a in ENV_ANGLES_DEG), "generalists", "at_least_one", "flagged")
#: Every column a metrics table must have (issue 57: tables with the coordinates or the model
#: column deleted passed).
REQUIRED = ("model", "design", *COORDS, *ARRAY_COLUMNS[:-1], *metrics.METRICS, "flagged")


def meaning_problems(metrics_csv: Path, table: pd.DataFrame) -> list[str]:
    """What a metrics table says that its merged store beside it contradicts (issue 38: a forger
    who re-sealed the digests got a duplicated, deleted or off-grid row, a rewritten model column
    or a store replaced by ``[]`` through every check). The rows must be exactly the designs the
    store's science names (every design of its grid, or its ``designs`` list), each once, with the
    grid coordinates of its index and the store's model; the store must be readable and each
    design it holds must give the table's counts (its metrics recomputed from its arrays at the
    table's recorded thresholds). A table with no store beside it (a scenario's) is not checked
    here. At most a few lines per kind."""
    merged = metrics_csv.parent / "merged.zarr"
    if not merged.is_dir():
        return []
    try:
        ds = store.open_merged(merged)
        sci = store.science_of(ds)
        model = str(ds.attrs.get("model", sci.get("model")))
        grid = DesignGrid(models.get(model).positions_of(sci))
    except (ValueError, KeyError, TypeError, AttributeError) as e:  # IntegrityError is a ValueError
        return [f"the merged store beside it is unreadable ({str(e).splitlines()[0][:200]})"]
    if "design" not in table.columns or not pd.api.types.is_integer_dtype(table.design):
        return ["no integer design column"]
    if absent := [c for c in REQUIRED if c not in table.columns]:
        return [f"no column {absent[0]!r} (a metrics table has {', '.join(REQUIRED)})"]
    out = []
    d = table.design.to_numpy()
    want = set(int(x) for x in sci["designs"]) if isinstance(sci.get("designs"), list) else set(range(grid.size))
    for why, rows in (
        ("appears more than once", sorted(set(d[table.design.duplicated()].tolist()))),
        (f"is not a design of this bundle's grid or design list ({len(want)} designs)", sorted(set(d) - want)),
        ("is missing (a design of this bundle's grid or design list)", sorted(want - set(d.tolist()))),
    ):
        if rows:
            out.append(f"design {_few(rows)} {why}")
    if bad := sorted(set(d[table.model.astype(str) != model].tolist())):
        out.append(f"design {_few(bad)}: model column is not {model!r} (the store's)")
    on = table[np.isin(d, list(want))]
    if len(on):
        try:
            have = on[list(COORDS)].to_numpy(dtype=float)
        except (ValueError, TypeError):
            return [*out, f"coordinate columns {', '.join(COORDS)} that are not numbers"]
        off = ~np.isclose(have, grid.coords(on.design.to_numpy()), rtol=0, atol=1e-9).all(axis=1)
        if off.any():
            out.append(f"design {_few(on.design[off].tolist())}: coordinates are not its grid position's")
    return out + _store_disagrees(metrics_csv, table, ds)


def _store_disagrees(metrics_csv: Path, table: pd.DataFrame, ds: Any) -> list[str]:
    """Every design the store declares read and verified (a missing, unreadable or damaged chunk
    is a problem, never skipped: issue 57), then recomputed at the table's recorded thresholds:
    its row's counts, flagged included (:data:`ARRAY_COLUMNS`)."""
    try:
        th = metrics.Thresholds(
            **provenance.read_record(metrics_csv.with_suffix(".provenance.json"))["config"]["thresholds"]
        )
    except (ValueError, KeyError, TypeError):  # the record's own check names it
        th = None
    cols = list(ARRAY_COLUMNS)
    rows = table.drop_duplicates("design").set_index("design")
    usable = th is not None and all(pd.api.types.is_integer_dtype(rows[c]) for c in cols)
    bad, missing, unreadable = [], [], []
    for i, design in enumerate(int(x) for x in ds["design"].values):
        try:
            one = store.read_design(ds, i)  # store.verify_merged's check: names a missing chunk file
        except store.IntegrityError as e:
            unreadable.append(str(e))
            continue
        if design not in rows.index:
            missing.append(design)
            continue
        if not usable:
            continue
        dm = metrics.design_metrics(metrics.success(one["first_time"], one["min_dist"], th), one["status"])
        row = rows.loc[design]
        if [int(row[c]) for c in cols] != [*dm.per_env, dm.generalists, dm.at_least_one, dm.flagged]:
            bad.append(design)
    out = [f"the merged store beside it: {u}" for u in unreadable[:3]]
    if len(unreadable) > 3:
        out.append(f"the merged store beside it: {len(unreadable) - 3} more chunks missing or unreadable")
    if missing:
        out.append(f"design {_few(missing)}: held in the merged store but has no row")
    if bad:
        out.append(f"design {_few(bad)}: its row's counts differ from the merged store's arrays")
    return out


def _few(designs: list[int]) -> str:
    more = f" and {len(designs) - 3} more" if len(designs) > 3 else ""
    return ", ".join(map(str, designs[:3])) + more


def row_problems(table: pd.DataFrame, cells: int | None) -> list[str]:
    """What is inconsistent in a metrics table's rows (``cells``: controllers per design, when
    known), at most a few lines per kind."""
    envs = [f"n_{a}" for a in ENV_ANGLES_DEG]
    missing = [c for c in REQUIRED if c not in table.columns]
    if missing:
        return [f"no column {missing[0]!r} (a metrics table has {', '.join(REQUIRED)})"]
    counts = table[[*envs, "generalists", "at_least_one", "flagged"]]
    if not all(pd.api.types.is_integer_dtype(t) for t in counts.dtypes):
        return ["counts that are not whole numbers"]
    n = counts[envs].to_numpy()
    g, a = table.generalists.to_numpy(), table.at_least_one.to_numpy()
    total = n.sum(axis=1)
    bad: dict[str, np.ndarray] = {
        "a negative count": (counts.to_numpy() < 0).any(axis=1),
        "generalists above an environment's count": (g[:, None] > n).any(axis=1),
        "an environment's count above at_least_one": (n > a[:, None]).any(axis=1),
        "at_least_one above the sum of the environments' counts": a > total,
        "counts that no set of controllers gives (sum over environments > 3 at_least_one + generalists)": total
        > 3 * a + g,
    }
    if cells:
        bad[f"a count above the {cells} controllers"] = (counts.to_numpy()[:, :-1] > cells).any(axis=1)
        bad[f"flagged above the {4 * cells} trajectories (4 environments x {cells} controllers)"] = (
            table.flagged.to_numpy() > 4 * cells
        )
    for name, m in metrics.METRICS.items():  # each metric from the counts, as the table stores it
        try:
            want = [
                float(metrics.CSV_FLOAT_FORMAT % m.of(metrics.Counts(cells or 0, int(x), int(y))))
                for x, y in zip(g, a, strict=True)
            ]
        except ZeroDivisionError:  # a metric of the controllers per design, not known here
            continue
        bad[f"{name} != its value from the counts ({m.text})"] = table[name].to_numpy() != np.array(want)
    out = []
    for why, mask in bad.items():
        rows = table.design[mask].tolist()
        if rows:
            more = f" and {len(rows) - 3} more" if len(rows) > 3 else ""
            out.append(f"design {', '.join(map(str, rows[:3]))}{more}: {why}")
    return out


def _controllers(metrics_csv: Path) -> int | None:
    """Controllers per design of a table in a bundle: from the merged store beside it, else from
    the summary of its folder (a scenario's), else unknown."""
    merged = metrics_csv.parent / "merged.zarr"
    if merged.is_dir():
        try:
            ds = store.open_merged(merged)
            return int(ds.sizes["w1"] * ds.sizes["w2"])
        except (ValueError, KeyError, OSError):
            return None
    summary = metrics_csv.parent.parent / "summary.json"
    try:
        return int(bounded.json_file(summary)[metrics_csv.parent.name]["controllers"])
    except (OSError, ValueError, KeyError, TypeError):
        return None


# -- what bundle.json says about how the bundle was made (issue 57: a forged commit, command or
# design subset passed) ---------------------------------------------------------------------------

#: What a recorded config file may be named: a relative path of plain words ending in .yaml or .yml
#: (the project's own, config.yaml and config/*.yaml, must exist at the bundle's commit; a user's
#: own file elsewhere is read from the working tree where it is there, else a note says so).
CONFIG_NAME = re.compile(r"(?!/)(?!-)(?!.*(^|/)\.\.(/|$))[\w./-]+\.ya?ml")
#: What a recorded command's words may hold: no shell syntax (``;``, ``|``, ``$``, quotes, ...).
SAFE_WORD = re.compile(r"[\w./=:,+@-]+")
#: The project root of this code (commits and config files are looked up in its repository).
ROOT = Path(__file__).resolve().parents[3]


def project() -> Path:
    """Where commits and config files are looked up: this code's checkout, or (an installed
    package, no config.yaml beside it) the folder the command runs in."""
    return ROOT if (ROOT / "config.yaml").is_file() else Path.cwd()


def _commits(manifest: dict[str, Any]) -> dict[Any, str]:
    """Every commit bundle.json names -> where (made_by, rendered_by, each subset's and scenario's
    shards and designs)."""
    named: dict[Any, str] = {}
    for key in ("made_by", "rendered_by"):
        if isinstance(manifest.get(key), dict) and "git_commit" in manifest[key]:
            named.setdefault(manifest[key]["git_commit"], f"{key}.git_commit")
    sims = [(f"subsets.{m}.simulated_by", s.get("simulated_by")) for m, s in _dict(manifest.get("subsets")).items()]
    sims += [(f"simulated_by.{n}", s) for n, s in _dict(manifest.get("simulated_by")).items()]
    for where, by in sims:
        for part in ("git_commits", "design_commits"):
            for key in _dict(_dict(by).get(part)):
                named.setdefault(key, f"{where}.{part}")
    return named


def _dict(x: Any) -> dict[Any, Any]:
    return x if isinstance(x, dict) else {}


def commit_problems(manifest: dict[str, Any], notes: list[str]) -> list[str]:
    """Each commit bundle.json names is a commit of this repository's history (HEAD or an ancestor
    of it); where the repository cannot tell (no git, a shallow clone) a note says so instead."""
    out: list[str] = []
    unsure: list[str] = []
    for c, where in _commits(manifest).items():
        if not isinstance(c, str) or not re.fullmatch(r"[0-9a-f]{40}", c):
            out.append(f"{where} names {shown(str(c))}, not a commit (allowed: a 40-digit git hash)")
            continue
        known = provenance.in_history(c, cwd=project())
        if known is None:
            unsure.append(c)
        elif not known:
            if provenance.is_shallow(cwd=project()):
                unsure.append(c)
            else:
                out.append(f"{where} names commit {c}, which is not in this repository's history (HEAD or an ancestor)")
    if unsure:
        notes.append(
            f"cannot tell whether {len(unsure)} commit(s) it names (first {unsure[0][:12]}) are of this history: "
            "no git repository here, or a shallow clone (git fetch --unshallow, then check again)"
        )
    return out


def _config_text(name: str, commit: str | None) -> tuple[str | None, bool]:
    """A recorded config file's text at the bundle's commit, else the working tree's; whether it
    came from the commit."""
    text = provenance.file_at(commit, name, cwd=project()) if commit else None
    if text is not None:
        return text, True
    p = project() / name
    try:
        return (bounded.read_bytes(p).decode("utf-8") if p.is_file() else None), False
    except (ValueError, OSError, UnicodeDecodeError):
        return None, False


def command_problems(manifest: dict[str, Any], notes: list[str]) -> list[str]:
    """The configs and commands bundle.json records: config files of the project (at its commit),
    commands of plain words naming only them, and the command of a workflow bundle the one its
    configs give (:func:`morphlearn.bundles.make.command_of`)."""
    from morphlearn.bundles.make import command_of

    by = manifest["made_by"]
    commit = by.get("git_commit") if isinstance(by.get("git_commit"), str) else None

    out = []
    if "tool" in by:  # every bundle is made by the workflow's rules (issue 58: one results pipeline)
        return [f"made_by.tool = {shown(str(by['tool']))}; allowed: none (a bundle the workflow made)"]
    configs = by.get("configs")
    if configs is not None:
        if not isinstance(configs, list) or not all(isinstance(c, str) and CONFIG_NAME.fullmatch(c) for c in configs):
            allowed = "a list of relative YAML file names (config.yaml, config/NAME.yaml)"
            return [f"made_by.configs = {shown(str(configs))}; allowed: {allowed}"]
    named = list(configs or [])
    rendered = _dict(manifest.get("rendered_by")).get("command")
    for where, cmd in (("made_by", by.get("command")), ("rendered_by", rendered)):
        if cmd is None and where == "rendered_by":
            continue
        if not isinstance(cmd, str):
            out.append(f"{where}.command = {shown(str(cmd))}; allowed: the snakemake command that made it")
            continue
        try:
            words = shlex.split(cmd)
        except ValueError:
            words = []
        bad = next((w for w in words if not SAFE_WORD.fullmatch(w)), None)
        if not words or bad is not None or words[0] != "snakemake":
            out.append(
                f"{where}.command = {shown(cmd)}: not a snakemake command of plain words"
                + (f" (holds {shown(bad)})" if bad else "")
                + "; allowed: the snakemake command its configs give"
            )
            continue
        given = _configfiles(words)
        named += given
        extra = [c for c in configs or [] if Path(c).name != "config.yaml"]
        if where == "made_by" and configs is not None and cmd != command_of(configs):
            out.append(f"made_by.command = {shown(cmd)}; its configs {configs} give {command_of(configs)!r}")
        elif where == "rendered_by" and configs is not None and (given != extra or "render_only=True" not in words):
            out.append(
                f"rendered_by.command = {shown(cmd)}: not a render_only run of the configs that made it ({extra})"
            )
    missing, from_tree = [], False
    for name in dict.fromkeys(named):
        if not CONFIG_NAME.fullmatch(name):
            out.append(f"a command names the config file {shown(name)}; allowed: a relative YAML file name")
            continue
        text, at_commit = _config_text(name, commit)
        from_tree |= text is not None and not at_commit
        if text is None:
            missing.append(name)
    own = [m for m in missing if m == "config.yaml" or m.startswith("config/")]
    if own:
        out.append(f"names the config file {own[0]}, which this repository does not hold (at {commit or 'HEAD'})")
    elif missing:
        notes.append(
            f"cannot tell what its config file {missing[0]} held (not in this repository: a config of your own?): "
            "its subsets and results folder are not checked against its configs"
        )
    if from_tree:
        notes.append("its config files were read from the working tree (its commit is not in this clone)")
    return out


def _configfiles(words: list[str]) -> list[str]:
    out, taking = [], False
    for w in words:
        if w in ("--configfile", "--configfiles"):
            taking = True
        elif w.startswith("-"):
            taking = False
        elif taking:
            out.append(w)
    return out


def _configured(configs: list[str], commit: str | None) -> dict[str, Any] | None:
    """The config a bundle's recorded files give (base first, then the others in order), read at
    its commit; None where one cannot be read."""
    cfg: dict[str, Any] = {}
    for name in sorted(configs, key=lambda c: c != "config.yaml"):
        text, _ = _config_text(name, commit)
        try:
            data = yaml.safe_load(text) if text is not None else None
        except yaml.YAMLError:
            data = None
        if not isinstance(data, dict):
            return None
        cfg = cfgmod.deep_merge(cfg, data)
    return cfg


def _config_agrees(by: dict[str, Any], cfg: dict[str, Any], held: list[str]) -> list[str]:
    """The recorded configs (as merged at the bundle's commit) give its results folder and enable
    every model it holds (a section's ``enabled``, else the schema's default)."""
    props = cfgmod.schema().get("properties", {})
    out = []
    rd = cfg.get("results_dir", props.get("results_dir", {}).get("default"))
    if by.get("results_dir") != rd:
        out.append(f"made_by.results_dir = {by.get('results_dir')!r:.80}, but its configs {by['configs']} give {rd!r}")
    for model in (m for m in held if not m.startswith(f"{store.SURVEY_DIR}/")):
        sec = cfg.get(model)
        on = sec.get("enabled") if isinstance(sec, dict) and "enabled" in sec else None
        if on is None:
            on = props.get(model, {}).get("properties", {}).get("enabled", {}).get("default")
        if on is False:
            out.append(f"holds {model} results, but its configs {by['configs']} do not enable {model}")
    return out


def subset_problems(out_dir: Path, manifest: dict[str, Any]) -> list[str]:
    """Each model's subset in bundle.json is what its store holds and what its configs keep: the
    designs ``subsets.<model>.designs`` are those of ``<model>/merged.zarr``, and those the bundle
    rule keeps of the table with the recorded configs (``analysis.top``, ``bundle_designs``: the
    canonical, the paper's best, the top by each metric and their mirror images; every design of a
    table that is not the whole grid); ``of`` is the table's length; ``simulated_by`` the store's
    own record; and every store of the bundle has its subset."""
    if "subsets" not in manifest:
        return []
    mpath = out_dir / MANIFEST
    subsets = manifest["subsets"]
    if not isinstance(subsets, dict):
        return [f"{mpath}: subsets is not an object of model -> designs"]
    by = manifest["made_by"]
    commit = by.get("git_commit") if isinstance(by.get("git_commit"), str) else None
    cfg = _configured(by["configs"], commit) if isinstance(by.get("configs"), list) and by["configs"] else None
    out = []
    stores = {p.parent.relative_to(out_dir).as_posix() for p in out_dir.glob("*/merged.zarr")}
    stores |= {p.parent.relative_to(out_dir).as_posix() for p in out_dir.glob(f"{store.SURVEY_DIR}/*/merged.zarr")}
    for rel in sorted(stores - set(subsets)):
        out.append(f"{mpath}: {rel}/merged.zarr has no subset in bundle.json")
    if cfg is not None:
        out += [f"{mpath}: {p}" for p in _config_agrees(by, cfg, [str(m) for m in subsets])]
    for model, s in subsets.items():
        where = f"{mpath}: subsets.{model}"
        designs = _dict(s).get("designs")
        if not isinstance(designs, list) or not all(isinstance(d, int) and not isinstance(d, bool) for d in designs):
            out.append(f"{where}.designs is not a list of design indices")
            continue
        merged = out_dir / str(model) / "merged.zarr"
        if not _inside(f"{model}/merged.zarr", merged, out_dir.resolve()) or not merged.is_dir():
            out.append(f"{where} names {len(designs)} designs, but the bundle holds no {model}/merged.zarr")
            continue
        try:
            ds = store.open_merged(merged)
            sci = store.science_of(ds)
            held = [int(d) for d in ds["design"].values]
            shards = json.loads(ds.attrs.get("provenance_json", "{}")).get("shards", {})
            table = pd.read_csv(out_dir / str(model) / "metrics.csv")
            n = models.get(str(sci["model"])).positions_of(sci)
        except (ValueError, KeyError, TypeError, AttributeError, OSError):  # the table's checks name it
            continue
        if designs != held:
            out.append(f"{where}.designs {_few(designs)} are not the designs {model}/merged.zarr holds ({_few(held)})")
            continue
        if s.get("of") != len(table):
            out.append(f"{where}.of = {s.get('of')!r:.40}, but {model}/metrics.csv has {len(table)} rows")
        if s.get("simulated_by") != shards:
            out.append(f"{where}.simulated_by is not the shards' record in {model}/merged.zarr")
        if cfg is None or str(model).startswith(f"{store.SURVEY_DIR}/"):
            continue  # a survey read from another bundle keeps that bundle's subset
        top, kept = _dict(cfg.get("analysis")).get("top", 10), cfg.get("bundle_designs", "drawn")
        try:
            every = len(table) == n**4 and kept == "drawn"
            want = [int(d) for d in (drawn_designs(table, n, int(top)) if every else np.sort(table.design))]
        except (ValueError, TypeError, KeyError):  # a malformed table: its own checks name it
            continue
        if designs != want:
            odd = sorted(set(designs) ^ set(want))
            out.append(
                f"{where}.designs are not the designs its configs keep (analysis.top = {top}, bundle_designs = "
                f"{kept}, of {model}/metrics.csv): they differ in design {_few(odd)}"
            )
    return out


def manifest_problems(out_dir: Path, manifest: dict[str, Any], notes: list[str] | None = None) -> list[str]:
    """What bundle.json records about how the bundle was made, checked (issue 57): its commits
    (:func:`commit_problems`), configs and commands (:func:`command_problems`) and design subsets
    (:func:`subset_problems`). ``notes``: where a check cannot tell, a line is added there."""
    notes = [] if notes is None else notes
    mpath = out_dir / MANIFEST
    if not isinstance(manifest.get("made_by"), dict):
        return [f"{mpath}: no made_by record (the configs, command and commit that made it)"]
    out = [f"{mpath}: {p}" for p in commit_problems(manifest, notes) + command_problems(manifest, notes)]
    if "git_commit" not in manifest["made_by"]:
        out.append(f"{mpath}: made_by names no git_commit (the commit that made it)")
    return out + subset_problems(out_dir, manifest)
