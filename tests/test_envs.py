"""envs/*.yaml (for --sdm conda users): pinned as requirements.lock, and each holds what its rules import."""

import os
import re
import subprocess
import sys
import time
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tools"))
import make_envs  # noqa: E402


def test_env_files_agree_with_lock() -> None:
    pins = make_envs.lock()
    files = sorted((ROOT / "envs").glob("*.yaml"))
    assert {f.stem for f in files} == set(make_envs.ENVS)
    for f in files:
        env = yaml.safe_load(f.read_text())
        pip = next(d["pip"] for d in env["dependencies"] if isinstance(d, dict))
        for spec in pip:
            name, version = re.fullmatch(r"([A-Za-z0-9_.\-]+)==(\S+)", spec).groups()
            assert pins.get(name.lower()) == version, f"{f.name}: {spec} vs lock {pins.get(name.lower())}"
        assert f.read_text() == make_envs.render(f.stem, make_envs.ENVS[f.stem], pins)


def test_every_rule_names_an_existing_env() -> None:
    for smk in (ROOT / "workflow/rules").glob("*.smk"):
        for ref in re.findall(r'conda:\s*\n\s*"([^"]+)"', smk.read_text()):
            assert (smk.parent / ref).resolve().is_file(), f"{smk.name}: {ref}"


# --- Each environment runs its own rules -----------------------------------------------------------
# conda channels cannot be reached in CI, so each env file's pip package set is built into its own
# virtual environment with uv (from uv's cache: seconds) and Snakemake runs, with that environment's
# Python, only the rules that name that env file (--allowed-rules). Snakemake itself is added to
# each environment: under --sdm conda a rule's Python imports the host's Snakemake the same way (the
# script preamble appends its search path), so what is checked is everything else a rule imports.
# The runs also parse the Snakefile in each environment.

# env -> (rules that name envs/<env>.yaml, targets to make with only those rules). In workflow
# order: each run finds the previous runs' outputs. test_every_conda_rule_is_run checks coverage.
SMOKE_STEPS = {
    "theory": (["theory_shard"], [f"results/theory/shards/shard_{i}.nc" for i in range(3)]),
    "empirical": (
        ["empirical_shard", "optimise_morphology"],
        ["results/empirical/shards/shard_0.nc", "results/morphology/pareto.csv"],
    ),
    "analysis": (["merge", "metrics", "summary"], ["results/summary.md"]),
    "learners": (
        [
            "learners_shard",
            "learners_analysis",
            "coopt_landscape",
            "coopt_runs",
            "coopt_restart_runs",
            "coopt_analysis",
        ],
        ["results/learners/summary.md", "results/coopt/summary.md"],
    ),
    # Every notebook, the reproduction table and the results bundle (which holds all of them); the
    # coopt stage's bundle (its tables and figure)
    "figures": (
        [
            *(f"figure_fig{i}" for i in range(1, 8)),
            "figure_learners",
            "figure_coopt",
            "reproduction",
            "bundle",
            "coopt_bundle",
        ],
        ["results/bundle", "results/coopt-bundle/bundle.json"],
    ),
}
CONFIGS = ("config/smoke.yaml", "tiny_optimise.yaml", "tiny_learners.yaml")
# The scenario rules (workflow/rules/scenarios.smk), on a base and a shorter-horizon scenario of the
# smoke config: env -> (rules, --until rules; the run's targets are the scenario workflow's own).
SCENARIO_STEPS = {
    "theory": (["scenario_shard"], ["scenario_shard"]),
    "analysis": (
        ["scenario_merge", "scenario_metrics", "scenario_summary", "scenario_compare"],
        ["scenario_summary", "scenario_compare"],
    ),
    "figures": (["scenario_report"], ["scenario_report"]),
}
SCENARIOS = ("--config", "scenario_file=s.yaml", "scenarios=all")
# A run that reads the theory and empirical results of the bundle the figures step made
# (theory.results_from, empirical.results_from).
READER_STEP = (
    "analysis",
    ["empirical_from_bundle", "theory_from_bundle"],
    ["results/reader/empirical/metrics.csv", "results/reader/theory/metrics.csv"],
)
# The engine comparison (config/engines.yaml) on the copy's committed survey (pybullet against
# itself: what is checked is what the rules import): env -> (rules, targets).
ENGINE_STEPS = {
    "analysis": (["engines_numbers"], ["results/eng/engines.json"]),
    "figures": (["figure_engines"], ["results/eng/figures/engines.png"]),
}
ENGINE_CONFIGS = ("config/smoke.yaml", "eng.yaml")
# Rules that run the same script in the same environment as a rule run above (what this test
# checks is that an environment holds what a rule's script imports): rule -> that rule.
# engines_disagreement imports what empirical_shard imports (both engines' episode runners) and
# takes 2-3 CPU-minutes on the committed surveys: not run here (tests/test_engines.py checks its
# committed outputs); figure_disagreement draws with figure_engines' imports. agreement imports
# what engines_numbers (the rank statistics) and metrics (the outcome arrays) import, both run here
# in envs/analysis.yaml, and reads committed bundles only (tests/test_agreement.py).
SAME_SCRIPT_AND_ENV = {
    "survey_from_bundle": "empirical_from_bundle",
    "agreement": "engines_numbers",
    "engines_disagreement": "empirical_shard",
    "figure_disagreement": "figure_engines",
}


def build_env(name: str, dest: Path) -> Path:
    env = yaml.safe_load((ROOT / "envs" / f"{name}.yaml").read_text())
    pip = next(d["pip"] for d in env["dependencies"] if isinstance(d, dict))
    pins = make_envs.lock()
    uv = Path(sys.executable).with_name("uv")
    subprocess.run([str(uv), "venv", "-q", "--python", sys.executable, str(dest)], check=True)
    subprocess.run(
        [
            str(uv),
            "pip",
            "install",
            "-q",
            "--compile-bytecode",  # as tools/setup.sh: each rule job and kernel loads bytecode
            "--python",
            str(dest / "bin/python"),
            "-c",
            str(ROOT / "requirements.lock"),
            *pip,
            f"snakemake=={pins['snakemake']}",
        ],
        check=True,
    )
    return dest / "bin/python"


def test_every_conda_rule_is_run() -> None:
    for smk in (ROOT / "workflow/rules").glob("*.smk"):
        text = smk.read_text()
        for name, env in re.findall(r'rule (\w+):\n(?:.*\n)*?\s+conda:\s*\n\s*"\.\./\.\./envs/(\w+)\.yaml"', text):
            run = SMOKE_STEPS[env][0] + SCENARIO_STEPS.get(env, ([], []))[0] + ENGINE_STEPS.get(env, ([], []))[0]
            run = run + (READER_STEP[1] if env == READER_STEP[0] else [])
            assert SAME_SCRIPT_AND_ENV.get(name, name) in run, f"{smk.name}: rule {name} (envs/{env}.yaml) is not run"
    # the figure rules are made in a loop (rule name f"figure_{_fig}"): all name envs/figures.yaml
    assert '"../../envs/figures.yaml"' in (ROOT / "workflow/rules/figures.smk").read_text()


@pytest.mark.slow
def test_each_env_runs_its_rules(tmp_path: Path) -> None:
    from conftest import TEST_COMMIT, copy_workflow, job_stats, snakemake

    wd = copy_workflow(tmp_path / "wd")
    # optimise_morphology with one NSGA-II population (20 evaluations: seconds, not minutes)
    (wd / "tiny_optimise.yaml").write_text("empirical:\n  optimise:\n    evaluations: 20\nbundle_dir: results/bundle\n")
    (wd / "tiny_learners.yaml").write_text(  # the learner stage, seconds (tests/test_learners_workflow.py)
        "learners: {enabled: true, seeds: 2, budget: 4, cycles: 1, per_phase: 4, max_designs: 3, shards: 1, "
        "threads: 1, bootstrap: 100}\n"
        # the coopt stage (docs/coopt.md), seconds: one setup, one learner, one seed, a 3^4 landscape
        "coopt: {enabled: true, setups: [a], learners: [random], budgets: [3], seeds: 1, landscape_weights: 3, "
        "bootstrap: 100, best_metrics: results/survey/theory/metrics.csv, "
        # its restart runs and its bundle (rules coopt_restart_runs, coopt_bundle)
        "restart: {learners: [one_plus_one_restart], setups: [a]}, bundle_dir: results/coopt-bundle}\n"
    )
    (wd / "eng.yaml").write_text(
        "results_dir: results/eng\nengines: {enabled: true, mujoco: results/survey/empirical/metrics.csv}\n"
    )
    (wd / "s.yaml").write_text("base: {}\nshort:\n  theory:\n    horizon: 200.0\n")
    t0 = time.perf_counter()
    pythons = {env: build_env(env, tmp_path / "envs" / env) for env in SMOKE_STEPS}
    print(f"\n{len(pythons)} environments built in {time.perf_counter() - t0:.1f} s")

    def run(env: str, *args: str, configs: tuple[str, ...] = CONFIGS) -> dict[str, int]:
        # args before --configfile, which takes every following word as a config file
        t0 = time.perf_counter()
        proc = subprocess.run(
            [str(pythons[env]), "-m", "snakemake", *args, "--cores", "2", "--configfile", *configs],
            cwd=wd,
            capture_output=True,
            text=True,
            timeout=900,
            env=dict(os.environ, MORPHLEARN_GIT_COMMIT=TEST_COMMIT),
        )
        logs = "\n".join(p.read_text()[-1500:] for p in sorted((wd / "results").rglob("logs/**/*.log")))
        assert proc.returncode == 0, f"envs/{env}.yaml {args}:\n{proc.stderr[-3000:]}\n{logs}"
        print(f"envs/{env}.yaml, {' '.join(args)[:60]}: {time.perf_counter() - t0:.1f} s")
        return job_stats(proc.stdout + proc.stderr)

    for env, (rules, targets) in SMOKE_STEPS.items():
        run(env, *targets, "--allowed-rules", *rules)
    for env, (rules, targets) in ENGINE_STEPS.items():
        assert run(env, *targets, "--allowed-rules", *rules, configs=ENGINE_CONFIGS) == {r: 1 for r in rules}
    for env, (rules, until) in SCENARIO_STEPS.items():
        # --until, not --allowed-rules (which would leave the final targets unmakeable): the jobs
        # run are the step's own rules, since earlier steps made everything upstream.
        ran = run(env, *SCENARIOS, "--until", *until)
        assert set(ran) - {"scenarios", "all"} == set(rules), (env, ran)
    # reads results/bundle, so it must not bundle into it too (bundle_dir refuses another config's bundle)
    (wd / "reader.yaml").write_text(
        "results_dir: results/reader\nbundle_dir: null\nempirical:\n  results_from: results/bundle\n"
        "theory:\n  results_from: results/bundle\n"
    )
    env, rules, targets = READER_STEP
    assert run(env, *targets, "--allowed-rules", *rules, configs=(*CONFIGS, "reader.yaml")) == dict.fromkeys(rules, 1)
    # Together the environments made the workflow: the main environment has nothing left to do
    # (nothing made in an environment is out of date).
    for extra in ((), SCENARIOS):
        proc = snakemake(wd, "-n", "--cores", "1", "--configfile", *CONFIGS, *extra)
        assert job_stats(proc.stdout + proc.stderr) in ({}, {"all": 1}), proc.stdout[-2000:]


PARSE_AND_PLAN = """
import json, sys
from snakemake.cli import main
sys.argv = ["snakemake", "-n", "--cores", "1", "--configfile", "config/smoke.yaml"]
try:
    main()
except SystemExit as e:
    assert not e.code, e.code
print(json.dumps(sorted(m for m in sys.modules if m.split(".")[0] in ("pybullet", "pymoo"))))
"""


def test_parsing_and_planning_import_no_pybullet_or_pymoo(tmp_path: Path) -> None:
    """The Snakefile's parse and a dry run (every rule's params evaluated, the empirical ones too)
    load neither: they run in the host environment and import morphlearn.physics.params."""
    from conftest import copy_workflow

    wd = copy_workflow(tmp_path / "wd")
    proc = subprocess.run([sys.executable, "-c", PARSE_AND_PLAN], cwd=wd, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert proc.stdout.strip().splitlines()[-1] == "[]", proc.stdout[-2000:]
