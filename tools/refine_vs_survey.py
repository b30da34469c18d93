#!/usr/bin/env python
"""A refine_design folder against a committed survey store on the weights both share.

  refine_vs_survey.py /work/runs/refine/canonical_121 results/survey/empirical/merged.zarr

Every cell the survey simulated (status not ``inferred``) on a weight of both grids and in a row
the folder has done must agree bit for bit when both runs used the same body and exact levers
(early stop is exact; the adaptive grid only skips cells); the survey's inferred cells are where
its adaptive grid could miss successes, counted separately.
"""

from __future__ import annotations

import argparse
import json
import sys

import numpy as np

from morphlearn import metrics, store
from morphlearn import resumable as rz
from morphlearn.results import STATUS_INFERRED


def compare(folder: str, merged: str) -> dict[str, object]:
    asm = rz.assemble(folder)
    job = rz.job_from_manifest(asm.manifest)
    ds = store.open_merged(merged)
    sci = store.science_of(ds)
    if sci.get("params") != job.params.to_dict():
        raise rz.RefineError(f"{merged}: simulated with other body parameters than {folder}")
    cols = ["l1x", "l1y", "l2x", "l2y"]
    want = (*job.l1, *job.l2)
    hit = np.flatnonzero(np.all([ds[c].values == v for c, v in zip(cols, want, strict=True)], axis=0))
    if hit.size != 1:
        raise rz.RefineError(f"{merged}: holds no design l1={job.l1} l2={job.l2}")
    sv = ds["w1"].values if "w1" in ds else ds["weight"].values
    fine = job.weights
    # linspace(-1, 1, 11) is not bit-exact every 12th of linspace(-1, 1, 121) (+-0.4 differ by an
    # ulp): matched within 1e-12, and bit-identical outcomes are expected only where both weights
    # of a cell are exactly equal.
    idx = [
        int(np.flatnonzero(np.isclose(fine, w, rtol=0, atol=1e-12))[0])
        for w in sv
        if np.isclose(fine, w, rtol=0, atol=1e-12).any()
    ]
    if len(idx) != len(sv):
        raise rz.RefineError(f"{merged}: its weights are not a subset of the folder's {job.m}-point grid")
    exact_w = fine[idx] == sv
    s = store.read_design(ds, int(hit[0]))
    ix = np.ix_(range(4), idx, idx)
    rows_ok = asm.rows_done[idx]
    mine = {k: getattr(asm.result, k)[ix][:, rows_ok] for k in ("first_time", "min_dist", "status")}
    theirs = {k: s[k][:, rows_ok] for k in ("first_time", "min_dist", "status")}
    exact = np.broadcast_to((exact_w[rows_ok][:, None] & exact_w[None, :])[None], theirs["status"].shape)
    sim = theirs["status"] != STATUS_INFERRED
    both = sim & exact
    th = rz.thresholds(job.params)
    succ_m = metrics.success(mine["first_time"], mine["min_dist"], th)
    succ_t = metrics.success(theirs["first_time"], theirs["min_dist"], th)
    same = {
        k: int(
            (
                mine[k][both].view(np.uint8 if k == "status" else np.uint32)
                == theirs[k][both].view(np.uint8 if k == "status" else np.uint32)
            ).sum()
        )
        for k in ("first_time", "min_dist", "status")
    }
    return {
        "survey_rows_in_folder": int(rows_ok.sum()),
        "survey_rows": len(idx),
        "cells_compared": int(rows_ok.sum()) * len(idx) * 4,
        "survey_simulated": int(sim.sum()),
        "survey_simulated_with_bit_equal_weights": int(both.sum()),
        "bit_identical_there": same,
        "success_disagreements_where_survey_simulated": int((succ_m != succ_t)[sim].sum()),
        "success_disagreements_there_weights_1ulp_apart": int((succ_m != succ_t)[sim & ~exact].sum()),
        "successes_folder": int(succ_m.sum()),
        "successes_survey": int(succ_t.sum()),
        "successes_survey_missed_inferred": int((succ_m & ~sim).sum()),
        "generalists_folder_on_subgrid": int(succ_m.all(axis=0).sum()),
        "generalists_survey_on_these_rows": int(succ_t.all(axis=0).sum()),
        "survey_generalists_whole_11x11": int(metrics.success(s["first_time"], s["min_dist"], th).all(axis=0).sum()),
        "complete_on_subgrid": bool(rows_ok.all()),
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("folder")
    ap.add_argument("merged")
    a = ap.parse_args(argv)
    try:
        print(json.dumps(compare(a.folder, a.merged), indent=1))
    except rz.RefineError as e:
        print(f"refine_vs_survey: {e}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
