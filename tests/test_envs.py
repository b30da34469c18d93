"""envs/*.yaml (for --sdm conda users) pin exactly the versions of requirements.lock."""

import re
import sys
from pathlib import Path

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
