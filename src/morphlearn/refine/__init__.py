"""The committed refine folders, read-only history (issue 58: every result is now made by
the workflow's rules): their reader and checks (:mod:`.folder`), a workflow design seeded from one
(:mod:`.seed`), and ``morphlearn refine`` (:mod:`.cli`: status, assemble, seed).

Nothing is imported here: import the submodules.
"""
