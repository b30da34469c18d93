"""The plug-in, proved: a toy engine (trivial analytic physics on the physics base) registered by
its own package and one line in the model registry, and nothing else changed, reaches the CLI,
the shard / merge / metrics rules, a bundle, figures 3, 6 and 7 and the reproduction rows. Toy
engines registered in this process give a paper claim's row that differs their own reason and,
registered as Fig. 1C's body, their own body, which Fig. 1C then draws.

The project is copied (what a clone holds, :func:`conftest.copy_workflow`), the toy package is
written into the copy's ``src`` and the registry line added; the copy's package is the one every
process imports (``PYTHONPATH``)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import TEST_COMMIT, copy_workflow

TOY = '''"""A toy engine: success is analytic (same-sign weights, close enough for the sensors' spread)."""

from __future__ import annotations

from collections.abc import Callable
from types import SimpleNamespace

import numpy as np

from morphlearn.physics.model import Physics
from morphlearn.physics.options import SweepOptions
from morphlearn.physics.sweep import sweep
from morphlearn.results import DesignResult


def evaluate_design(l1, l2, weights, params, progress=None, options=None) -> DesignResult:
    spread = abs(l1[0] - l2[0]) + abs(l1[1] - l2[1])

    def batch(w, env):  # the engine: a batch of episodes (weights (n, 2), environments (n,))
        ok = (w[:, 0] * w[:, 1] > 0) & (np.abs(w[:, 0] - w[:, 1]) <= spread * env / 4)
        far = 10.0 * params.contact_distance
        return SimpleNamespace(first_time=np.where(ok, 1.0, np.nan), min_dist=np.where(ok, 0.0, far), finite=ok | True)

    # the physics layer's sweep: the levers (adaptive grid, resume inside a design) come with it
    return sweep(batch, l1, l2, weights, params, options or SweepOptions(), progress)


class Toy(Physics):
    name = "toy"
    engine = "toy"
    env_file = "envs/empirical.yaml"

    @staticmethod
    def design_evaluator() -> Callable[..., DesignResult]:
        return evaluate_design
'''

CONFIG = """\
bundle_dir: results/toy-bundle
empirical:
  enabled: false
toy:
  enabled: true
  weights: 5
  designs: all
  shards: 2
"""


def _run(wd: Path, *args: str, timeout: int = 900) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "PYTHONPATH": str(wd / "src"), "MORPHLEARN_GIT_COMMIT": TEST_COMMIT}
    r = subprocess.run(list(args), cwd=wd, capture_output=True, text=True, timeout=timeout, env=env)
    assert r.returncode == 0, f"{' '.join(args)}:\n{r.stdout[-3000:]}\n{r.stderr[-3000:]}"
    return r


@pytest.fixture(scope="module")
def toy_project(tmp_path_factory: pytest.TempPathFactory) -> Path:
    wd = copy_workflow(tmp_path_factory.mktemp("toy"))
    pkg = wd / "src" / "morphlearn" / "toy"
    pkg.mkdir()
    (pkg / "__init__.py").write_text('"""A toy engine (tests/test_toy_engine.py)."""\n')
    (pkg / "plugin.py").write_text(TOY)
    reg = wd / "src" / "morphlearn" / "models.py"
    text = reg.read_text()
    line = '    "ode": "morphlearn.ode.plugin:Ode",\n'
    assert text.count(line) == 1
    reg.write_text(text.replace(line, line + '    "toy": "morphlearn.toy.plugin:Toy",\n'))  # the one line
    (wd / "toy.yaml").write_text(CONFIG)
    return wd


def test_the_toy_reaches_the_cli(toy_project: Path) -> None:
    exe = str(Path(sys.executable).with_name("morphlearn"))
    r = _run(
        toy_project, exe, "design", "--model", "toy", "--l1", "0.5", "0.5", "--l2", "0.5", "-0.5", "--weights", "5"
    )
    r = _run(
        toy_project, exe, "design", "--model", "toy", "--l1", "0.5", "0.5", "--l2", "0.5", "-0.5", "--weights", "5",
        "--json",
    )  # fmt: skip
    out = json.loads(r.stdout.strip().splitlines()[-1])
    # w in {-1, -0.5, 0, 0.5, 1}, spread 1: the 8 same-sign pairs, 4 of them equal (all four
    # environments), 4 half a unit apart (environments 2 and 3: within 2/4 and 3/4)
    assert out["generalists"] == 4 and out["per_env"] == [4, 4, 8, 8], out


def test_the_toy_reaches_rules_bundle_figures_and_reproduction(toy_project: Path) -> None:
    wd = toy_project
    snakemake = str(Path(sys.executable).with_name("snakemake"))
    _run(wd, snakemake, "all", "bundle", "--cores", "2", "--configfile", "config/smoke.yaml", "toy.yaml")
    r = wd / "results"
    assert sorted(p.name for p in (r / "toy" / "shards").glob("*.nc")) == ["shard_0.nc", "shard_1.nc"]
    table = (r / "toy" / "metrics.csv").read_text().splitlines()
    assert len(table) == 1 + 81 and table[1].startswith("toy,")  # every design of the 3-point grid
    bundle = wd / "results" / "toy-bundle"
    manifest = json.loads((bundle / "bundle.json").read_text())
    assert any(f.startswith("toy/") for f in manifest["files"]), sorted(manifest["files"])[:20]
    for fig in ("fig3", "fig6", "fig7"):
        caption = (bundle / "figures" / f"{fig}.caption.md").read_text()
        assert "toy" in caption, (fig, caption[:500])
    repro = (bundle / "reproduction.md").read_text()
    assert any("toy" in line for line in repro.splitlines() if line.startswith("|")), repro[:2000]


def _toy_model(reason: tuple[str, str] | None) -> object:
    """A toy engine on the physics base (no simulation needed): the paper's engine with the
    authors' robot, so its results answer the paper's physics claims, and its own reason or none."""
    from morphlearn.physics.model import Physics

    class ReasonToy(Physics):
        name = "reasontoy"
        engine = "reasontoy"
        engine_label = "Toy"
        robots = ("authors",)
        paper_engine = True
        differs_because = reason

    return ReasonToy()


def _differing_row(model: str) -> dict[str, str]:
    from morphlearn.figures.reproduction import claims, table
    from morphlearn.figures.reproduction.claim_values import Ours

    claim = next(c for c in claims.CLAIMS if c.model == "physics" and c.kind == claims.COUNT)
    far = float(claim.value) * 10 + 100  # type: ignore[arg-type]
    return table.claim_row(claim, model, Ours(str(far), value=far), "toy.yaml")


@pytest.mark.parametrize(
    ("reason", "want"),
    [
        (("The toy's own reason.", "differs-toy"), ("The toy's own reason.", "differs-toy")),
        (None, ("The authors' robot in Toy, at the designs this run holds.", "")),  # no KeyError: a generic one
    ],
)
def test_a_toy_engine_gives_the_reason_of_its_paper_claim_row_that_differs(
    monkeypatch: pytest.MonkeyPatch, reason: tuple[str, str] | None, want: tuple[str, str]
) -> None:
    """The reason text of a paper claim's row that differs comes from the engine that answers it
    (its plug-in), not from a table of engine names in the analysis code."""
    from morphlearn import models
    from morphlearn.figures.reproduction.verdict import DIFFERS

    monkeypatch.setitem(models.MODELS, "reasontoy", _toy_model(reason))
    row = _differing_row("reasontoy")
    assert row["verdict"] == DIFFERS and (row["reason"], row["anchor"]) == want
    # the paper's engine keeps its committed reason (the bundles' reproduction rows)
    assert _differing_row("ode")["reason"].startswith("The authors' robot in ODE")


# -- a toy engine's own figure body: Fig. 1C draws what the engine supplies ---------------------

TOY_BODY = '''"""A toy engine's body for Fig. 1C: a box and two sensor spheres (no wheels, no castor)."""

import pybullet as pb

from morphlearn.physics.body import GREY, RED, YELLOW, FigureBody


def build(p, l1, l2, light_xy):
    c = pb.connect(pb.DIRECT)
    box = pb.createVisualShape(pb.GEOM_BOX, halfExtents=[0.5, 0.5, 0.25], rgbaColor=GREY, physicsClientId=c)
    pb.createMultiBody(0, -1, box, basePosition=[0, 0, 0.25], physicsClientId=c)
    sensor = pb.createVisualShape(pb.GEOM_SPHERE, radius=0.15, rgbaColor=RED, physicsClientId=c)
    for q in (l1, l2):
        pb.createMultiBody(0, -1, sensor, basePosition=[q[0], q[1], 0.6], physicsClientId=c)
    light = pb.createVisualShape(pb.GEOM_SPHERE, radius=p.light_radius, rgbaColor=YELLOW, physicsClientId=c)
    pb.createMultiBody(0, -1, light, basePosition=[*light_xy, p.light_radius], physicsClientId=c)
    parts = {"toy box": (0.0, 0.0, 0.5), "toy sensor 1": (l1[0], l1[1], 0.75), "toy sensor 2": (l2[0], l2[1], 0.75)}
    return c, lambda: pb.disconnect(c), parts


BODY = FigureBody(build=build, text="the toy's box with two sensor spheres (red)", offsets={"toy box": (-150, 60)})
'''


def _body_toy() -> object:
    """A toy engine on the physics base, registered as Fig. 1C's body, with a body of its own."""
    from types import MappingProxyType

    from morphlearn.physics.model import Physics

    class BodyToy(Physics):
        name = "bodytoy"
        engine = "bodytoy"
        engine_label = "Toy"
        figure_body = True
        figure_bodies = MappingProxyType({"project": "toy_body:BODY"})  # its own body (TOY_BODY)

    return BodyToy()


def test_a_toy_engine_registered_as_fig1_body_draws_its_own_body(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Fig. 1C draws the body the registry's figure_body engine supplies (its builder, its caption
    words), not one the figure module builds: the toy's box and sensors, not the ODE robot."""
    import matplotlib.image as mpimg
    import numpy as np
    import papermill

    from morphlearn import configure, models
    from morphlearn.figures import options
    from morphlearn.figures.render import render_robot

    root = Path(__file__).resolve().parents[1]
    (tmp_path / "toy_body.py").write_text(TOY_BODY)
    monkeypatch.syspath_prepend(str(tmp_path))
    # the notebook's kernel imports the body too
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([str(tmp_path), os.environ.get("PYTHONPATH", "")]))
    s_ode = configure.load(root / "config.yaml", [root / "config/paper.yaml"])
    ode = options.figure_robot(s_ode)
    monkeypatch.setattr(type(models.MODELS[ode_name := models.figure_body()]), "figure_body", False)
    monkeypatch.setitem(models.MODELS, "bodytoy", _body_toy())
    s = configure.load(root / "config.yaml", [root / "config/paper.yaml"])  # parsed again: the toy registered
    assert models.figure_body() == "bodytoy" and ode_name != "bodytoy"
    drawn = options.figure_options(s, "fig1")["figure_robot"]
    assert (drawn["engine"], drawn["robot"], drawn["figure_body"]) == ("Toy", "project", "toy_body:BODY")

    shots = [render_robot(d["figure_body"], width=160, height=120) for d in (drawn, ode)]
    assert set(shots[0].labels) == {"toy box", "toy sensor 1", "toy sensor 2"}  # the toy's parts, no wheel
    assert "castor" in shots[1].labels and not np.array_equal(shots[0].rgb, shots[1].rgb)

    # the figure itself: Fig. 1C's caption says the toy's words, its picture differs from the ODE body's
    out = tmp_path / "fig1"
    out.mkdir()
    files = {"png": str(out / "fig1.png"), "pdf": str(out / "fig1.pdf"), "caption": str(out / "fig1.caption.md")}
    params = options.figure_options(s, "fig1") | files | {"style": str(root / "notebooks/style.mplstyle")}
    papermill.execute_notebook(
        str(root / "notebooks/fig1.ipynb"), str(out / "fig1.ipynb"), parameters=json.loads(json.dumps(params)),
        cwd=str(root), progress_bar=False,
    )  # fmt: skip
    caption = (out / "fig1.caption.md").read_text()
    assert "the toy's box with two sensor spheres (red)" in caption and "as Toy simulates it" in caption
    committed = mpimg.imread(root / "results/paper/figures/fig1.png")
    mine = mpimg.imread(out / "fig1.png")
    assert mine.shape == committed.shape and not np.array_equal(mine, committed)
    sys.modules.pop("toy_body", None)  # the body's module goes with its folder
