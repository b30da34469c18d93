"""Figures that show what their captions say (issue 59): the marks a caption names visible at print
size (a single generalist ringed, not one cyan pixel), panel letters clear of titles, axes fitted
to the data, every trajectory figure naming its model and design, Fig. 1C the robot the headline
numbers use (the registry's ``figure_body``: the authors' robot in ODE), captions that say what is
drawn (Fig. 7's weight grid, Fig. 5 without doubled parentheses). The notebooks whose captions are
checked are executed on the committed paper bundle (read only) into a temporary folder."""

from __future__ import annotations

import json
import math
from pathlib import Path
from types import SimpleNamespace

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pytest
import yaml
from conftest import ROOT

from morphlearn import configure, models
from morphlearn.figures import caption as cap
from morphlearn.figures import data, options
from morphlearn.figures.draw import matrix, panel, trajectory

BUNDLE = ROOT / "results/paper"
W121 = np.linspace(-1.0, 1.0, 121)


def test_a_single_generalist_is_ringed_whole_in_its_corner() -> None:
    """Fig. 6 D: the canonical design's one generalist in ODE, at w = (1, 1), was one cyan cell of
    121 x 121 in a corner; it is ringed, drawn whole over the edge, and the title clears it. Many
    generalists show as cyan areas and are not ringed."""
    fig, (a, b) = plt.subplots(1, 2)
    o = np.zeros((121, 121), int)
    o[120, 120] = 4
    matrix.overlap_image(a, o, W121, "one")
    rings = [ln for ln in a.lines if ln.get_marker() == "o"]
    assert len(rings) == 1 and rings[0].get_xydata().tolist() == [[1.0, 1.0]] and not rings[0].get_clip_on()
    assert rings[0].get_markersize() >= 8  # a point at print size, not a 1/121 of the panel
    many = np.zeros((121, 121), int)
    many[:30, :30] = 4
    matrix.overlap_image(b, many, W121, "many")
    assert not [ln for ln in b.lines if ln.get_marker() == "o"]
    fig.canvas.draw()
    ring = rings[0].get_window_extent(fig.canvas.get_renderer())
    assert a.title.get_window_extent().y0 > ring.y1  # the title clear of the ring
    plt.close(fig)


def test_the_panel_letter_is_clear_of_a_wide_multiline_title() -> None:
    """Fig. 6 D: "DM_L = ...": the letter sat level with a centred title's last line, which runs
    past the axes; it now sits level with the title's first line, left of the axes."""
    fig, ax = plt.subplots(figsize=(4, 4), layout="constrained")
    ax.set_title("ODE (121 x 121), canonical\nl1 = (0.5, 0.5), l2 = (0.5, -0.5)\nM_L = 6.83e-05, M_CF = 0.0005236 0000")
    panel.panel_letter(ax, "D")
    fig.canvas.draw()
    r = fig.canvas.get_renderer()
    letter = next(t for t in ax.texts if t.get_text() == "D").get_window_extent(r)
    title = ax.title.get_window_extent(r)
    # level with the title's first line (not its last, which runs past the axes), left of the axes
    assert abs(letter.y1 - title.y1) < 3
    assert letter.y0 > title.y1 - title.height / 3 - 3 and letter.x1 <= ax.get_window_extent(r).x0
    plt.close(fig)


def test_axes_fitted_to_the_data() -> None:
    """The survey figure drew maxima of 0.0038 and 0.038 on axes to 0.006 and 0.06 (room for a
    legend on top of the points); fitted, the legend outside."""
    fig, ax = plt.subplots()
    panel.fit_to_data(ax, np.array([0.0, 0.15]), np.array([0.0, 0.0038]))
    assert ax.get_ylim()[1] == pytest.approx(0.0038 * 1.06) and ax.get_xlim()[1] == pytest.approx(0.15 * 1.06)
    panel.fit_to_data(ax, np.zeros(3), np.zeros(3))  # nothing above 0: a small range round it
    assert ax.get_ylim()[0] < 0 < ax.get_ylim()[1]
    plt.close(fig)


def _path(speed: float, first: float) -> SimpleNamespace:
    t = np.linspace(0.0, 500.0, 5001)
    return SimpleNamespace(t=t, path=np.column_stack([4.0 - speed * t, 0 * t]), first_time=first)


def test_trajectory_figures_show_speed_and_name_their_design() -> None:
    """Fig. 5's three controllers run nearly the same paths (true: checked in this issue; their
    first successes come at t = 150-161, 174-203 and 376-434); dots every TIME_DOTS time units up to
    the first success show the difference, the titles give the times, the figure names its model
    and design."""
    fast, slow = _path(0.025, 150.0), _path(0.01, 400.0)
    assert len(trajectory.time_dots(fast)) == 2 and len(trajectory.time_dots(slow)) == 7
    assert trajectory.time_dots(slow)[0].tolist() == pytest.approx([3.5, 0.0])
    never = _path(0.001, math.nan)
    assert len(trajectory.time_dots(never)) == 9  # to the horizon
    assert trajectory.first_times([fast, slow, never]) == "t = 150-400"
    assert trajectory.first_times([never]) == "no success"
    fig, _ = plt.subplots()
    trajectory.design_title(fig, "theory", "the best design by M_L", ((-0.5, -0.375), (0.5, 0.375)))
    assert fig.get_suptitle() == "theory, the best design by M_L: l1 = (-0.5, -0.375), l2 = (0.5, 0.375)"
    plt.close(fig)


def test_fig1_draws_the_robot_of_the_registry_figure_body() -> None:
    """The headline numbers are the authors' robot's in ODE: Fig. 1C draws that robot (it drew the
    project's pybullet body), as the registry's figure_body says, with the body the registry names
    for it: ODE has no renderer, so pybullet's build of the authors' robot (Physics.figure_bodies)."""
    from morphlearn.figures.render import render_robot
    from morphlearn.physics.body import FigureBody, load

    assert models.figure_body() == "ode" and models.get("ode").paper_engine
    s = configure.load(ROOT / "config.yaml", [ROOT / "config/paper.yaml"])
    drawn = options.figure_options(s, "fig1")["figure_robot"]
    assert (drawn["engine"], drawn["robot"], drawn["robot_label"]) == ("ODE", "authors", "the authors' robot")
    assert drawn["body"]["body_mass"] == yaml.safe_load((ROOT / "config/authors_body.yaml").read_text())["body_mass"]
    assert drawn["figure_body"] == models.get("empirical").figure_bodies["authors"]  # type: ignore[attr-defined]
    assert not models.get("ode").figure_bodies  # type: ignore[attr-defined]
    # the disagreement figure keeps the reference engine's body (the one both engines simulated there)
    assert models.reference_physics() == "empirical"
    from morphlearn.physics.params import EmpiricalParams

    p = EmpiricalParams.from_mapping(drawn["body"])
    shot = render_robot(drawn["figure_body"], p, width=160, height=120)
    assert shot.rgb.shape == (120, 160, 3) and set(shot.labels) >= {"sensor 1", "sensor 2", "castor", "light"}
    # the notebook run on its own: the reference engine's first robot, its own body
    alone = options.figure_robot()
    own = models.get("empirical").figure_bodies["project"]  # type: ignore[attr-defined]
    assert (alone["engine"], alone["robot"], alone["body"], alone["figure_body"]) == ("pybullet", "project", None, own)
    assert isinstance(load(alone["figure_body"]), FigureBody)
    with pytest.raises(LookupError, match="no registered engine builds the 'nobody' robot"):
        models.figure_body_path("ode", "nobody")
    with pytest.raises(TypeError, match=r"allowed: a morphlearn\.physics\.body\.FigureBody"):
        render_robot("morphlearn.physics.body:GREY", p)


def test_paper_design_note_is_one_sentence_not_a_second_parenthesis() -> None:
    theory = data.load_results(BUNDLE, "theory", None)
    ours = data.row_design(theory.best("M_L"))
    note = cap.paper_design_note(theory, ours, data.PAPER_BEST_DESIGN)
    assert note == " The paper's design is l1 = (-0.5, -0.25), l2 = (0.5, 0.25); this run ranks it 21st by M_L."
    assert cap.paper_design_note(theory, ours, ours) == ""


# -- the captions, rendered from the committed paper bundle -----------------------------------


@pytest.fixture(scope="module")
def rendered(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Figs. 5, 6, 7 and the survey figure of results/paper (config/paper.yaml's options), rendered
    into a temporary folder: about a minute."""
    import papermill

    out = tmp_path_factory.mktemp("figures")
    s = configure.load(ROOT / "config.yaml", [ROOT / "config/paper.yaml"])
    for fig in ("fig5", "fig6", "fig7", "survey"):
        params = options.figure_options(s, fig) | {
            "results_dir": str(BUNDLE),
            "png": str(out / f"{fig}.png"),
            "pdf": str(out / f"{fig}.pdf"),
            "caption": str(out / f"{fig}.caption.md"),
            "style": str(ROOT / "notebooks/style.mplstyle"),
        }
        params = json.loads(json.dumps(params))  # plain types for papermill
        papermill.execute_notebook(
            str(ROOT / f"notebooks/{fig}.ipynb"), str(out / f"{fig}.ipynb"), parameters=params, cwd=str(ROOT)
        )
    return out


def test_captions_say_what_is_drawn(rendered: Path) -> None:
    fig7 = (rendered / "fig7.caption.md").read_text()
    assert "its M_L counts generalists among 121 x 121 = 14641 controllers, the paper's weight grid." in fig7
    assert "not the paper's 121 x 121" not in fig7  # 14,641 is 121 x 121
    fig5 = (rendered / "fig5.caption.md").read_text()
    assert ") (l1 =" not in fig5 and "))" not in fig5.split("**Data and config.**")[0].replace("(0.25))", "")
    assert (
        "Trajectories of the design with the highest M_L in this run, l1 = (-0.5, -0.375), l2 = (0.5, 0.375)," in fig5
    )
    assert "dots every 50 time units" in fig5 and "at t = 159, 150, 161, 152" in fig5
    fig6 = (rendered / "fig6.caption.md").read_text()
    assert "theory (A-C) and ODE (D-F)" in fig6 and "20 generalists or fewer, each is also ringed" in fig6
    assert (
        "**D:** ODE, 121 x 121 weights, canonical: l1 = (0.5, 0.5), l2 = (0.5, -0.5), M_L = 6.83e-05 (1 of 14641"
        in fig6
    )
    survey = (rendered / "survey.caption.md").read_text()
    assert "forward = +x, to the right" in survey and "arrow" not in survey
    for fig in ("fig5", "fig6", "fig7", "survey"):
        assert (rendered / f"{fig}.png").stat().st_size > 20_000


def test_a_long_engine_label_breaks_the_panel_title() -> None:
    """Figs. 3 and 6 title a physics panel "<engine> (m x m), <what>"; one wider than the panel
    (the reduced model's) goes on two lines, the engines' titles committed bundles hold stay on one."""
    from morphlearn.figures import caption as cap

    assert cap.title_head("pybullet (121 x 121)", "best by M_CF", 34) == "pybullet (121 x 121), best by M_CF"
    both = "best by M_L and M_CF"
    assert cap.title_head("pybullet (121 x 121)", both, 42) == f"pybullet (121 x 121), {both}"
    assert cap.title_head("reduced model (121 x 121)", "best by M_CF", 34) == "reduced model (121 x 121),\nbest by M_CF"
