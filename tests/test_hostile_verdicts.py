"""Verdicts a forger of another bundle cannot flip, and manifests whose every field is typed: a
result that reads other bundles is checked against them (``bundles_read``), a screen's verdict
rows are re-simulated on request (``--resimulate screen``), derived mirror designs are exact
mirrors, summaries are what their tables give, a bundle's commit is younger than what made its
designs, every manifest field has its type before use (one line, no traceback), and unlisted files
are named whatever their names. Every attack runs on a copy (tmp dir); no committed byte changes."""

from __future__ import annotations

import contextlib
import io
import json
import shutil
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import zarr
from conftest import ROOT

from morphlearn import metrics, provenance, store
from morphlearn.apps import cli, explore
from morphlearn.bundles import check as bundle_check
from morphlearn.bundles import make as bundle
from morphlearn.bundles import render as bundle_render
from morphlearn.bundles import resimulate, summaries
from morphlearn.grid import ENV_ANGLES_DEG

#: The bundles these attacks copy (results/paper reads the other two where they are).
USED = ("paper", "reduced-paper", "ode-screened-paper", "ode-paper", "reduced-maps")
#: The screen's rows with no arrays in results/reduced-paper (its margin rests on them).
MARGIN_ROWS = (234, 316, 559, 560, 641, 6319, 6320, 6401, 6404, 6486)
#: The repository's first commit: in history, older than every config and simulation.
ROOT_COMMIT = "2a4a6576967f9a86ddb6959eb67d7b4ca90560e7"


def _digests(root: Path) -> dict[str, str]:
    return {p.relative_to(root).as_posix(): provenance.sha256_file(p) for p in sorted(root.rglob("*")) if p.is_file()}


@pytest.fixture(scope="module")
def committed() -> dict[str, dict[str, str]]:
    """The committed bundles' digests before the attacks (compared after each)."""
    return {name: _digests(ROOT / "results" / name) for name in USED}


@pytest.fixture(autouse=True)
def _unchanged(committed: dict[str, dict[str, str]]):
    yield
    for name, before in committed.items():
        assert _digests(ROOT / "results" / name) == before, f"results/{name} changed"


@pytest.fixture(scope="module")
def pristine(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A project folder (a Snakefile, results/) holding the used bundles as a clone does: bundle.json
    and the files it lists. Copied again per test (:func:`proj`)."""
    wd = tmp_path_factory.mktemp("pristine") / "wd"
    (wd / "results").mkdir(parents=True)
    (wd / "Snakefile").write_text("# the attacks are refused before any rule runs\n")
    for name in USED:
        src = ROOT / "results" / name
        for rel in [bundle.MANIFEST, *json.loads((src / bundle.MANIFEST).read_text())["files"]]:
            (wd / "results" / name / rel).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src / rel, wd / "results" / name / rel)
    return wd


@pytest.fixture
def proj(pristine: Path, tmp_path: Path, request: pytest.FixtureRequest) -> Path:
    """A fresh copy of the project with only the bundles a test names (``bundles`` marker's
    arguments; default all used)."""
    mark = request.node.get_closest_marker("bundles")
    names = mark.args if mark else USED
    wd = tmp_path / "wd"
    (wd / "results").mkdir(parents=True)
    shutil.copy2(pristine / "Snakefile", wd / "Snakefile")
    for name in names:
        shutil.copytree(pristine / "results" / name, wd / "results" / name)
    return wd


def _run(*args: str) -> tuple[int, str]:
    """``morphlearn ARGS``: exit code and what it printed (stdout and stderr); a traceback fails."""
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf), contextlib.redirect_stderr(buf):
        try:
            rc = cli.main(list(args))
        except SystemExit as e:
            rc = int(e.code or 0)
    out = buf.getvalue()
    assert "Traceback" not in out, out
    return rc, out


def _manifest(b: Path) -> dict:
    return json.loads((b / bundle.MANIFEST).read_text())


def _write_manifest(b: Path, m: dict) -> None:
    (b / bundle.MANIFEST).write_text(json.dumps(m, indent=1, sort_keys=True) + "\n")


def _reseal(b: Path) -> None:
    """The forger's last step: every sealed record of the bundle re-sealed with its files' digests,
    then bundle.json's digests of every file it lists."""
    for rec_path in sorted(b.rglob("*.provenance.json")):
        rec = json.loads(rec_path.read_text())
        outs = [rec_path.parent / n for n in rec.get(provenance.OUTPUTS, {})]
        if rec_path.name == "metrics.provenance.json" and (rec_path.parent / "merged.zarr").is_dir():
            cfg = rec.get("config", {})
            if "merged_sha256_overall" in cfg:
                cfg["merged_sha256_overall"] = store.open_merged(rec_path.parent / "merged.zarr").attrs["integrity"][
                    "overall"
                ]
        if provenance.SEAL in rec:
            rec_path.write_text(json.dumps(provenance.seal(rec, outs), indent=1, sort_keys=True) + "\n")
    m = _manifest(b)
    m["files"] = {rel: provenance.sha256_file(b / rel) for rel in m["files"] if (b / rel).is_file()}
    _write_manifest(b, m)


def _resummarise(b: Path, top: int = 10) -> None:
    """The forger's summary: re-made from the forged tables, as the summary rule makes it."""
    s = json.loads((b / "summary.json").read_text())
    for model in [k for k in s if isinstance(s[k], dict)]:
        one = summaries.summarise(pd.read_csv(b / model / "metrics.csv"), top)
        s[model] = one | {"controllers": s[model]["controllers"]}
    s = json.loads(json.dumps(s))
    (b / "summary.json").write_text(json.dumps(s, indent=1, sort_keys=True) + "\n")
    (b / "summary.md").write_text(summaries.summary_markdown(s))


def _forge_rows(b: Path, model: str, designs: list[int], generalists: int = 0) -> None:
    """Rows of designs set to ``generalists`` (M_L, M_CF as the counts give them), consistently."""
    path = b / model / "metrics.csv"
    t = pd.read_csv(path)
    cells = int(store.open_merged(b / model / "merged.zarr").sizes["w1"]) ** 2
    for d in designs:
        row = t.design == d
        a = int(t.loc[row, "at_least_one"].iloc[0])
        c = metrics.Counts(cells, generalists, a)
        t.loc[row, "generalists"] = generalists
        for name, m in metrics.METRICS.items():
            t.loc[row, name] = float(metrics.CSV_FLOAT_FORMAT % m.of(c))
    t.to_csv(path, index=False, float_format=metrics.CSV_FLOAT_FORMAT)
    _resummarise(b)


# -- A1: a result checked against the bundles it read -------------------------------------------


def test_a_forged_screen_is_named_by_check_render_and_rerender(proj: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The issue's attack: designs 559 and 6401 forged (generalists 45 -> 0) in a copy of
    results/reduced-paper and re-sealed. That bundle still passes (the rows have no arrays: only
    re-simulation can tell); results/paper, which read it, names it in check-bundle, and render
    and rerender-bundle refuse before rendering, saying an input bundle changed."""
    red, paper = proj / "results" / "reduced-paper", proj / "results" / "paper"
    _forge_rows(red, "reduced", [559, 6401])
    _reseal(red)
    assert bundle_check.check(red) == []
    rc, out = _run("check-bundle", str(paper))
    assert rc == 1 and "the bundle results/reduced-paper it read changed since" in out, out
    before = _digests(paper)
    monkeypatch.chdir(proj)
    monkeypatch.setattr(bundle_render, "_render", lambda *a: pytest.fail("the render started"))
    for cmd in ("render", "rerender-bundle"):
        rc, out = _run(cmd, "results/paper")
        assert rc == 1 and "an input bundle changed (its data, not the figure code)" in out, (cmd, out)
        assert "results/reduced-paper" in out and "figure code changed" not in out
    assert _digests(paper) == before


@pytest.mark.parametrize("design", MARGIN_ROWS)
@pytest.mark.bundles("paper", "reduced-paper")
def test_each_margin_row_forged_is_named(proj: Path, design: int) -> None:
    red = proj / "results" / "reduced-paper"
    _forge_rows(red, "reduced", [design], generalists=0)
    _reseal(red)
    problems = bundle_check.check(proj / "results" / "paper")
    assert any("results/reduced-paper it read changed" in p for p in problems), problems


@pytest.mark.bundles("paper", "ode-screened-paper")
def test_a_forged_refinement_is_named(proj: Path) -> None:
    ref = proj / "results" / "ode-screened-paper"
    (ref / "ode" / "metrics.csv").write_text((ref / "ode" / "metrics.csv").read_text() + "\n")
    _reseal(ref)
    problems = bundle_check.check(proj / "results" / "paper")
    assert any("results/ode-screened-paper it read changed" in p for p in problems), problems


@pytest.mark.bundles("paper")
@pytest.mark.parametrize(
    "read",
    [
        {"results/reduced-paper/reduced/metrics.csv": "0" * 64},
        {"results/nowhere/reduced/metrics.csv": "0" * 64},
        {"../../etc/passwd": "0" * 64},
        {"/etc/passwd": "0" * 64},
        ["results/reduced-paper/reduced/metrics.csv"],
        {"results/reduced-paper/reduced/metrics.csv": 7},
    ],
)
def test_a_forged_bundles_read_record_is_refused(proj: Path, read: object, tmp_path: Path) -> None:
    """The reading bundle's own record altered (digests, names, types) and re-sealed: named."""
    paper = proj / "results" / "paper"
    path = paper / bundle_check.READ_RECORD
    rec = json.loads(path.read_text())
    rec["bundles_read"] = read
    outs = [paper / n for n in rec[provenance.OUTPUTS]]
    path.write_text(json.dumps(provenance.seal(rec, outs), indent=1, sort_keys=True) + "\n")
    _reseal(paper)
    rc, out = _run("check-bundle", str(paper))
    assert rc == 1 and "bundles_read" in out, out


@pytest.mark.slow
def test_a_consistent_forger_is_caught_by_resimulating_the_screen(proj: Path) -> None:
    """The forger also re-seals results/paper's record with the forged table's digest (its
    verdicts now rest on rows no one re-checked): ``--resimulate screen`` re-simulates the rows the
    screen's verdicts read (24, 40 s on 2 cores) and names the forged designs."""
    red, paper = proj / "results" / "reduced-paper", proj / "results" / "paper"
    _forge_rows(red, "reduced", [559, 6401])
    _reseal(red)
    path = paper / bundle_check.READ_RECORD
    rec = json.loads(path.read_text())
    rec["bundles_read"]["results/reduced-paper/reduced/metrics.csv"] = provenance.sha256_file(
        red / "reduced" / "metrics.csv"
    )
    path.write_text(
        json.dumps(provenance.seal(rec, [paper / n for n in rec[provenance.OUTPUTS]]), indent=1, sort_keys=True) + "\n"
    )
    _reseal(paper)
    assert bundle_check.check(paper) == []
    said: list[str] = []
    problems = resimulate.resimulate(paper, ["screen"], seed=1, say=said.append)
    assert {559, 6401} <= {int(d) for d in said[0].rsplit(": ", 1)[1].strip("[]").split(", ")}, said
    assert any("reduced design 559: metrics row" in p for p in problems), problems
    assert any("reduced design 6401: metrics row" in p for p in problems), problems


def test_screen_designs_are_the_refinement_and_the_rows_at_the_margin() -> None:
    """Which rows the screen's verdicts read: the refinement's designs and, by each metric, the
    best outside and the open ones (a made-up screen: by M_L the margin 0.1 leaves design 9 open;
    by M_CF, margin 0, design 8 is the best outside, ruled out)."""
    screen = pd.DataFrame(
        {"design": [1, 2, 8, 9, 10], "M_L": [0.5, 0.4, 0.1, 0.45, 0.0], "M_CF": [0.5, 0.4, 0.3, 0, 0]}
    )
    refined = pd.DataFrame({"design": [1, 2], "M_L": [0.5, 0.3], "M_CF": [0.5, 0.4]})
    assert resimulate.screen_designs(screen, refined) == [1, 2, 8, 9]


@pytest.mark.bundles("ode-paper")
def test_resimulate_screen_of_a_bundle_without_a_screen_says_so(proj: Path) -> None:
    rc, out = _run("check-bundle", str(proj / "results" / "ode-paper"), "--resimulate", "screen")
    assert rc == 1 and "reads no screen" in out, out


# -- A2: derived mirror designs are exact mirrors ------------------------------------------------


def _edit_store(merged: Path, design: int, change: Callable[[dict[str, np.ndarray]], None]) -> None:
    """A design's arrays changed in place and the store's digests re-computed (the forger's)."""
    ds = store.open_merged(merged)
    i = [int(d) for d in ds["design"].values].index(design)
    arrays = store.read_design(ds, i)
    change(arrays)
    g = zarr.open_group(str(merged), mode="r+")
    integ = dict(g.attrs["integrity"])
    chunks = {k: list(v) for k, v in integ["chunks"].items()}
    for k in store.VARS:
        g[k][i] = arrays[k]
        chunks[k][i] = store.chunk_digest(np.ascontiguousarray(arrays[k], dtype=store.FILL[k].dtype))
    integ["chunks"] = chunks
    integ["overall"] = store.overall_digest(chunks, integ["coords"])
    g.attrs["integrity"] = integ


def _rows_from_store(b: Path, model: str, design: int) -> None:
    """A design's metrics row re-made from its (edited) arrays, as its rule makes it."""
    path = b / model / "metrics.csv"
    th = metrics.Thresholds(**provenance.read_record(path.with_suffix(".provenance.json"))["config"]["thresholds"])
    ds = store.open_merged(b / model / "merged.zarr")
    one = store.read_design(ds, [int(d) for d in ds["design"].values].index(design))
    dm = metrics.design_metrics(metrics.success(one["first_time"], one["min_dist"], th), one["status"])
    t = pd.read_csv(path)
    row = t.design == design
    for col, v in [
        *((f"n_{a}", n) for a, n in zip(ENV_ANGLES_DEG, dm.per_env, strict=True)),
        ("generalists", dm.generalists),
        ("at_least_one", dm.at_least_one),
        ("flagged", dm.flagged),
        *((name, float(metrics.CSV_FLOAT_FORMAT % getattr(dm, name))) for name in metrics.METRICS),
    ]:
        t.loc[row, col] = v
    t.to_csv(path, index=False, float_format=metrics.CSV_FLOAT_FORMAT)
    _resummarise(b)


def _nan_cells(k: int, transposed: bool = False) -> Callable[[dict[str, np.ndarray]], None]:
    def change(a: dict[str, np.ndarray]) -> None:
        ok = np.isfinite(a["first_time"]).all(axis=0)  # the generalist cells
        cells = np.argwhere(ok)[:k]
        for w1, w2 in cells:
            a["first_time"][:, w1, w2] = np.nan

    return change


@pytest.mark.bundles("ode-screened-paper")
@pytest.mark.parametrize("design,k", [(6402, 10), (478, 10), (6402, 1), (720, 3), (6480, 2)])
def test_a_derived_mirror_that_is_no_mirror_is_named(proj: Path, design: int, k: int) -> None:
    """The issue's attack (first_time NaN at generalist cells of one design of a mirror pair,
    its row re-made from its arrays, everything re-sealed) and other pairs and cell counts."""
    b = proj / "results" / "ode-screened-paper"
    _edit_store(b / "ode" / "merged.zarr", design, _nan_cells(k))
    _rows_from_store(b, "ode", design)
    _reseal(b)
    problems = bundle_check.check(b)
    assert any("not exact mirror images of each other" in p and str(design) in p for p in problems), problems


@pytest.mark.bundles("ode-paper")
def test_a_store_that_derives_no_mirrors_is_not_held_to_them(proj: Path) -> None:
    """results/ode-paper simulates every design (no mirror_derive): an edit consistent with its
    rows passes the mirror check (what re-simulation is for)."""
    b = proj / "results" / "ode-paper"
    _edit_store(b / "ode" / "merged.zarr", 6552, _nan_cells(1))
    _rows_from_store(b, "ode", 6552)
    _reseal(b)
    assert not any("mirror" in p for p in bundle_check.check(b))


# -- A3: summaries are what their tables give ---------------------------------------------------


def _set(path: list[str], value: object) -> Callable[[dict], None]:
    def change(d: dict) -> None:
        for k in path[:-1]:
            d = d[k]
        d[path[-1]] = value

    return change


SUMMARY_ATTACKS = [
    ("reduced-maps", ["reduced", "canonical"], None),
    ("reduced-maps", ["reduced", "top_M_L"], []),
    ("reduced-maps", ["reduced", "top_M_CF"], []),
    ("reduced-maps", ["reduced", "M_CF_eq_1"], 5),
    ("reduced-maps", ["reduced", "controllers"], 1),
    ("reduced-maps", ["theory", "designs"], 1),
    (
        "reduced-maps",
        [
            "weights",
        ],
        11,
    ),
    ("ode-paper", ["ode", "canonical", "generalists"], 9999),
    ("ode-paper", ["ode", "best_M_L_among_M_CF_eq_1"], 1.0),
    ("ode-paper", ["ode", "canonical", "rank_M_L"], 1),
]


@pytest.mark.parametrize("name,path,value", SUMMARY_ATTACKS)
def test_a_summary_that_its_tables_do_not_give_is_named(proj: Path, name: str, path: list[str], value: object) -> None:
    b = proj / "results" / name
    s = json.loads((b / "summary.json").read_text())
    _set(path, value)(s)
    (b / "summary.json").write_text(json.dumps(s, indent=1, sort_keys=True) + "\n")
    _reseal(b)
    rc, out = _run("check-bundle", str(b))
    assert rc == 1 and "summary.json: " in out and "is not what the bundle's metrics tables give" in out, out


@pytest.mark.parametrize("name", ["reduced-maps", "ode-paper"])
def test_a_summary_markdown_edit_is_named(proj: Path, name: str) -> None:
    b = proj / "results" / name
    md = b / "summary.md"
    md.write_text(md.read_text().replace("Canonical design: rank", "Canonical design: rank 1,", 1))
    _reseal(b)
    problems = bundle_check.check(b)
    assert any(p.startswith(f"{md}: is not what") for p in problems), problems


# -- A4: the commits in the order that made the bundle -------------------------------------------


@pytest.mark.bundles("ode-paper")
@pytest.mark.parametrize(
    "change,want",
    [
        (lambda m: m["made_by"].update(git_commit=ROOT_COMMIT), "is older than commit"),
        # the commit before the one that simulated its designs
        (lambda m: m["made_by"].update(git_commit=_parent("f3d8ca132b7395b87188626c3edee3aec912b05f")), "older"),
        (
            lambda m: m.update(
                rendered_by={
                    "git_commit": ROOT_COMMIT,
                    "command": "snakemake --cores 2 --configfile config/ode_paper.yaml --config render_only=True "
                    "results_dir=results/ode-paper --forceall",
                    "files": [],
                }
            ),
            "is older than made_by.git_commit",
        ),
    ],
)
def test_a_commit_older_than_what_made_the_bundle_is_refused(proj: Path, change: Callable, want: str) -> None:
    b = proj / "results" / "ode-paper"
    m = _manifest(b)
    change(m)
    _write_manifest(b, m)
    notes: list[str] = []
    problems = bundle_check.check(b, notes=notes)
    assert any(want in p for p in problems), problems
    assert not any("not in this clone" in n for n in notes), notes


def _parent(c: str) -> str:
    import subprocess

    return subprocess.run(["git", "rev-parse", f"{c}^"], cwd=ROOT, capture_output=True, text=True).stdout.strip()


@pytest.mark.bundles("ode-paper")
def test_a_commit_that_lacks_its_config_is_refused(proj: Path) -> None:
    """Its commit (the one that simulated its designs) names a config added after it: once read
    from the working tree with a note, now refused."""
    b = proj / "results" / "ode-paper"
    m = _manifest(b)
    m["made_by"]["configs"] = ["config/reduced_paper.yaml", "config.yaml"]
    m["made_by"]["command"] = bundle.command_of(m["made_by"]["configs"])
    _write_manifest(b, m)
    problems = bundle_check.check(b)
    assert any("does not hold its config file config/reduced_paper.yaml" in p for p in problems), problems


# -- D13, D14: every manifest field typed before use ---------------------------------------------

SHAPE_ATTACKS: list[tuple[str, Callable[[dict], None], str]] = [
    ("made_by.git_commit list", lambda m: m["made_by"].update(git_commit=["a", "b"]), "made_by.git_commit is a list"),
    ("made_by.git_commit dict", lambda m: m["made_by"].update(git_commit={"a": 1}), "made_by.git_commit is an object"),
    ("made_by.git_commit int", lambda m: m["made_by"].update(git_commit=7), "made_by.git_commit is an integer"),
    ("made_by.git_commit null", lambda m: m["made_by"].update(git_commit=None), "made_by.git_commit is null"),
    ("rendered_by.git_commit dict", lambda m: m.update(rendered_by={"git_commit": {}}), "rendered_by.git_commit is"),
    ("rendered_by list", lambda m: m.update(rendered_by=[1]), "rendered_by is a list"),
    ("rendered_by.files str", lambda m: m.update(rendered_by={"files": "abc"}), "rendered_by.files is a string"),
    ("rendered_by.command int", lambda m: m.update(rendered_by={"command": 1}), "rendered_by.command is an integer"),
    ("subsets.X list", lambda m: m["subsets"].update(ode=[]), "subsets.ode is a list"),
    ("subsets.X str", lambda m: m["subsets"].update(ode="x"), "subsets.ode is a string"),
    ("subsets.X null", lambda m: m["subsets"].update(ode=None), "subsets.ode is null"),
    ("subsets list", lambda m: m.update(subsets=[]), "subsets is a list"),
    ("subsets.designs str", lambda m: m["subsets"]["ode"].update(designs="1,2"), "subsets.ode.designs is a string"),
    ("subsets.designs floats", lambda m: m["subsets"]["ode"].update(designs=[1.5]), "subsets.ode.designs is a list"),
    ("subsets.designs bools", lambda m: m["subsets"]["ode"].update(designs=[True]), "subsets.ode.designs is a list"),
    ("subsets.of str", lambda m: m["subsets"]["ode"].update(of="10"), "subsets.ode.of is a string"),
    ("subsets.of negative", lambda m: m["subsets"]["ode"].update(of=-1), "subsets.ode.of is an integer"),
    ("subsets.simulated_by list", lambda m: m["subsets"]["ode"].update(simulated_by=[]), "simulated_by is a list"),
    (
        "subsets.simulated_by commits list",
        lambda m: m["subsets"]["ode"]["simulated_by"].update(git_commits=["x"]),
        "subsets.ode.simulated_by is an object",
    ),
    (
        "subsets.simulated_by counts str",
        lambda m: m["subsets"]["ode"]["simulated_by"].update(backends={"ode": "10"}),
        "subsets.ode.simulated_by is an object",
    ),
    ("made_by.configs str", lambda m: m["made_by"].update(configs="config/ode_paper.yaml"), "made_by.configs is a"),
    ("made_by.configs dict", lambda m: m["made_by"].update(configs={"a": 1}), "made_by.configs is an object"),
    ("made_by.configs ints", lambda m: m["made_by"].update(configs=[1, 2]), "made_by.configs is a list"),
    ("made_by.command list", lambda m: m["made_by"].update(command=["snakemake"]), "made_by.command is a list"),
    ("made_by.results_dir int", lambda m: m["made_by"].update(results_dir=3), "made_by.results_dir is an integer"),
    ("made_by.version list", lambda m: m["made_by"].update(version=[0]), "made_by.version is a list"),
    ("made_by.libraries list", lambda m: m["made_by"].update(libraries=[]), "made_by.libraries is a list"),
    ("made_by list", lambda m: m.update(made_by=[]), "made_by is a list"),
    ("simulated_by list", lambda m: m.update(simulated_by=[]), "simulated_by is a list"),
    ("simulated_by.X str", lambda m: m.update(simulated_by={"a": "b"}), "simulated_by.a is a string"),
    ("scenarios dict", lambda m: m.update(scenarios={}), "scenarios is an object"),
]


@pytest.mark.bundles("ode-paper")
@pytest.mark.parametrize("name,change,want", SHAPE_ATTACKS, ids=[a[0] for a in SHAPE_ATTACKS])
def test_every_manifest_field_is_typed_before_use(
    proj: Path, name: str, change: Callable[[dict], None], want: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    """check-bundle, render, rerender-bundle and the explorer each say the field and its type in
    one line (once: TypeError in check._commits, "TypeError in file workflow/rules/common.smk"
    from the render's start check, ``--configfile c o n f i g`` from a string)."""
    b = proj / "results" / "ode-paper"
    m = _manifest(b)
    change(m)
    _write_manifest(b, m)
    rc, out = _run("check-bundle", str(b))
    assert rc == 1 and want in out and "allowed:" in out, out
    monkeypatch.chdir(proj)
    monkeypatch.setattr(bundle_render, "_render", lambda *a: pytest.fail("the render started"))
    with pytest.raises(bundle.BundleError, match="allowed"):
        bundle_render.rerender("results/ode-paper", proj)
    rc, out = _run("rerender-bundle", "results/ode-paper")
    assert rc == 1 and want in out, out
    with pytest.raises(bundle.BundleError, match="problem"):
        explore.open_source(explore.Source(b, "ode"))


@pytest.mark.bundles("paper")
@pytest.mark.parametrize("configs", ["config/paper.yaml", ["--forceall", "config.yaml"], ["/etc/x.yaml"]])
def test_render_never_passes_a_bad_configs_record_to_snakemake(
    proj: Path, configs: object, monkeypatch: pytest.MonkeyPatch
) -> None:
    b = proj / "results" / "paper"
    m = _manifest(b)
    m["made_by"]["configs"] = configs
    _write_manifest(b, m)
    monkeypatch.chdir(proj)
    monkeypatch.setattr(bundle_render, "_render", lambda *a: pytest.fail("the render started"))
    rc, out = _run("render", "results/paper")
    assert rc in (1, 2) and "made_by.configs" in out and "c o n f" not in out, out


# -- D17: unlisted files named whatever their names ----------------------------------------------


@pytest.mark.bundles("paper")
@pytest.mark.parametrize(
    "rel", ["figures/fig6.html", "logs/figures/fig6.ipynb", "logs/figures/fig6.log", "benchmarks/reproduction.tsv"]
)
def test_unlisted_files_at_rendered_names_are_named(proj: Path, rel: str) -> None:
    b = proj / "results" / "paper"
    (b / rel).parent.mkdir(parents=True, exist_ok=True)
    (b / rel).write_text("<html>forged</html>\n")
    _, out = _run("check-bundle", str(b))
    assert "not listed in bundle.json" in out and repr(rel) in out, out
