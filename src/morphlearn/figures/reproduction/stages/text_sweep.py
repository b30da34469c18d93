"""Rows of the second theory sweep (config ``text_sweep_from``): the paper's text values as a sweep
of every design at 11 x 11 weights and a horizon of 1000 answers them (results/theory-text).

Its set-up was inferred from the text values themselves (they read as fractions of 121 and 25
controllers; the horizon from the paper's "10^5 timesteps"), so a value it reproduces gets the
verdict ``verdict.INFERRED``, weaker evidence than an independent reproduction. Each row's note
says over which horizons of :data:`HORIZONS` the verdict holds, so how far the answer rests on the
horizon is read beside it.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from morphlearn import grid as gridmod
from morphlearn.figures import data as fd
from morphlearn.figures.reproduction.claims import CLAIMS, NOTE_SEP, Claim
from morphlearn.figures.reproduction.inputs import TableInputs
from morphlearn.figures.reproduction.verdict import DIFFERS, inferred, verdict
from morphlearn.theory import text_sweep

#: The horizons each row's verdict is checked at (the project's 500 to the paper's 1000).
HORIZONS = tuple(float(h) for h in range(500, 1001, 10))
#: The model column of these rows.
MODEL = "theory: second sweep (11 x 11)"
#: The paper's claims these rows answer (claims.CLAIMS keys), in table order.
KEYS = (
    "theory_canonical_M_L",
    "theory_canonical_M_CF",
    "theory_paper_best_M_L",
    "theory_paper_best_M_CF",
    "theory_best_design",
    "theory_best_M_L_with_M_CF_1",
    "theory_persistence_canonical",
)
#: Why a row of the second sweep differs (a sentence; docs/results.md says more under ANCHOR).
REASON = "The second sweep does not give the paper's value at its horizon (its note: at which horizons it would)."
PERSISTENCE_REASON = (
    "The paper states no rule for staying near; the project's gives another count, and the note says which "
    "thresholds give the paper's."
)
ANCHOR = "text-sweep"


def _value(key: str, v: text_sweep.TextValues, g: gridmod.DesignGrid) -> tuple[str, float | bool | None]:
    """A claim's answer at one horizon: (text, the value the verdict compares)."""
    pb = f"{v.paper_best_generalists} generalists, {v.paper_best_solvers} controllers solving one or more"
    can = f"{v.canonical_generalists} generalists, {v.canonical_solvers} controllers solving one or more"
    if key == "theory_canonical_M_L":
        return f"{v.canonical_ml:.4g} ({can})", v.canonical_ml
    if key == "theory_canonical_M_CF":
        return f"{v.canonical_mcf:.4g} ({can})", v.canonical_mcf
    if key == "theory_paper_best_M_L":
        return f"{v.paper_best_ml:.4g} ({pb})", v.paper_best_ml
    if key == "theory_paper_best_M_CF":
        return f"{v.paper_best_mcf:.4g} ({pb})", v.paper_best_mcf
    if key == "theory_best_design":
        c = g.coords(v.best_design)
        paper = g.index_of(*gridmod.PAPER_BEST_DESIGN)
        gen = v.best_ml
        return (
            f"{fd.design_label(c[:2], c[2:])}, M_L = {gen:.4g}",
            bool(math.isclose(v.paper_best_ml, gen) or g.same_pair(paper, v.best_design)),
        )
    if key == "theory_best_M_L_with_M_CF_1":
        if not v.cf1_designs:
            return f"no design (the largest M_CF is {v.max_mcf:.4g})", None
        return f"{v.cf1_best_ml:.4g} ({v.cf1_designs} designs at M_CF = 1)", v.cf1_best_ml
    raise KeyError(key)


def _held(claim: Claim, said: float | bool | None) -> bool:
    return said is not None and verdict(claim.kind, claim.value, said)[0] != DIFFERS


def _horizons_note(claim: Claim, scan: list[tuple[float, bool]]) -> str:
    """Where over :data:`HORIZONS` the claim's value is reproduced (as intervals of the scan)."""
    spans, start, prev = [], None, None
    for h, ok in scan:
        if ok and start is None:
            start = h
        if not ok and start is not None:
            spans.append((start, prev))
            start = None
        prev = h
    if start is not None:
        spans.append((start, prev))
    where = ", ".join(f"{a:g}" if a == b else f"{a:g}-{b:g}" for a, b in spans)
    step = HORIZONS[1] - HORIZONS[0]
    head = f"second sweep at horizons {HORIZONS[0]:g}-{HORIZONS[-1]:g} (steps of {step:g})"
    if not where:
        return f"{head}: the verdict rule gives the paper's {claim.paper} at none"
    return f"{head}: the verdict rule gives the paper's {claim.paper} at {where}"


def persistence(
    ft: np.ndarray, w: np.ndarray, g: gridmod.DesignGrid, s: fd.TheorySettings, near: float
) -> tuple[int, int, list[float]]:
    """The canonical design's generalists at the sweep's horizon, each integrated by the reference
    solver to the horizon in all four environments: (staying within ``near`` after success,
    generalists, their largest distances after success sorted)."""
    design = gridmod.canonical_design()
    o = (np.nan_to_num(ft[g.index_of(*design)], nan=np.inf) <= s.horizon).sum(axis=0)
    far = []
    for i, j in zip(*np.nonzero(o == 4), strict=True):
        trs = fd.trajectories(design, (float(w[i]), float(w[j])), s)
        far.append(max(fd.max_distance_after_success(t) for t in trs))
    far.sort()
    return sum(d <= near for d in far), len(far), far


def _persistence_row(claim: Claim, stay: int, n: int, far: list[float], near: float) -> tuple[str, float | None, str]:
    """(ours, value, the thresholds of "near" that give the paper's count)."""
    if not n:
        return "no generalist", None, ""
    k, of = (int(x) for x in claim.paper.split(" of "))
    rule = f"stays near: after its first success the centre never again farther than {near:g} from the light"
    if of == n and 0 < k <= n:
        lo, hi = far[k - 1], far[k] if k < n else math.inf
        rule += f"; {k} of {n} stay near for every threshold from {lo:.3g} to below {hi:.3g}"
    return f"{stay} of {n}", stay / n, f"{rule} (largest distances after success: {', '.join(f'{d:.3g}' for d in far)})"


def text_rows(bundle: str | Path, near: float) -> list[dict[str, str]]:
    """The rows of the second sweep read from its bundle (every design's first-success times)."""
    ft, w, g, science = text_sweep.load_first_times(Path(bundle) / "theory" / "merged.zarr")
    th = science["theory"]
    r, horizon, radius = float(th["r"]), float(th["horizon"]), float(th["success_radius"])
    at = text_sweep.text_values(ft, g, horizon, r)
    scan = [text_sweep.text_values(ft, g, h, r) for h in HORIZONS if h <= horizon]
    config = (
        f"second theory sweep ({bundle}): all {g.size} designs at {len(w)} x {len(w)} weights, r = {r:g}, "
        f"horizon {horizon:g}, success radius {radius:g}, {th['integrator']} at rtol = atol = {th['rtol']:g}; "
        "its set-up inferred from the paper's text values"
    )
    claims = {c.key: c for c in CLAIMS}
    out = []
    for key in KEYS:
        claim = claims[key]
        note = ""
        if key == "theory_persistence_canonical":
            stay, n, far = persistence(ft, w, g, fd.TheorySettings(r=r, horizon=horizon, radius=radius), near)
            text, value, note = _persistence_row(claim, stay, n, far, near)
        else:
            text, value = _value(key, at, g)
            note = _horizons_note(claim, [(v.horizon, _held(claim, _value(key, v, g)[1])) for v in scan])
        said, why = verdict(claim.kind, claim.value, value)
        out.append(
            {
                "key": f"{key}_text_sweep",
                "section": "paper",
                "model": MODEL,
                "quantity": claim.quantity,
                "paper": claim.paper,
                "source": claim.source,
                "ours": text,
                "verdict": inferred(said),
                "reason": (PERSISTENCE_REASON if key == "theory_persistence_canonical" else REASON)
                if said == DIFFERS
                else why,
                "anchor": ANCHOR if said == DIFFERS else "",
                "config": config,
                "note": NOTE_SEP.join(x for x in (note,) if x),
            }
        )
    return out


def rows(t: TableInputs) -> list[dict[str, str]]:
    """The second sweep's rows, when the config reads one (``text_sweep_from``)."""
    if t.text_sweep is None:
        return []
    return text_rows(t.text_sweep, t.near)
