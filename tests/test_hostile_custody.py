"""Issue 24, parts 1-3 attacked: the chain of custody from the simulation to the figure, nothing
good destroyed, and a forger who has to re-simulate. Each attack is one parameter; an attack is
"refused cleanly" when it stops with the documented exit code, names the file and writes nothing.

The workflow attacks run on a private copy of the shared smoke run (refused runs stop while the
workflow is parsed: about three seconds each); the bundle attacks on copies of a bundle of that
run and of the committed paper bundle."""

from __future__ import annotations

import contextlib
import io
import json
import os
import shutil
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

import pandas as pd
import pytest
from conftest import ROOT, TEST_COMMIT, copy_paper_sources, snakemake

from morphlearn import config as config_mod
from morphlearn import configure, metrics, provenance, store
from morphlearn import settings as settings_mod
from morphlearn.apps import cli
from morphlearn.bundles import check as bundle_check
from morphlearn.bundles import make as bundle
from morphlearn.bundles import resimulate
from morphlearn.figures import caption, data
from morphlearn.grid import ENV_ANGLES_DEG
from morphlearn.workflow import rules

SMOKE = ("--configfile", "config/smoke.yaml")
COORDS = ["l1x", "l1y", "l2x", "l2y"]
PAPER = ROOT / "results" / "paper"


def _refusal(proc: subprocess.CompletedProcess) -> str:
    """The run's own message: its first line from morphlearn (Snakemake's notices come first)."""
    return next((ln for ln in proc.stderr.splitlines() if ln.startswith("morphlearn: ")), proc.stderr[-2000:])


def _snapshot(root: Path) -> dict[str, tuple[int, bytes]]:
    """Every file under ``root`` (but Snakemake's own records): mtime and bytes."""
    return {
        str(p.relative_to(root)): (p.stat().st_mtime_ns, p.read_bytes())
        for p in sorted(root.rglob("*"))
        if p.is_file() and ".snakemake" not in p.parts
    }


@pytest.fixture(scope="module")
def run(smoke_run: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A private copy of the smoke run (its .snakemake records too), and a bundle of it."""
    wd = tmp_path_factory.mktemp("hostile") / "wd"
    shutil.copytree(smoke_run, wd, symlinks=True, ignore=shutil.ignore_patterns("bundle", "report.html"))
    made = bundle.made_by(["config/smoke.yaml", "config.yaml"], "results")
    bundle.build(wd / "results", wd / "smoke-bundle", top=3, made_by=made)
    return wd


def _csv_edit(path: Path, design: int | None = None, **values: float) -> int:
    """Change one row of a metrics table (the first, or ``design``); the design edited."""
    t = pd.read_csv(path)
    d = int(t.design.iloc[0] if design is None else design)
    for k, v in values.items():
        t.loc[t.design == d, k] = v
    t.to_csv(path, index=False, float_format=metrics.CSV_FLOAT_FORMAT)
    return d


def _json_edit(path: Path, change: Callable[[dict], None]) -> None:
    rec = json.loads(path.read_text())
    change(rec)
    path.write_text(json.dumps(rec, indent=1, sort_keys=True) + "\n")


def _reseal_manifest(b: Path, *rels: str) -> None:
    """What a forger does after editing files of a bundle: put their new SHA-256 in bundle.json."""
    _json_edit(b / bundle.MANIFEST, lambda m: m["files"].update({r: provenance.sha256_file(b / r) for r in rels}))


# One example of each class runs the workflow end to end (one Snakemake start each, about 5 CPU
# seconds); the other examples and the variants call in process what the workflow calls at its
# start (rules.check_custody, rules.check_render_inputs, bundle.check_target): milliseconds.

# -- 1. custody in a run: an edited table or record stops the rerun before anything runs ------


def _edit_generalists(r: Path) -> str:
    """The issue's example: a design's generalists turned into M_L = 1."""
    _csv_edit(r / "theory/metrics.csv", generalists=25, M_L=1.0, M_CF=1.0)
    return "theory/metrics.csv: SHA-256"


def _fake_commit(r: Path) -> str:
    """The issue's example: a fake commit in the record the captions quote."""
    _json_edit(r / "theory/metrics.provenance.json", lambda p: p.update(git_commit="0" * 40))
    return "metrics.provenance.json: edited or damaged"


def _fake_store_hash(r: Path) -> str:
    def change(p: dict) -> None:
        p["config"]["merged_sha256_overall"] = "f" * 64
        p["inputs"] = {k: "f" * 64 for k in p["inputs"]}

    _json_edit(r / "empirical/metrics.provenance.json", change)
    return "empirical/metrics.provenance.json: edited or damaged"


def _reseal_outputs_only(r: Path) -> str:
    """A forger edits the table and writes its new digest into the record (not the seal)."""
    t = r / "theory/metrics.csv"
    _csv_edit(t, generalists=7)
    _json_edit(r / "theory/metrics.provenance.json", lambda p: p["outputs"].update({t.name: provenance.sha256_file(t)}))
    return "metrics.provenance.json: edited or damaged"


def _reseal_everything(r: Path) -> str:
    """A forger who re-seals the record too: the table no longer matches the store it names."""
    t = r / "theory/metrics.csv"
    _csv_edit(t, generalists=7)
    side = r / "theory/metrics.provenance.json"
    rec = json.loads(side.read_text())
    rec["config"]["merged_sha256_overall"] = "e" * 64
    provenance.write_sealed(side, rec, [t])
    return "computed from the merged store eeeeeeeeeeee"


def _record_removed(r: Path) -> str:
    (r / "theory/metrics.provenance.json").unlink()
    return "theory/metrics.csv: no provenance record"


def _unsealed_record(r: Path) -> str:
    _json_edit(r / "theory/metrics.provenance.json", lambda p: [p.pop(k) for k in ("outputs", provenance.SEAL)])
    return "records no digest of metrics.csv"


def _summary_edited(r: Path) -> str:
    """A sentence added to the summary (summary.json untouched)."""
    md = r / "summary.md"
    md.write_text(md.read_text() + "\nThe canonical design is the best of all.\n")
    return "summary.md: SHA-256"


def _reproduction_edited(r: Path) -> str:
    (r / "reproduction.csv").write_text((r / "reproduction.csv").read_text() + "forged,row\n")
    return "reproduction.csv: SHA-256"


@pytest.mark.parametrize(
    ("attack", "end_to_end"),
    [
        (_edit_generalists, True),
        (_fake_commit, False),
        (_fake_store_hash, False),
        (_reseal_outputs_only, False),
        (_record_removed, False),
        (_unsealed_record, False),
        (_summary_edited, False),
        (_reproduction_edited, False),
    ],
)
def test_rerun_refuses_edited_results(run: Path, attack: Callable[[Path], str], end_to_end: bool) -> None:
    r = run / "results"
    keep = {p: p.read_bytes() for p in [*r.glob("*/metrics*"), *r.glob("summary.*"), *r.glob("reproduction.*")]}
    try:
        want = attack(r)
        before = _snapshot(r)
        if end_to_end:
            proc = snakemake(run, "--cores", "1", *SMOKE, check=False)
            assert proc.returncode == 2, proc.stderr[-2000:]
            first = _refusal(proc)
            assert want in first and "nothing was run" in first, first
        else:
            with pytest.raises(provenance.CustodyError) as err:
                rules.check_custody(
                    [r / m / "metrics.csv" for m in ("theory", "empirical")],
                    [r / "summary.json", r / "reproduction.csv"],
                )
            assert want in str(err.value), err.value
        assert _snapshot(r) == before  # nothing written, nothing deleted
    finally:
        for p, b in keep.items():
            p.write_bytes(b)


def test_a_resealed_record_must_name_the_store_read_beside_it(run: Path) -> None:
    """A forger who re-seals the record after editing the table passes the start check (the
    record is whole), but the figures and the table read the table beside its store, and the
    store's digest is not the one the record names."""
    r = run / "results"
    keep = {p: p.read_bytes() for p in r.glob("theory/metrics*")}
    try:
        want = _reseal_everything(r)
        with pytest.raises(provenance.CustodyError, match=want):
            data.require_results(r, "theory")
    finally:
        for p, b in keep.items():
            p.write_bytes(b)


def test_caption_refuses_an_edited_record(run: Path) -> None:
    """Where the record is quoted (a caption's data paragraph), its seal is checked first."""
    r = run / "results"
    res = data.require_results(r, "theory")
    assert f"git commit {TEST_COMMIT}" in caption.provenance_md([res])
    side = r / "theory/metrics.provenance.json"
    keep = side.read_bytes()
    try:
        _fake_commit(r)
        with pytest.raises(provenance.CustodyError, match="edited or damaged"):
            caption.provenance_md([res])
    finally:
        side.write_bytes(keep)


# -- 1. render-only verifies the bundle first --------------------------------------------------


def _row_changed(b: Path) -> str:
    """The issue's example: one metrics row of a bundle changed."""
    _csv_edit(b / "theory/metrics.csv", generalists=7)
    return "theory/metrics.csv: checksum differs from bundle.json"


def _chunk_flipped(b: Path) -> str:
    """The issue's example: a flipped byte in a chunk no figure draws."""
    held = json.loads((b / bundle.MANIFEST).read_text())["subsets"]["theory"]["designs"]
    chunk = b / f"theory/merged.zarr/min_dist/c/{len(held) - 1}/0/0/0"
    raw = bytearray(chunk.read_bytes())
    raw[len(raw) // 2] ^= 0x01
    chunk.write_bytes(bytes(raw))
    return f"merged.zarr/min_dist/c/{len(held) - 1}/0/0/0: checksum differs"


def _forged_manifest(b: Path) -> str:
    """The issue's forger: edits a row, then its SHA-256 in bundle.json (generalists 740)."""
    _csv_edit(b / "theory/metrics.csv", generalists=740)
    _reseal_manifest(b, "theory/metrics.csv")
    return "generalists above an environment's count"


def _stray_log(b: Path) -> str:
    (b / "logs").mkdir(exist_ok=True)
    (b / "logs/notes.txt").write_text("not made by a render\n")
    return "logs/notes.txt: not listed in bundle.json"


def _provenance_edited_in_bundle(b: Path) -> str:
    _json_edit(b / "theory/metrics.provenance.json", lambda p: p.update(git_commit="0" * 40))
    return "metrics.provenance.json: checksum differs"


def _manifest_unreadable(b: Path) -> str:
    (b / bundle.MANIFEST).write_text('{"files": ')
    return "bundle.json: unreadable"


@pytest.mark.parametrize(
    ("attack", "end_to_end"),
    [
        (_row_changed, True),
        (_chunk_flipped, False),
        (_forged_manifest, False),
        (_stray_log, False),
        (_provenance_edited_in_bundle, False),
        (_manifest_unreadable, False),
    ],
)
def test_render_only_refuses_a_damaged_bundle(run: Path, attack: Callable[[Path], str], end_to_end: bool) -> None:
    b = run / "results" / "attacked"
    shutil.rmtree(b, ignore_errors=True)
    shutil.copytree(run / "smoke-bundle", b)
    want = attack(b)
    before = _snapshot(b)
    if end_to_end:
        proc = snakemake(
            run, "--cores", "1", *SMOKE, "--config", "render_only=True", "results_dir=results/attacked", check=False
        )
        assert proc.returncode == 2, proc.stderr[-2000:]
        first = _refusal(proc)
        assert first.startswith("morphlearn: render_only: ") and "nothing was rendered" in first, first
        assert want in proc.stderr, proc.stderr[-2000:]
    else:
        with pytest.raises(ValueError) as err:
            rules.check_render_inputs(
                [f"{b}/{m}/{n}" for m in ("theory", "empirical") for n in ("metrics.csv", "merged.zarr")]
            )
        assert want in str(err.value), err.value
    assert _snapshot(b) == before  # no figure, log or benchmark written


def test_render_only_reads_the_stored_persistence_table_only_when_its_record_vouches_for_it(
    run: Path, tmp_path: Path
) -> None:
    """render_only reads persistence.csv instead of integrating it again: an edited table, or one
    without its sealed record, is refused by name."""
    for name in ("persistence.csv", "reproduction.provenance.json"):
        shutil.copy2(run / "results" / name, tmp_path / name)
    table = tmp_path / "persistence.csv"
    rules.check_stored_persistence(table)  # intact: read as it is
    lines = table.read_text().splitlines(keepends=True)
    table.write_text("".join(lines[:-1]))  # one controller's row dropped
    with pytest.raises(ValueError, match=r"persistence\.csv: SHA-256 .* differs from the .* that reproduction"):
        rules.check_stored_persistence(table)
    (tmp_path / "reproduction.provenance.json").unlink()
    with pytest.raises(ValueError, match=r"no provenance record reproduction\.provenance\.json beside it"):
        rules.check_stored_persistence(table)


# -- 2. bundle_dir writes only where it may ----------------------------------------------------


def _docs(wd: Path) -> str:
    return "docs"


def _readme(wd: Path) -> str:
    (wd / "README.md").write_text("# the project's readme\n")
    return "README.md"


def _committed_paper(wd: Path) -> str:
    (wd / "results/paper").mkdir(exist_ok=True)
    shutil.copy2(PAPER / bundle.MANIFEST, wd / "results/paper" / bundle.MANIFEST)
    (wd / "results/paper/README.md").write_text("committed\n")
    return "results/paper"


def _project_root(wd: Path) -> str:
    return "."


def _results_folder(wd: Path) -> str:
    return "results"


def _link_to_docs(wd: Path) -> str:
    (wd / "docs-link").unlink(missing_ok=True)
    os.symlink("docs", wd / "docs-link")
    return "docs-link"


@pytest.mark.parametrize(
    ("target", "end_to_end"),
    [
        (_docs, True),
        (_readme, False),
        (_committed_paper, True),
        (_project_root, False),
        (_results_folder, False),
        (_link_to_docs, False),
    ],
)
def test_bundle_dir_refuses_what_it_did_not_make(
    run: Path, target: Callable[[Path], str], end_to_end: bool, monkeypatch: pytest.MonkeyPatch
) -> None:
    (run / "docs").mkdir(exist_ok=True)
    (run / "docs/index.md").write_text("documentation\n")
    name = target(run)
    before = _snapshot(run / "docs") | _snapshot(run / "results")
    if end_to_end:
        proc = snakemake(run, "bundle", "--cores", "1", *SMOKE, "--config", f"bundle_dir={name}", check=False)
        assert proc.returncode == 2, proc.stderr[-2000:]
        first = _refusal(proc).removeprefix("morphlearn: ")
    else:
        monkeypatch.chdir(run)
        with pytest.raises(bundle.BundleError) as err:
            bundle.check_target(name, bundle.made_by(["config/smoke.yaml", "config.yaml"], "results"))
        first = str(err.value)
    assert first.startswith(f"bundle_dir = '{name}' ") and "nothing was written" in first, first
    assert not any(w in first.lower() for w in ("delete", "remove", "rm ")), first
    assert _snapshot(run / "docs") | _snapshot(run / "results") == before


def test_config_slip_cannot_overwrite_the_paper_bundle(run: Path) -> None:
    """``--configfile config/paper.yaml config/smoke.yaml`` names bundle_dir results/paper. Since
    config/paper.yaml reads its theory from results/theory-paper, the first guard the slip meets is
    that read's (the smoke grid is not the bundle's); the bundle_dir guard behind it:
    test_bundle_dir_refuses_what_it_did_not_make."""
    # the paper bundle and the bundles config/paper.yaml reads, as a clone holds them
    copy_paper_sources(run)
    shutil.copytree(PAPER, run / "results/paper", dirs_exist_ok=True)
    before = _snapshot(run / "results/paper")
    proc = snakemake(
        run, "bundle", "-n", "--cores", "1", "--configfile", "config/paper.yaml", "config/smoke.yaml", check=False
    )
    assert proc.returncode == 2, proc.stderr[-2000:]
    assert (
        "theory.results_from = 'results/theory-paper' holds theory results made with grid.positions_per_axis = 9, "
        "this config has 3" in proc.stderr
    ), proc.stderr[-2000:]
    assert _snapshot(run / "results/paper") == before


def test_bundle_dir_allows_an_absent_folder_and_its_own_bundle(run: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    # (also the positive control of the start-up custody check: the untouched run passes it; an
    # intact bundle passing render-only's check: tests/test_bundle.py renders one)
    proc = snakemake(run, "bundle", "-n", "--cores", "1", *SMOKE, "--config", "bundle_dir=results/new-bundle")
    assert "morphlearn:" not in proc.stderr and "rule bundle" in proc.stdout + proc.stderr
    own = run / "results" / "own"
    shutil.copytree(run / "smoke-bundle", own, dirs_exist_ok=True)
    monkeypatch.chdir(run)
    bundle.check_target("results/own", bundle.made_by(["config/smoke.yaml", "config.yaml"], "results"))
    (run / "results/empty").mkdir(exist_ok=True)
    bundle.check_target("results/empty", bundle.made_by(["config/smoke.yaml", "config.yaml"], "results"))


# -- 2. a failed rerun keeps the previous valid outputs ----------------------------------------


def test_failed_reruns_keep_previous_outputs(run: Path) -> None:
    """A damaged chunk makes the metrics rerun and the re-render of Fig. 6 fail (they verify
    every chunk they read): the previous table, its record and the figure stay, byte for byte."""
    r = run / "results"
    keep = ["theory/metrics.csv", "theory/metrics.provenance.json", "figures/fig6.png", "figures/fig6.caption.md"]
    before = {k: (r / k).read_bytes() for k in keep}
    chunks = sorted((r / "theory/merged.zarr/first_time/c").rglob("0"))
    saved = {p: p.read_bytes() for p in chunks if p.is_file()}
    try:
        for p, b in saved.items():  # every design's chunk, so the canonical one Fig. 6 draws too
            raw = bytearray(b)
            raw[len(raw) // 2] ^= 0x01
            p.write_bytes(bytes(raw))
        # the figure first: its inputs stay older than it, so only it re-runs (forced); then the metrics
        for rule in ("figure_fig6", "metrics"):
            proc = snakemake(run, "--cores", "1", *SMOKE, "--forcerun", rule, check=False)
            out = proc.stdout + proc.stderr
            assert proc.returncode == 1 and f"Error in rule {rule}" in out, out[-3000:]
            assert "Restored previous version" in out
            assert {k: (r / k).read_bytes() for k in keep} == before, rule
    finally:
        for p, b in saved.items():
            p.write_bytes(b)


# -- 1-2 in the other stages: learners, co-optimisation, scenarios -----------------------------

#: Every rule of these configs (stages on: learners, coopt, MuJoCo, a bundle; the scenarios; a
#: physics model read from a bundle) has only update() outputs: a failed or refused rerun keeps
#: the previous ones (the sweep's is shown end to end above). One process parses all three.
_STAGE_CONFIGS = {
    "stages.yaml": {
        "learners": {"enabled": True, "max_designs": 3, "shards": 2},
        "coopt": {"enabled": True},
        "mujoco": {"enabled": True, "results_from": None, "weights": 2, "designs": [[[0.5, 0.5], [0.5, -0.5]]]},
        "bundle_dir": "results/b",
    },
    "scen.yaml": {"scenario_file": "config/scenarios.yaml", "scenarios": "all"},
    "from_bundle.yaml": {"results_dir": "results/fresh", "empirical": {"results_from": "results/survey"}},
}
_FLAGS = """
import json, sys
from pathlib import Path
from snakemake.api import SnakemakeApi
from snakemake.io import is_flagged
from snakemake.settings.types import ConfigSettings, OutputSettings, ResourceSettings
out = {}
for files in json.loads(sys.argv[1]):
    with SnakemakeApi(OutputSettings(quiet={"all"})) as api:
        cs = ConfigSettings(configfiles=[Path(f) for f in files])
        wf = api.workflow(resource_settings=ResourceSettings(), config_settings=cs, snakefile=Path("Snakefile"))
        for r in wf._workflow.rules:
            out[r.name] = [str(f) for f in r.output if not is_flagged(f, "update")]
print(json.dumps(out))
"""


def test_every_rule_of_every_stage_keeps_its_previous_outputs(run: Path) -> None:
    for name, cfg in _STAGE_CONFIGS.items():
        (run / name).write_text(json.dumps(cfg))
    sets = [["config/smoke.yaml", "stages.yaml"], ["config/smoke.yaml", "scen.yaml"], ["from_bundle.yaml"]]
    proc = subprocess.run(
        [str(Path(sys.executable)), "-c", _FLAGS, json.dumps(sets)],
        cwd=run,
        capture_output=True,
        text=True,
        timeout=600,
        env={**os.environ, "MORPHLEARN_GIT_COMMIT": TEST_COMMIT},
    )
    assert proc.returncode == 0, proc.stderr[-3000:]
    rules_seen = json.loads(proc.stdout.splitlines()[-1])
    stages = {"learners_shard", "learners_analysis", "coopt_landscape", "coopt_runs", "coopt_analysis"}
    stages |= {"scenario_shard", "scenario_merge", "scenario_metrics", "scenario_summary", "scenario_compare"}
    stages |= {"scenario_report", "mujoco_shard", "empirical_from_bundle", "bundle", "optimise_morphology"}
    assert stages <= set(rules_seen), sorted(stages - set(rules_seen))
    assert {r: o for r, o in rules_seen.items() if o} == {}


def _edited_table(run: Path, tmp_path: Path) -> Path:
    """A sealed theory table of the smoke run (and its record), copied, with one row edited."""
    t = tmp_path / "edited" / "theory" / "metrics.csv"
    t.parent.mkdir(parents=True)
    for name in ("metrics.csv", "metrics.provenance.json"):
        shutil.copy2(run / "results/theory" / name, t.parent / name)
    provenance.check_derived(t)  # as written, it passes
    _csv_edit(t, generalists=1)
    return t


def _stage_settings(run: Path, **over: dict) -> settings_mod.Settings:
    cfg = config_mod.deep_merge(config_mod.read(run / "config.yaml"), config_mod.read(run / "config/smoke.yaml"))
    cwd = Path.cwd()
    os.chdir(run)  # the body file is named relative to the project root
    try:
        return configure.parse(config_mod.deep_merge(cfg, over))
    finally:
        os.chdir(cwd)


def _learners(run: Path, table: Path, out: Path) -> None:
    from morphlearn.learners import experiment

    s = _stage_settings(run, learners={"enabled": True, "max_designs": 3, "shards": 1})
    experiment.run_analysis(s, [], str(table), out / "runs.csv", out / "corr.csv", out / "s.md", out / "c.json")


def _coopt(run: Path, table: Path, out: Path) -> None:
    from morphlearn.coopt import stage

    s = _stage_settings(run, coopt={"enabled": True, "best_metrics": str(table)})
    stage.run_analysis(s, [], [], out)


def _coopt_landscape(run: Path, table: Path, out: Path) -> None:
    from morphlearn.coopt import stage

    s = _stage_settings(run, coopt={"enabled": True, "best_metrics": str(table)})
    stage.run_landscape(s, "best_M_L", out / "best_M_L.json")


def _scenarios(run: Path, table: Path, out: Path) -> None:
    from morphlearn import scenarios

    merged = {"0" * 16: str(run / "results/theory/merged.zarr")}
    scenarios.run_compare(
        {"base": str(table)}, merged, 3, out / "c.csv", out / "c.md", out / "t.csv", "", out / "r.json"
    )


@pytest.mark.parametrize("stage", [_learners, _coopt, _coopt_landscape, _scenarios], ids=lambda f: f.__name__)
def test_a_stage_refuses_an_edited_metrics_table_before_reading_it(
    run: Path, tmp_path: Path, stage: Callable[[Path, Path, Path], None]
) -> None:
    """The learner analysis, the co-optimisation's steps that read the best designs and the
    scenario comparison check the metrics table against its sealed record first (they read the
    edit before): CustodyError naming it, nothing written."""
    table = _edited_table(run, tmp_path)
    out = tmp_path / "out"
    out.mkdir()
    with pytest.raises(provenance.CustodyError, match=f"{table}: SHA-256 .* differs"):
        stage(run, table, out)
    assert list(out.iterdir()) == []


# -- 3. check-bundle: a forger has to re-simulate ----------------------------------------------


def _cli(*args: str) -> tuple[int, str]:
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        rc = cli.main(["check-bundle", *args])
    return rc, buf.getvalue()


@pytest.fixture
def paper_copy(tmp_path: Path) -> Path:
    b = tmp_path / "paper"
    shutil.copytree(PAPER, b, ignore=shutil.ignore_patterns("logs", "benchmarks", "*.html", ".snakemake*"))
    for name in ("reproduction.html",):  # listed in the manifest, so copied back
        shutil.copy2(PAPER / name, b / name)
    return b


def _generalists_740(b: Path) -> str:
    """The issue's example: generalists 740 beside M_L = 240/14641, the manifest updated."""
    t = pd.read_csv(b / "theory/metrics.csv")
    d = int(t.design[t.generalists == 240].iloc[0])
    _csv_edit(b / "theory/metrics.csv", d, generalists=740)
    _reseal_manifest(b, "theory/metrics.csv")
    return f"design {d}"


def _m_cf_forged(b: Path) -> str:
    _csv_edit(b / "theory/metrics.csv", 5, M_CF=0.5)
    _reseal_manifest(b, "theory/metrics.csv")
    return "M_CF != its value from the counts"


def _at_least_one_below_env(b: Path) -> str:
    t = pd.read_csv(b / "empirical/metrics.csv")
    _csv_edit(b / "empirical/metrics.csv", int(t.design[t.n_45 > 0].iloc[0]), at_least_one=0, M_CF=0.0)
    _reseal_manifest(b, "empirical/metrics.csv")
    return "an environment's count above at_least_one"


def _table_forgery(name: str, change: Callable[[pd.DataFrame], pd.DataFrame], want: str, model: str = "theory"):
    """A forged metrics table whose digests were updated in bundle.json (issue 38, item 3): each
    row consistent in itself, so only the check of what the rows mean against the bundle's grid and
    store finds it."""

    def attack(b: Path) -> str:
        rel = f"{model}/metrics.csv"
        change(pd.read_csv(b / rel)).to_csv(b / rel, index=False, float_format=metrics.CSV_FLOAT_FORMAT)
        _reseal_manifest(b, rel)
        return want

    attack.__name__ = name
    return attack


def _best(t: pd.DataFrame) -> int:
    return int(metrics.rank_designs(t, "M_L").design.iloc[0])


def _set(t: pd.DataFrame, row: int, **values: object) -> pd.DataFrame:
    t = t.copy()
    for k, v in values.items():
        t[k] = t[k].astype(object) if isinstance(v, str) else t[k]
        t.loc[row, k] = v
    return t


TABLE_FORGERIES = [
    _table_forgery("duplicated row", lambda t: pd.concat([t, t.iloc[[7]]]), "design 7 appears more than once"),
    _table_forgery("deleted best row", lambda t: t[t.design != _best(t)], "is missing (a design of this bundle's"),
    _table_forgery("design 99999", lambda t: _set(t, 7, design=99999), "design 99999 is not a design of this bundle"),
    _table_forgery("design -3", lambda t: _set(t, 7, design=-3), "design -3 is not a design of this bundle"),
    _table_forgery("off-grid l1x", lambda t: _set(t, 5, l1x=0.77), "design 5: coordinates are not its grid position's"),
    _table_forgery(
        "swapped coordinates",
        lambda t: _set(t, 5, l1x=t.l2x[5], l1y=t.l2y[5], l2x=t.l1x[5], l2y=t.l1y[5]),
        "design 5: coordinates are not its grid position's",
    ),
    _table_forgery(
        "model rewritten", lambda t: _set(t, 3, model="empirical"), "design 3: model column is not 'theory'"
    ),
    _table_forgery(
        "held row swapped with another",  # the counts of two designs exchanged: each row consistent
        lambda t: t.assign(design=t.design.replace({_best(t): 0, 0: _best(t)})).assign(
            **{c: t.set_index("design").loc[t.design.replace({_best(t): 0, 0: _best(t)}), c].to_numpy() for c in COORDS}
        ),
        "its row's counts differ from the merged store's arrays",
    ),
]


def _store_replaced(b: Path) -> str:
    (b / "theory/merged.zarr/zarr.json").write_text("[]")
    _reseal_manifest(b, "theory/merged.zarr/zarr.json")
    return "the merged store beside it is unreadable"


def _path_outside(b: Path) -> str:
    _json_edit(b / bundle.MANIFEST, lambda m: m["files"].update({"../../etc/hostname": "0" * 64}))
    return "'../../etc/hostname', a path outside the bundle (not read)"


def _absolute_path(b: Path) -> str:
    _json_edit(b / bundle.MANIFEST, lambda m: m["files"].update({"/etc/hostname": "0" * 64}))
    return "'/etc/hostname', a path outside the bundle"


def _link_out(b: Path) -> str:
    os.symlink("/etc/hostname", b / "theory/hostname")
    _json_edit(b / bundle.MANIFEST, lambda m: m["files"].update({"theory/hostname": "0" * 64}))
    return "'theory/hostname', a path outside the bundle"


def _stray(rel: str) -> Callable[[Path], str]:
    def attack(b: Path) -> str:
        (b / rel).parent.mkdir(parents=True, exist_ok=True)
        (b / rel).write_text("stray\n")
        return f"{rel}: not listed in bundle.json"

    attack.__name__ = f"stray {rel}"
    return attack


def _shape(text: str | bytes) -> Callable[[Path], str]:
    def attack(b: Path) -> str:
        m = b / bundle.MANIFEST
        m.write_bytes(text if isinstance(text, bytes) else text.encode())
        return "bundle.json: "

    attack.__name__ = f"manifest {text!r:.20}"
    return attack


@pytest.mark.parametrize(
    "attack",
    [
        _generalists_740,
        _m_cf_forged,
        _at_least_one_below_env,
        _path_outside,
        _absolute_path,
        _link_out,
        *(
            _stray(r)
            for r in ("logs/x.log", "benchmarks/x.tsv", ".snakemake_x", "figures/fig9.html", "figures/evil.html")
        ),
        *(_shape(t) for t in ("[]", '{"files": []}', '{"files": {"summary.md": 1}}', "null", b"\xff\xfe\x00")),
        *TABLE_FORGERIES,
        _store_replaced,
    ],
    ids=lambda f: f.__name__,
)
def test_check_bundle_refuses(paper_copy: Path, attack: Callable[[Path], str]) -> None:
    want = attack(paper_copy)
    rc, out = _cli(str(paper_copy))
    assert rc == 1 and want in out, out
    assert "Traceback" not in out


def test_check_bundle_accepts_the_committed_bundles() -> None:
    for name in ("paper", "survey", "scenario-set"):
        assert bundle_check.check(ROOT / "results" / name) == [], name


def test_a_consistent_forgery_of_a_row_not_held_needs_resimulation(run: Path, tmp_path: Path) -> None:
    """Edited counts that keep every row consistent, of a design whose arrays the bundle does not
    hold, the manifest updated: only re-simulating that row catches it."""
    b = tmp_path / "forged"
    shutil.copytree(run / "smoke-bundle", b)
    held = set(json.loads((b / bundle.MANIFEST).read_text())["subsets"]["theory"]["designs"])
    t = pd.read_csv(b / "theory/metrics.csv")
    row = t[~t.design.isin(held) & (t.generalists == 0) & (t.at_least_one > 0)].iloc[0]
    d = int(row.design)
    _csv_edit(b / "theory/metrics.csv", d, n_45=row.n_45 + 1, at_least_one=max(row.at_least_one, row.n_45 + 1))
    t = pd.read_csv(b / "theory/metrics.csv")
    _csv_edit(b / "theory/metrics.csv", d, M_CF=0.0)
    _reseal_manifest(b, "theory/metrics.csv")
    assert bundle_check.check(b) == []  # consistent in itself
    rc, out = _cli(str(b), "--resimulate", str(d))
    assert rc == 1 and f"design {d}: metrics row" in out, out


def test_a_sample_of_paper_rows_resimulates_exactly() -> None:
    """Two rows of the committed paper bundle drawn at random (seed 0), held or not, re-simulated
    at paper resolution (121 x 121 weights, 4 environments)."""
    assert resimulate.resimulate(PAPER, ["sample:2"]) == []


# -- 3b. physics rows re-simulated on request (MODEL:WHICH, through the model registry) ---------


def _consistent_forgery(table: Path, d: int) -> None:
    """Replace the row of design ``d`` by another that is consistent in itself
    (bundle_check.row_problems finds nothing): no success at all, or, where the row has none, one
    success in the first environment."""
    counts = [*(f"n_{a}" for a in ENV_ANGLES_DEG), "generalists", "at_least_one"]
    none = dict.fromkeys([*counts, "M_L", "M_CF"], 0)
    row = pd.read_csv(table).set_index("design").loc[d]
    _csv_edit(table, d, **(none if row[counts].any() else none | {"n_45": 1, "at_least_one": 1}))


def test_a_consistent_forgery_of_a_pybullet_row_needs_resimulation(run: Path, tmp_path: Path) -> None:
    """The smoke bundle's pybullet rows (2 x 2 weights, early stop on): a consistent edit with the
    manifest updated passes the row checks; a design whose arrays the bundle holds is caught by
    comparing the row with them (issue 38), and ``--resimulate empirical:D`` re-simulates that
    design with the recorded science and catches it (was: refused as a usage error, theory rows
    only)."""
    b = tmp_path / "forged"
    shutil.copytree(run / "smoke-bundle", b)
    d = int(pd.read_csv(b / "empirical/metrics.csv").design.iloc[0])
    rc, out = _cli(str(b), "--resimulate", f"empirical:{d}")
    assert rc == 0 and "agree exactly" in out, out
    _consistent_forgery(b / "empirical/metrics.csv", d)
    _reseal_manifest(b, "empirical/metrics.csv")
    assert bundle_check.row_problems(pd.read_csv(b / "empirical/metrics.csv"), None) == []  # consistent in itself
    assert bundle_check.check(b) == [
        f"{b}/empirical/metrics.csv: design {d}: its row's counts differ from the merged store's arrays"
    ]
    rc, out = _cli(str(b), "--resimulate", f"empirical:{d}")
    assert rc == 1 and f"empirical design {d}: metrics row" in out, out


@pytest.fixture(scope="module")
def mujoco_results(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """MuJoCo results with every lever a survey records (mirror_derive, early stop, adaptive
    weights) on the smallest grid: design 75 and its mirror 51, 3 x 3 weights; about 5 s."""
    pytest.importorskip("mujoco")
    from morphlearn import config, models

    out = tmp_path_factory.mktemp("mujoco")
    section = {"enabled": True, "results_from": None, "weights": 3, "designs": [[[0.5, 0.5], [0.0, -0.5]]]}
    section |= {"include_mirrors": True, "mirror_derive": True, "early_stop": True, "adaptive_weights": True}
    cfg = config.deep_merge(
        config.read(ROOT / "config.yaml"),
        {
            "results_dir": str(out),
            "grid": {"positions_per_axis": 3, "weights": 5},
            "sweep": {"shards": 1, "threads": 1},
            "figures": {"enabled": False},
            "empirical": {"enabled": False},
            "mujoco": section | {"shards": 1},
        },
    )
    cwd = Path.cwd()
    os.chdir(ROOT)  # the body file is named relative to the project root
    try:
        s = configure.parse(cfg)
    finally:
        os.chdir(cwd)
    shard = out / "mujoco/shards/shard_0.nc"
    rules.run_shard(s, "mujoco", 0, shard)
    rules.run_merge(s, "mujoco", [str(shard)], out / "mujoco/merged.zarr")
    th = models.get("mujoco").thresholds(s)
    rules.run_metrics("mujoco", th, out / "mujoco/merged.zarr", out / "mujoco/metrics.csv")
    return out


def test_mujoco_rows_resimulate_with_their_recorded_levers(mujoco_results: Path, tmp_path: Path) -> None:
    """Both rows (51 simulated, 75 derived from it as the merge derives it) and their stored arrays
    re-made exactly from the science record (levers included); a consistent forgery of either row
    is caught."""
    sci = store.science_of(store.open_merged(mujoco_results / "mujoco/merged.zarr"))
    assert sci["mirror_derive"] and sci["early_stop"] and sci["adaptive_weights"], sci
    assert resimulate.resimulate(mujoco_results, ["mujoco:51", "mujoco:75"]) == []
    for d in (51, 75):
        b = tmp_path / str(d)
        shutil.copytree(mujoco_results, b)
        _consistent_forgery(b / "mujoco/metrics.csv", d)
        assert bundle_check.row_problems(pd.read_csv(b / "mujoco/metrics.csv"), 9) == []
        meaning, again = resimulate.resimulate(b, [f"mujoco:{d}"])  # the held arrays, then the simulation
        assert meaning.endswith(f"design {d}: its row's counts differ from the merged store's arrays"), meaning
        assert again.startswith(f"mujoco design {d}: metrics row"), again


def test_a_physics_only_run_bundles(mujoco_results: Path, tmp_path: Path) -> None:
    """A run of one physics model and no theory (config/survey9_mujoco.yaml) makes a bundle that
    checks out; a run with no model's results is refused by name."""
    from morphlearn.bundles import make as bundle

    out = tmp_path / "b"
    made = bundle.made_by(["config/survey9_mujoco.yaml", "config.yaml"], "results/survey9-mujoco-run")
    manifest = bundle.build(mujoco_results, out, top=3, made_by=made)
    assert set(manifest["subsets"]) == {"mujoco"} and manifest["subsets"]["mujoco"]["designs"] == [51, 75]
    assert bundle_check.check(out) == []
    with pytest.raises(bundle.BundleError, match=r"no model's metrics\.csv"):
        bundle.build(tmp_path / "empty", tmp_path / "b2", top=3, made_by={})


@pytest.mark.parametrize(
    "which",
    ["nomodel:1", "empirical:", "sample:x", "mujoco:canonical:2"],
)
def test_resimulate_refuses_an_unknown_model_or_design(which: str, capsys: pytest.CaptureFixture) -> None:
    """Refused before the bundle is read: one line naming what is allowed, exit 2."""
    rc, out = _cli(str(ROOT / "results/survey"), "--resimulate", which)
    err = capsys.readouterr().err
    assert rc == 2 and out == "" and "Traceback" not in err, (rc, out, err)
    assert len(err.strip().splitlines()) == 1 and "allowed: [MODEL:]WHICH, MODEL one of theory, empirical" in err, err


def test_resimulate_names_a_model_the_bundle_does_not_hold(mujoco_results: Path) -> None:
    assert resimulate.resimulate(mujoco_results, ["empirical:1"]) == [
        f"{mujoco_results}/empirical: no empirical results in this bundle (allowed models here: mujoco)"
    ]


def test_one_check_of_a_tables_meaning_for_the_render_compare_and_resimulate(
    paper_copy: Path, capsys: pytest.CaptureFixture
) -> None:
    """The forged tables check-bundle refuses (test_check_bundle_refuses) are refused by the
    render's start check, by ``compare`` and by ``--resimulate`` too: one check
    (bundle_check.meaning_problems), not four that disagree (issue 38: compare refused the
    duplicated table the others passed; ``--resimulate 5`` said the off-grid row agreed exactly)."""
    off_grid = next(a for a in TABLE_FORGERIES if a.__name__ == "off-grid l1x")
    want = off_grid(paper_copy)
    with pytest.raises(ValueError, match="nothing was rendered") as err:
        rules.check_render_inputs([f"{paper_copy}/theory/{n}" for n in ("metrics.csv", "merged.zarr")])
    assert want in str(err.value), err.value
    rc = cli.main(["compare", str(paper_copy / "theory/metrics.csv"), str(PAPER / "mujoco/metrics.csv")])
    err_line = capsys.readouterr().err.strip()
    assert rc == 2 and want in err_line and len(err_line.splitlines()) == 1, err_line
    again = resimulate.resimulate(paper_copy, ["theory:0"])  # another design: the table is still forged
    assert any(want in p for p in again), again


def test_a_rerender_that_fails_midway_leaves_the_bundle_unchanged(
    paper_copy: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Issue 38: figures 1, 3 and 4 rewritten, then a notebook failed, and nothing was restored
    (check-bundle failed after). Now the render runs on a copy beside the bundle: the same failure
    midway leaves every file of the bundle as it was, and the copy is gone."""
    from morphlearn.bundles import render as bundle_rerender

    before = _snapshot(paper_copy)

    def fails_midway(cmd: list[str], root: Path, target: Path) -> None:
        assert f"results_dir={target}" in cmd and target != Path("paper")
        for i in (1, 3, 4):
            for ext in ("png", "caption.md"):
                (root / target / f"figures/fig{i}.{ext}").write_bytes(b"redrawn\n")
        raise bundle.BundleError(f"{target}: the render failed (exit 1): fig5 notebook raised")

    monkeypatch.setattr(bundle_rerender, "_render", fails_midway)
    with pytest.raises(bundle.BundleError, match="the render failed"):
        bundle_rerender.rerender("paper", paper_copy.parent)
    assert _snapshot(paper_copy) == before
    assert bundle_check.check(paper_copy) == []
    assert not list(paper_copy.parent.glob(".rerender-*"))
