# Config validation (one-line error, exit 2, nothing written) and shared helpers.
import sys

from morphlearn import config as cfgmod
from morphlearn import pipeline

try:
    CFG = cfgmod.validate(config)
except cfgmod.ConfigError as err:
    print(f"morphlearn: config error: {err}", file=sys.stderr)
    sys.exit(2)

R = CFG["results_dir"]
MODELS = pipeline.models(CFG)
SHARDS = {m: pipeline.shard_designs(CFG, m) for m in MODELS}


def shard_ids(model):
    return range(len(SHARDS[model]))


def shard_params(model):
    """Rerun triggers: a shard depends on the science subset and on the designs it holds."""
    return lambda w: {
        "science": cfgmod.digest(pipeline.science(CFG, model)),
        "designs": cfgmod.digest(SHARDS[model][int(w.shard)].tolist()),
    }


ALL_TARGETS = [
    *(f"{R}/{m}/metrics.csv" for m in MODELS),
    f"{R}/summary.md",
]
