"""What a site or a citing author needs: --version, LICENSE, CITATION.cff, the config key table."""

import os
import re
import subprocess
import sys
import tomllib

import yaml
from conftest import ROOT

import morphlearn


def _version(env: dict[str, str]) -> str:
    proc = subprocess.run(
        [sys.executable, "-m", "morphlearn.apps.cli", "--version"],
        capture_output=True,
        text=True,
        env=env,
        cwd=ROOT,
        check=True,
    )
    return proc.stdout.strip()


def test_version_names_package_version_and_commit() -> None:
    env = {k: v for k, v in os.environ.items() if k != "MORPHLEARN_GIT_COMMIT"}
    head = subprocess.run(
        ["git", "rev-parse", "HEAD"], cwd=ROOT, capture_output=True, text=True, check=True
    ).stdout.strip()
    m = re.fullmatch(r"morphlearn (\S+) \(commit ([0-9a-f]{40})(-dirty)?\)", _version(env))
    assert m and m.group(1) == morphlearn.__version__ and m.group(2) == head, _version(env)
    # Cluster nodes without the repository: the commit comes from the environment.
    assert _version(env | {"MORPHLEARN_GIT_COMMIT": "abc123"}) == f"morphlearn {morphlearn.__version__} (commit abc123)"


def test_versions_agree_and_citation_names_the_paper() -> None:
    cff = yaml.safe_load((ROOT / "CITATION.cff").read_text())
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    assert cff["version"] == project["version"] == morphlearn.__version__
    paper = cff["preferred-citation"]
    assert paper["title"] == "Morphology dictates learnability in neural controllers"
    assert [a["family-names"] for a in paper["authors"]][:2] == ["Powers", "Grindle"]
    assert cff["license"] == "MIT" and (ROOT / "LICENSE").read_text().startswith("MIT License")


def test_config_readme_is_current() -> None:
    proc = subprocess.run(
        [sys.executable, str(ROOT / "tools/config_docs.py"), "--check"], capture_output=True, text=True
    )
    assert proc.returncode == 0, proc.stderr
    # and it lists every leaf key of a preset, e.g. the one this issue added to them
    assert "| `results_dir` |" in (ROOT / "config/README.md").read_text()
