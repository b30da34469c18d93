"""Rule engines_disagreement: the design where pybullet and MuJoCo disagree most, simulated again.

Settings: the ``engines`` config section (the tables' paths) and the physics body
(``empirical.morphology``). Inputs: the pybullet and MuJoCo survey metrics tables (checked against
their records; the design is picked from them and its generalist counts checked against them).
Outputs: ``disagreement.json`` (the design, its generalists per engine, the controller drawn, its
failed environments, steps and closest approaches), ``disagreement_success.npy`` (bool, engine x
env x w1 x w2) and ``disagreement_paths.npy`` (the drawn controller's centre paths). ~2-3 CPU-min.
"""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821
from _entry import setup

s = setup(snakemake)  # noqa: F821
from morphlearn import models  # noqa: E402
from morphlearn.analysis import engines as engine_compare  # noqa: E402

engine_compare.write_disagreement(
    s.engines,
    s.models[models.reference_physics()].params,
    snakemake.output.info,  # noqa: F821
    snakemake.output.success,  # noqa: F821
    snakemake.output.paths,  # noqa: F821
)
