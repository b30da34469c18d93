"""Which run a config asks for (morphlearn.workflow.runs): the Snakefile includes its rule files and
asks for its targets, so each kind of run is data here, and two stages at once are refused."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import ROOT, copy_workflow, parse_at_root, snakemake

from morphlearn import config
from morphlearn.config import ConfigError
from morphlearn.workflow import runs


def _settings(*overlays: str, **override: object) -> object:
    cfg = config.read(ROOT / "config.yaml")
    for o in overlays:
        cfg = config.deep_merge(cfg, config.read(ROOT / o))
    return parse_at_root(config.deep_merge(cfg, override))


def test_default_config_is_the_papers_workflow() -> None:
    r = runs.run(_settings())
    assert r.kind == "paper" and r.figures is None
    assert r.rules == ("simulate", "morphology", "analysis", "figures")  # no learners, coopt, bundle


def test_stages_of_the_papers_workflow_follow_the_config() -> None:
    r = runs.run(_settings("config/paper.yaml"))
    assert r.rules[-2:] == ("bundle", "figures")
    assert "coopt" in runs.run(_settings("config/coopt.yaml")).rules
    assert "learners" in runs.run(_settings("config/learners.yaml")).rules


def test_render_only_includes_no_rule_that_simulates() -> None:
    """A re-render renders from stored results: no simulate, merge or metrics rule exists."""
    for overlay, kind in (("config/paper.yaml", "paper"), ("config/agreement.yaml", "agreement")):
        r = runs.run(_settings(overlay, render_only=True))
        assert (r.kind, r.rules) == (kind, ("figures",))


def test_stages_that_replace_the_papers_workflow() -> None:
    agreement = runs.run(_settings("config/agreement.yaml"))
    assert agreement.rules == ("agreement", "figures")
    assert agreement.figure_targets("R") == [f"R/figures/agreement.{e}" for e in ("png", "pdf", "html")]
    engines = runs.run(_settings("config/engines.yaml"))
    assert engines.rules == ("engines", "figures") and engines.figures == ("engines", "disagreement")
    scenarios = runs.run(_settings(scenarios="all"))
    assert scenarios.rules == ("scenarios",) and scenarios.figure_targets("R") == []


def test_two_stages_at_once_are_refused_by_name() -> None:
    s = _settings("config/agreement.yaml", engines={"enabled": True})
    with pytest.raises(ConfigError, match=r"^agreement and engines are both set; .*allowed: one of scenarios"):
        runs.run(s)


def test_every_rule_file_belongs_to_a_run() -> None:
    """No rule file the Snakefile could never include (common.smk: included first, by name)."""
    named = {
        f
        for s in (
            _settings("config/paper.yaml"),
            _settings("config/coopt.yaml"),
            _settings("config/learners.yaml"),
            _settings("config/agreement.yaml"),
            _settings("config/engines.yaml"),
            _settings(scenarios="all"),
        )
        for f in runs.run(s).rule_files
    }
    on_disk = {str(p.relative_to(ROOT)) for p in (ROOT / "workflow/rules").glob("*.smk")}
    assert on_disk - named == {"workflow/rules/common.smk"}
    assert named <= on_disk


def test_workflow_refuses_two_stages_in_one_line(tmp_path: Path) -> None:
    wd = copy_workflow(tmp_path / "clone")
    proc = snakemake(wd, "-n", "--configfile", "config/agreement.yaml", "config/engines.yaml", check=False)
    assert proc.returncode != 0
    err = [ln for ln in proc.stderr.splitlines() if ln.startswith("morphlearn:")]
    assert err and "agreement and engines are both set" in err[0], proc.stderr[-2000:]
    assert not (wd / "results" / "agreement" / "figures").exists()
