"""Shared drawing primitives, one module per kind of panel, so that a figure's rule depends only
on the primitives its notebook imports (see morphlearn.figures.registry):

- :mod:`.panel`: panel letters and the empty "not in this run" panel (every figure);
- :mod:`.sketch`: robot sketches (Figs. 1, 3 and the trajectory starts);
- :mod:`.matrix`: weight-grid matrices, the overlap colour map (Figs. 2, 6);
- :mod:`.trajectory`: theory trajectories in the four environments (Figs. 4, 5);
- :mod:`.distribution`: a metric's distribution over designs, seaborn (Fig. 7).

Conventions: body frame +x forward (drawn to the right), +y left (up); weight-grid images have w1
on the x axis and w2 on the y axis. Sizes and fonts come from notebooks/style.mplstyle.
"""
