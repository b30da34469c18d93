"""Re-simulating a bundle's designs and comparing them with its stored rows and arrays, bit for bit
(``morphlearn check-bundle --resimulate``). Any registered model that can re-make its results
from its science record (:meth:`morphlearn.model_interface.Model.resimulate`): the theory in
seconds, a physics engine's design on request (its levers as the run recorded them)."""

from __future__ import annotations

import secrets
from collections.abc import Callable, Iterable
from pathlib import Path

import numpy as np
import pandas as pd

from morphlearn import grid as gridmod
from morphlearn import metrics, models, provenance, store
from morphlearn.bundles.check import meaning_problems
from morphlearn.bundles.make import BundleError

#: What names designs (after an optional ``MODEL:``).
_NAMED = ("canonical", "best_M_L", "best_M_CF")


def parse_which(which: str, flag: str = "re-simulate") -> tuple[str, str]:
    """``[MODEL:]WHICH`` -> (model, which): the model a registered name (default: the reference
    model), WHICH one of canonical, best_M_L, best_M_CF, a design index or sample:K. Raises
    BundleError naming ``flag``, the value and what is allowed (the range of an index or K is
    checked with the table)."""
    head, _, rest = which.partition(":")
    model, spec = (head, rest) if head in models.MODELS else (models.REFERENCE, which)
    k = spec.removeprefix("sample:")
    if spec in _NAMED or spec.isdigit() or (spec.startswith("sample:") and k.isdigit()):
        return model, spec
    raise BundleError(
        f"{flag} {which!r}: allowed: [MODEL:]WHICH, MODEL one of {', '.join(models.MODELS)} "
        f"(default {models.REFERENCE}), WHICH one of {', '.join(_NAMED)}, a design index >= 0 or sample:K"
    )


#: Largest seed of a ``sample:K`` draw (drawn afresh each run unless given).
MAX_SEED = 2**63 - 1


def fresh_seed() -> int:
    """A seed no one can know before the run (the operating system's randomness)."""
    return secrets.randbelow(MAX_SEED + 1)


def resimulate(
    out_dir: str | Path,
    which: Iterable[str] = ("canonical", "best_M_L"),
    *,
    seed: int | None = None,
    say: Callable[[str], None] | None = None,
) -> list[str]:
    """Re-simulate designs of a bundle from its recorded science and compare with it.

    ``which``: ``[MODEL:]WHICH`` (:func:`parse_which`); ``sample:K`` draws K designs at random from
    all rows of that model's table, with ``seed`` (default: a fresh one, :func:`fresh_seed`: a
    forger who reads the code cannot know which rows will be drawn; issue 57, where seed 0 always
    drew the same ones). ``say`` is told the seed, the designs drawn and the chance that K rows
    catch a forgery of one design, so a failure can be replayed. Each design's metrics row (counts
    per environment, generalists, flagged) and, when the bundle holds them, its stored outcome
    arrays must come out exactly; the problems found are returned (empty: every design agrees). The
    thresholds are the ones the bundle's metrics were computed with (its provenance record).
    """
    out_dir = Path(out_dir)
    by_model: dict[str, list[str]] = {}
    for w in which:
        model, spec = parse_which(w)
        by_model.setdefault(model, []).append(spec)
    if seed is None:
        seed = fresh_seed()
    elif not 0 <= seed <= MAX_SEED:
        raise BundleError(f"--seed = {seed}; allowed: an integer 0 to {MAX_SEED}")
    rng = np.random.default_rng(seed)
    problems = []
    for model, specs in by_model.items():
        problems += _resimulate_model(out_dir, model, specs, rng, seed, say or (lambda _: None))
    return problems


def sample_chance(k: int, n: int) -> float:
    """The chance that ``k`` rows drawn without replacement from ``n`` include one given row."""
    return k / n if n else 0.0


def _resimulate_model(
    out_dir: Path, model: str, which: list[str], rng: np.random.Generator, seed: int, say: Callable[[str], None]
) -> list[str]:
    m = models.get(model)
    folder = out_dir / model
    if not (folder / "merged.zarr").is_dir():
        return [f"{folder}: no {model} results in this bundle (allowed models here: {_held_models(out_dir)})"]
    merged = store.open_merged(folder / "merged.zarr")
    sci = store.science_of(merged)
    table = pd.read_csv(folder / "metrics.csv")
    prov = provenance.read_record(folder / "metrics.provenance.json")
    th = metrics.Thresholds(**prov["config"]["thresholds"])
    g = gridmod.DesignGrid(m.positions_of(sci))
    wanted = []
    for w in which:
        got = _designs_of(w, table, g, rng)
        if w.startswith("sample:"):
            p = sample_chance(len(got), len(table))
            say(
                f"{model} {w}: designs {got} drawn with seed {seed} (replay: --seed {seed}); a forged row of one "
                f"design is among them with chance {len(got)}/{len(table)} = {p:.3g}"
            )
        wanted += got
    # the table's meaning first (check-bundle's check): a row whose coordinates are not its
    # design's would otherwise pass, the design being simulated at its index's coordinates
    meaning = [f"{folder}/metrics.csv: {p}" for p in meaning_problems(folder / "metrics.csv", table)]
    held = set(int(d) for d in merged["design"].values)
    # any row of the table, held or not: an edited row of a design whose arrays the bundle does
    # not hold is caught too (a forger has to re-simulate); the arrays are compared where held
    problems = meaning + [
        f"{model} design {d}: no row in {folder}/metrics.csv" for d in wanted if d not in set(table.design)
    ]
    todo = sorted({d for d in wanted if d in set(table.design)})
    if not todo:
        return problems
    try:
        results = m.resimulate(sci, np.array(todo, dtype=np.int64))
    except (NotImplementedError, ValueError) as e:
        return [*problems, f"{model}: cannot re-simulate ({e})"]
    for d, res in zip(todo, results, strict=True):
        dm = metrics.design_metrics(metrics.success(res.first_time, res.min_dist, th), res.status)
        row = table[table.design == d].iloc[0]
        stored = [
            *(int(row[f"n_{a}"]) for a in gridmod.ENV_ANGLES_DEG),
            int(row.generalists),
            int(row.at_least_one),
            int(row.flagged),
        ]
        fresh = [*dm.per_env, dm.generalists, dm.at_least_one, dm.flagged]
        if stored != fresh:
            problems.append(
                f"{model} design {d}: metrics row {stored} (per env, generalists, at least one, "
                f"flagged) but re-simulated {fresh}"
            )
        elif [row.M_L, row.M_CF] != [float(metrics.CSV_FLOAT_FORMAT % x) for x in (dm.M_L, dm.M_CF)]:
            problems.append(
                f"{model} design {d}: metrics row M_L, M_CF = {row.M_L}, {row.M_CF} but re-simulated "
                f"{dm.M_L}, {dm.M_CF}"
            )
        if d not in held:
            continue
        one = store.read_design(merged, list(merged["design"].values).index(d))
        for v in store.VARS:
            a, b = one[v], getattr(res, v)
            differ = a != b
            if a.dtype.kind == "f":  # NaN (never succeeded, or not simulated) equals NaN here
                differ &= ~(np.isnan(a) & np.isnan(b))
            if differ.any():
                problems.append(
                    f"{model} design {d}: stored {v} differs from the re-simulation in {int(differ.sum())} cells"
                )
    return problems


def _held_models(out_dir: Path) -> str:
    return ", ".join(n for n in models.MODELS if (out_dir / n / "merged.zarr").is_dir()) or "none"


def _designs_of(which: str, table: pd.DataFrame, g: gridmod.DesignGrid, rng: np.random.Generator) -> list[int]:
    if which == "canonical":
        return [g.index_of(*gridmod.canonical_design())]
    if which in ("best_M_L", "best_M_CF"):
        return [int(metrics.rank_designs(table, which.removeprefix("best_")).design.iloc[0])]
    if which.isdigit():
        if int(which) >= g.size:  # a usage error (exit 2 on the command line), not a missing row
            raise BundleError(
                f"--resimulate {which!r}: no design {which} on this bundle's grid; allowed: a design index "
                f"0 to {g.size - 1} ({g.n} positions per axis), canonical, best_M_L, best_M_CF or sample:K"
            )
        return [int(which)]
    k = which.removeprefix("sample:")
    if which.startswith("sample:") and k.isdigit() and 0 < int(k) <= len(table):
        return sorted(int(d) for d in rng.choice(table.design.to_numpy(), size=int(k), replace=False))
    raise BundleError(
        f"re-simulate {which!r}: allowed: canonical, best_M_L, best_M_CF, a design index or sample:K "
        f"(1 <= K <= {len(table)})"
    )
