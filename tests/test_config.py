"""Bad configuration: a one-line error naming the key and what is allowed, nothing written."""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml
from conftest import ROOT, copy_workflow, snakemake, written_results

from morphlearn import config, configure


def base() -> dict:
    return config.load(ROOT / "config.yaml", [ROOT / "config/smoke.yaml"])


@pytest.mark.parametrize(
    ("patch", "key", "allowed"),
    [
        ({"grid": {"positions_per_axis": 3, "weights": 1}}, "grid.weights = 1", ">= 2"),
        ({"grid": {"positions_per_axis": 3, "weights": "many"}}, "grid.weights = 'many'", "integer"),
        ({"theory": {"horizon": 0}}, "theory.horizon = 0", "> 0"),
        ({"theory": {"horizon": -5}}, "theory.horizon = -5", "> 0"),
        ({"theory": {"integrator": "euler"}}, "theory.integrator = 'euler'", "['dp5', 'rk4']"),
        ({"sweep": {"shards": 10_000}}, "sweep.shards = 10000", "1..45"),
        ({"colour": "red"}, "unknown key ['colour']", "allowed: ['agreement', 'analysis'"),
        ({"theory": {"horizn": 5}}, "unknown key ['horizn'] under 'theory'", "'horizon'"),
        ({"analysis": {"horizon": 900}}, "analysis.horizon = 900", "<= 500"),
    ],
)
def test_bad_values_name_the_key(patch: dict, key: str, allowed: str) -> None:
    cfg = config.deep_merge(base(), patch)
    with pytest.raises(config.ConfigError) as e:
        configure.parse(cfg)
    msg = str(e.value)
    assert key in msg and allowed in msg and "\n" not in msg


def test_positions_outside_body_refused() -> None:
    # Positions come from positions_per_axis over [-0.5, 0.5]; the CLI takes coordinates.
    from morphlearn.apps.cli import main

    assert main(["design", "--l1", "0.6", "0", "--l2", "0", "0"]) == 2


def test_malformed_yaml(tmp_path: Path) -> None:
    p = tmp_path / "bad.yaml"
    p.write_text("grid: [1, 2\n")
    with pytest.raises(config.ConfigError, match=r"bad.yaml: malformed YAML at line"):
        config.load(p)


@pytest.mark.parametrize(
    ("override", "needle"),
    [
        ({"grid": {"positions_per_axis": 3, "weights": 1}}, "grid.weights = 1"),
        ({"theory": {"horizon": 0}}, "theory.horizon = 0"),
        ({"bogus": 1}, "unknown key ['bogus']"),
    ],
)
def test_workflow_refuses_bad_config_and_writes_nothing(tmp_path: Path, override: dict, needle: str) -> None:
    wd = copy_workflow(tmp_path / "wf")
    (wd / "bad.yaml").write_text(
        yaml.safe_dump(config.deep_merge(yaml.safe_load((ROOT / "config/smoke.yaml").read_text()), override))
    )
    proc = snakemake(wd, "--cores", "1", "--configfile", "bad.yaml", check=False)
    assert proc.returncode == 2, proc.stderr[-2000:]
    assert needle in proc.stderr
    assert written_results(wd) == []


@pytest.mark.parametrize(
    "path", sorted(p.name for p in (ROOT / "config").glob("*.yaml") if "robot: authors" in p.read_text())
)
def test_the_authors_robot_gets_the_authors_body_in_every_committed_config(path: str, monkeypatch) -> None:
    """Each engine's ``robot: authors`` section, merged over config.yaml as ``--configfile`` merges
    it, simulates the authors' body file. Once config.yaml pinned ``empirical.morphology`` to the
    project's body and the pybullet survey of config/authors_pybullet.yaml ran the authors' robot
    with the project's masses, motor and gravity, unnoticed."""
    from morphlearn import models
    from morphlearn.physics.params import load_params

    monkeypatch.chdir(ROOT)
    s = configure.parse(config.read("config.yaml", [f"config/{path}"]))
    authors = [n for n, sec in s.models.items() if getattr(sec, "robot", None) == "authors" and sec.enabled]
    assert authors, "no enabled section with robot: authors"
    for name in authors:
        e = models.get(name).settings(s)
        assert e.morphology == "config/authors_body.yaml", name
        assert e.params == load_params("config/authors_body.yaml"), name
        assert e.science["params"]["gravity"] == 1.0, name  # the authors' world, not -9.81


def test_one_robot_with_the_other_robots_body_file_is_refused(monkeypatch) -> None:
    monkeypatch.chdir(ROOT)
    cfg = config.read("config.yaml", ["config/authors_pybullet.yaml"])
    cfg["empirical"]["morphology"] = "config/empirical_morphology.yaml"
    with pytest.raises(
        config.ConfigError,
        match=r"empirical.morphology = 'config/empirical_morphology.yaml' is the "
        r"project robot's body file but empirical.robot = 'authors'; allowed: null",
    ):
        configure.parse(cfg)
    cfg = config.read("config.yaml")
    cfg["empirical"]["morphology"] = "config/authors_body.yaml"  # robot: project (the default)
    with pytest.raises(config.ConfigError, match="is the authors robot's body file"):
        configure.parse(cfg)
