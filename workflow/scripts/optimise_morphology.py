"""Rule optimise_morphology: NSGA-II over the body, Pareto table + plot + chosen body."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821
from _entry import setup

setup(snakemake)  # noqa: F821
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from morphlearn import store  # noqa: E402
from morphlearn.empirical import optimise  # noqa: E402

budget = snakemake.params.budget  # noqa: F821
pareto, chosen = optimise.optimise(budget["evaluations"], budget["seed"], workers=snakemake.threads)  # noqa: F821
out = snakemake.output  # noqa: F821
with store.atomic_path(out.pareto) as tmp:
    pareto.to_csv(tmp, index=False)  # full precision: a row is a body (the dynamics are sensitive)
with store.atomic_path(out.chosen) as tmp:
    tmp.write_text(optimise.morphology_yaml(pareto, chosen, budget_evals=budget["evaluations"], seed=budget["seed"]))
fig, ax = plt.subplots(figsize=(5, 4), dpi=120)
front = pareto[pareto["pareto"]]
ax.plot(front["f_actuation"], front["f_distance"], "o-", label="Pareto set")
pick = pareto[pareto["chosen"]]
ax.plot(pick["f_actuation"], pick["f_distance"], "r*", ms=14, label="chosen")
ax.set_xlabel("actuation limits: max torque + max speed")
ax.set_ylabel("summed min distance to the light (4 envs)")
ax.legend()
fig.tight_layout()
with store.atomic_path(out.plot) as tmp:
    fig.savefig(tmp, format="png")
