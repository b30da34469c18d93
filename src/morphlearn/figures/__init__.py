"""Figures, captions and the reproduction table of the paper, from the workflow's results.

Each figure is drawn by its own notebook (``notebooks/figN.ipynb``, run by papermill from
``workflow/rules/figures.smk``; :mod:`.registry` lists them). The notebooks use:

- :mod:`.data`: load a model's results (metrics table + merged dataset), pick designs and
  controllers, theory trajectories and the "stays near the source" test;
- :mod:`.draw`: shared drawing primitives, one module per kind of panel;
- :mod:`.caption`: caption and provenance text;
- :mod:`.output`: the shared style, the readability check and writing PNG, PDF and caption;
- :mod:`.render`: the offscreen pybullet render of the simulated robot (Fig. 1C), the body its engine supplies.

:mod:`.reproduction` (a package) writes the paper-vs-ours table (CSV, Markdown, HTML) and the persistence count.
Nothing is imported here (so a figure's rule depends only on the modules its notebook imports):
import the submodules, e.g. ``from morphlearn.figures.data import load_results, ModelResults``.
"""
