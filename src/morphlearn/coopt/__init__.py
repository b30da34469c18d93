"""Co-optimising the body against a richer controller (issue 27; beyond the paper).

``landscape``: M_L and M_CF of the four-synapse controller space of a design (grid over four
weights). ``setups``: the learners' search spaces (fixed or co-optimised body, two or four weights).
``experiment``: the learner runs of the paper's comparison and their statistics.
"""
