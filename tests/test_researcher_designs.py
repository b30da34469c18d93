"""A researcher's own designs, as the README's "Your own designs" says: any coordinates in
``morphlearn design`` (progress, --save, --plot), a workflow config's designs off its grid refused
with the grid that holds them, a physics-only run that draws what needs no theory, one explorer
command, the commands' --help, and the config locations a bundle may be made from."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml
from conftest import ROOT, copy_workflow, snakemake
from quoted_sources import recipe_designs, recipe_grid

MORPHLEARN = Path(sys.executable).with_name("morphlearn")


def _recipe() -> str:
    text = (ROOT / "README.md").read_text().split("## Your own designs", 1)[1]
    return re.search(r"```bash\n(.*?)```", text, re.S)[1]  # type: ignore[index]


def test_the_readme_recipe_runs_end_to_end_on_the_reduced_model(tmp_path: Path) -> None:
    """The recipe as written, at 5 x 5 weights for speed (the README's: 121 x 121): each design's
    lines, its progress on stderr, its outcome arrays and its map."""
    script = _recipe().replace("--weights 121", "--weights 5")
    assert script != _recipe(), "the recipe no longer names its weights"
    for name in (".venv", "config"):  # run as from the project root, without writing into it
        (tmp_path / name).symlink_to(ROOT / name)
    proc = subprocess.run(["bash", "-euc", script], cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert proc.stdout.count("generalists (O == 4)") == 3
    assert proc.stderr.count("episodes") >= 3  # the progress lines
    designs = recipe_designs()
    assert len(designs) == 3 and any(not np.isclose(np.array(d) * 8, np.round(np.array(d) * 8)).all() for d in designs)
    for d in designs:
        stem = "_".join(f"{v:g}" for v in d)
        with np.load(tmp_path / "mine" / f"{stem}.npz") as z:
            assert z["first_time"].shape == z["status"].shape == (4, 5, 5)
            assert np.allclose(z["weights"], np.linspace(-1, 1, 5))
            assert [float(v) for v in z["meta_l1"].item().strip("[]").split(",")] == list(d[:2])
        assert (tmp_path / "mine" / f"{stem}.png").read_bytes()[:4] == b"\x89PNG"


def test_design_refuses_a_file_it_cannot_write_before_it_simulates(tmp_path: Path) -> None:
    base = [str(MORPHLEARN), "design", "--model", "reduced", "--l1", "0.3", "0.1", "--l2", "0.5", "-0.45"]
    for extra, said in (
        (["--plot", str(tmp_path / "no" / "map.png")], "no folder"),
        (["--save", str(tmp_path / "a.csv")], "allowed endings .npz"),
        (["--plot", str(tmp_path / "map.jpg")], "allowed endings .png, .pdf, .svg"),
    ):
        proc = subprocess.run([*base, *extra], capture_output=True, text=True, timeout=120)
        assert proc.returncode == 2 and said in proc.stderr and "Traceback" not in proc.stderr, proc.stderr
        assert "episodes" not in proc.stderr  # refused before any simulation


def _config(tmp: Path, positions: int) -> Path:
    cfg = {
        "results_dir": "results/mine",
        "grid": {"positions_per_axis": positions},
        "theory": {"enabled": False},
        "empirical": {"enabled": False},
        "reduced": {
            "enabled": True,
            "weights": 5,
            "designs": [[list(d[:2]), list(d[2:])] for d in recipe_designs()],
            "include_mirrors": False,
        },
    }
    (tmp / "config" / "mine.yaml").write_text(yaml.safe_dump(cfg))
    return tmp


def test_a_design_off_the_grid_is_refused_with_the_grid_that_holds_it(tmp_path: Path) -> None:
    """Once "l1.x=0.3 is not on the 9-point grid" and no word of how to run it."""
    wd = _config(copy_workflow(tmp_path / "wf"), 9)
    proc = snakemake(wd, "-n", "--configfile", "config/mine.yaml", check=False)
    out = proc.stdout + proc.stderr
    assert proc.returncode == 2 and "Traceback" not in out, out[-2000:]
    assert "is not on the 9-point grid" in out
    assert f"grid.positions_per_axis: {recipe_grid()} holds them all" in out and "morphlearn design" in out


def test_a_physics_only_run_draws_what_needs_no_theory(tmp_path: Path) -> None:
    """Theory off, figures on: Fig. 1 and each design's map, no reproduction table (once: no figure
    at all, and nothing said)."""
    wd = _config(copy_workflow(tmp_path / "wf"), recipe_grid())
    snakemake(wd, "--cores", "2", "--configfile", "config/mine.yaml", timeout=900)
    figs = wd / "results/mine/figures"
    assert sorted(p.name for p in figs.glob("*.png")) == ["fig1.png", "maps.png"]
    caption = (figs / "maps.caption.md").read_text()
    for d in recipe_designs():
        assert f"l1 = ({d[0]:g}, {d[1]:g}), l2 = ({d[2]:g}, {d[3]:g})" in caption
    assert not (wd / "results/mine/reproduction.md").exists()
    assert "weights per synapse: reduced 5" in (wd / "results/mine/summary.md").read_text()


@pytest.mark.parametrize("cmd", ["verify", "check-bundle", "compare", "design"])
def test_each_command_says_what_it_does_in_its_help(cmd: str) -> None:
    out = subprocess.run([str(MORPHLEARN), cmd, "--help"], capture_output=True, text=True, timeout=60).stdout
    head = out.split("\n\n")[1]  # argparse: usage, then the description
    assert not head.lstrip().startswith(("options:", "positional arguments:")), out[:400]
    if cmd == "design":
        for opt in ("--r", "--horizon", "--dt"):
            line = re.search(rf"\n  {opt} [^\n]*\n(?:\s{{10,}}[^\n]*\n)*", out)
            assert line and "theory" in line[0], (opt, out)


def test_one_explorer_command_everywhere() -> None:
    """results/README.md once said `voila notebooks/explore.ipynb`, docs/explorer.md `morphlearn explore`."""
    docs = [ROOT / "README.md", ROOT / "results/README.md", *sorted((ROOT / "docs").glob("*.md"))]
    said = [p.name for p in docs if re.search(r"`[^`\n]*voila notebooks/explore\.ipynb", p.read_text())]
    fenced = [p.name for p in docs if re.search(r"^\.venv/bin/voila notebooks/explore", p.read_text(), re.M)]
    assert not said and not fenced, said + fenced
    assert "morphlearn explore" in (ROOT / "results/README.md").read_text()


def test_a_bundle_is_made_only_from_configs_check_bundle_reads() -> None:
    """`bundle` once wrote a bundle from a config outside the project, which check-bundle refuses."""
    from morphlearn.bundles import check, make

    for name, ok in (
        ("config/mine.yaml", True),
        ("mine.yaml", True),
        ("../mine.yaml", False),
        ("/tmp/mine.yaml", False),
        ("config/../../x.yaml", False),
    ):
        assert bool(make.CONFIG_LOCATION.fullmatch(name)) is ok is bool(check.CONFIG_NAME.fullmatch(name)), name
        if not ok:
            with pytest.raises(make.BundleError, match="inside the project"):
                make.check_config_locations(["config.yaml", name])
    make.check_config_locations(["config.yaml", "config/mine.yaml"])


def test_a_workflow_runs_progress_says_the_time_left() -> None:
    """`morphlearn refine status --configfile`: the designs finished, and the time left at their pace
    (pauses between sessions left out)."""
    from morphlearn.refine.cli import time_left

    assert time_left([0.0, 100.0, 200.0, 90_000.0, 90_100.0], 6).startswith("; ~10 min left at the pace of the last 3")
    assert time_left([0.0], 5) == "" and time_left([0.0, 10.0], 0) == ""
    assert "h left" in time_left([0.0, 3600.0], 3)


def test_the_recipe_designs_are_off_the_paper_grid() -> None:
    assert recipe_grid() > 9
