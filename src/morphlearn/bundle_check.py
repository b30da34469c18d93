"""Checking a results bundle against its manifest, and reading one model's results out of it
(the bundle itself: :mod:`morphlearn.bundle`)."""

from __future__ import annotations

import json
import shutil
from pathlib import Path, PurePosixPath
from typing import Any

import numpy as np
import pandas as pd

from morphlearn import bounded, metrics, models, provenance, store
from morphlearn.bundle import MANIFEST, BundleError, bundle_files
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


def check(out_dir: str | Path, *, rows: bool = True) -> list[str]:
    """Problems of a bundle (empty: every file listed, present and unchanged, nothing extra,
    every metrics row consistent). Never reads a path the manifest names outside the bundle."""
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
        if rel not in listed and rel not in rendered:
            problems.append(f"{p}: not listed in {MANIFEST}")
    if rows:
        problems += check_rows(out_dir, listed)
    return problems


#: The longest file name, and path, a Linux file system holds (bytes): longer ones raise OSError.
NAME_MAX, PATH_MAX = 255, 4096


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
        problems += [f"{path}: {p}" for p in row_problems(table, _controllers(path))]
        problems += [f"{path}: {p}" for p in meaning_problems(path, table)]
    return problems


#: The coordinate columns of a metrics table, in the order of ``DesignGrid.coords``.
COORDS = ("l1x", "l1y", "l2x", "l2y")


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
    if "model" in table.columns and (bad := sorted(set(d[table.model.astype(str) != model].tolist()))):
        out.append(f"design {_few(bad)}: model column is not {model!r} (the store's)")
    on = table[np.isin(d, list(want))]
    if all(c in on.columns for c in COORDS) and len(on):
        have = on[list(COORDS)].to_numpy(dtype=float)
        off = ~np.isclose(have, grid.coords(on.design.to_numpy()), atol=1e-9).all(axis=1)
        if off.any():
            out.append(f"design {_few(on.design[off].tolist())}: coordinates are not its grid position's")
    return out + _store_disagrees(metrics_csv, table, ds)


def _store_disagrees(metrics_csv: Path, table: pd.DataFrame, ds: Any) -> list[str]:
    """Each design the store holds recomputed at the table's recorded thresholds: its row's counts."""
    try:
        th = metrics.Thresholds(
            **provenance.read_record(metrics_csv.with_suffix(".provenance.json"))["config"]["thresholds"]
        )
    except (ValueError, KeyError, TypeError):  # the record's own check names it
        return []
    envs = [f"n_{a}" for a in ENV_ANGLES_DEG]
    if not all(c in table.columns for c in (*envs, "generalists", "at_least_one")):
        return []
    rows = table.drop_duplicates("design").set_index("design")
    bad, missing = [], []
    for i, design in enumerate(int(x) for x in ds["design"].values):
        if design not in rows.index:
            missing.append(design)
            continue
        try:
            one = store.read_design(ds, i)
        except ValueError:  # a damaged chunk: the bundle's digests (and store.verify_merged) name it
            continue
        dm = metrics.design_metrics(metrics.success(one["first_time"], one["min_dist"], th), one["status"])
        row = rows.loc[design]
        if [*(int(row[c]) for c in envs), int(row.generalists), int(row.at_least_one)] != [
            *dm.per_env,
            dm.generalists,
            dm.at_least_one,
        ]:
            bad.append(design)
    out = []
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
    need = ["design", *envs, "generalists", "at_least_one", "M_L", "M_CF"]
    missing = [c for c in need if c not in table.columns]
    if missing:
        return [f"no column {missing[0]!r} (a metrics table has {', '.join(need)})"]
    counts = table[[*envs, "generalists", "at_least_one"]]
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
        bad[f"a count above the {cells} controllers"] = (counts.to_numpy() > cells).any(axis=1)
        want_l = np.array([float(metrics.CSV_FLOAT_FORMAT % (x / cells)) for x in g])
        bad[f"M_L != generalists / {cells}"] = table.M_L.to_numpy() != want_l
    want_cf = np.array([float(metrics.CSV_FLOAT_FORMAT % (x / y)) if y else 0.0 for x, y in zip(g, a, strict=True)])
    bad["M_CF != generalists / at_least_one"] = table.M_CF.to_numpy() != want_cf
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
