"""The apps: the command line (:mod:`.cli`) and the interactive explorer (:mod:`.explore`, its
widgets :mod:`.explore_app`).

Nothing is imported here: import the submodules.
"""
