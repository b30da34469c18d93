"""Figures, captions and the reproduction table of the paper, from the workflow's results.

The notebooks in ``notebooks/`` (one per figure, run by papermill from
``workflow/rules/figures.smk``) only call these functions:

- :mod:`.data`: load a model's results (metrics table + merged dataset), pick designs and
  controllers, theory trajectories and the "stays near the source" test;
- :mod:`.draw`: matplotlib panels (robot sketches, success/overlap matrices, trajectories,
  distributions) and the empty "not in this run" panel;
- :mod:`.render`: the offscreen pybullet render of the simulated robot (Fig. 1C);
- :mod:`.make`: one function per figure returning the figure and its caption;
- :mod:`.reproduction`: the paper-vs-ours table (CSV, Markdown, HTML) and the persistence count.
"""

from morphlearn.figures.data import ModelResults, load_results
from morphlearn.figures.make import FIGURES, FigureOutput, make_figure, save_outputs

__all__ = ["FIGURES", "FigureOutput", "ModelResults", "load_results", "make_figure", "save_outputs"]
