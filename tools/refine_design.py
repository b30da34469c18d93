#!/usr/bin/env python
"""One empirical (pybullet) design on an exhaustive weight grid, resumable row by row.

  run:       refine_design.py run --design-l1 0.5 0.5 --design-l2 0.5 -0.5 --weights 121 \\
                 --out /work/runs/refine/canonical_121/
             (the same command resumes: finished rows are verified and skipped)
  status:    refine_design.py status /work/runs/refine/canonical_121/
  assemble:  refine_design.py assemble /work/runs/refine/canonical_121/ [--write]
             (metrics of the rows done; --write also saves result.npz and summary.json there)

Levers: early stop (exact, docs/empirical_levers.md) on unless --no-early-stop; never the
adaptive weight grid (this is the reference it is measured against). See
morphlearn.empirical.resumable for the folder layout.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

from morphlearn.empirical import resumable as rz
from morphlearn.empirical.options import SweepOptions
from morphlearn.empirical.params import load_params


def _log(msg: str) -> None:
    from datetime import UTC, datetime

    print(f"[{datetime.now(UTC).strftime('%H:%M:%S')}] {msg}", flush=True)


def cmd_run(a: argparse.Namespace) -> int:
    try:
        params = load_params(a.body)
    except ValueError as e:
        raise rz.RefineError(f"--body {a.body}: {e}") from None
    if a.steps is not None:
        try:
            params = params.replace(steps=a.steps)
        except ValueError as e:
            raise rz.RefineError(f"--steps: {e}") from None
    job = rz.Job(l1=tuple(a.design_l1), l2=tuple(a.design_l2), m=a.weights, params=params,
                 options=SweepOptions(early_stop=not a.no_early_stop))  # fmt: skip
    try:
        rz.run(a.out, job, body_file=a.body, max_rows=a.max_rows, log=_log)
    except KeyboardInterrupt:
        return 130
    return 0


def cmd_status(a: argparse.Namespace) -> int:
    asm = rz.assemble(a.folder, log=_log)
    s, c = rz.summary(asm), rz.cost(a.folder)
    man = asm.manifest
    ident = man["identity"]
    print(f"{a.folder}: design l1={ident['design']['l1']} l2={ident['design']['l2']}, "
          f"{ident['weights']} x {ident['weights']} weights, levers {ident['levers'] or 'none'}")  # fmt: skip
    print(f"  rows {s['rows_done']}/{s['rows']} ({s['fraction_done']:.1%}), {s['episodes']} episodes, "
          f"{'complete' if s['complete'] else 'PARTIAL'}")  # fmt: skip
    if c["rows_logged"]:
        left = (s["rows"] - s["rows_done"]) * 4 * s["rows"] / c["episodes_per_wall_s"]
        print(f"  cost: {c['episodes_per_wall_s']:.2f} episodes/wall-s, {c['episodes_per_cpu_s']:.2f} episodes/CPU-s "
              f"over {c['rows_logged']} rows logged; ~{left / 3600:.2f} h left at that rate")  # fmt: skip
    dm = s["metrics_over_rows_done"]
    print(f"  over the rows done: generalists {dm['generalists']} of {s['episodes'] // 4} cells, "
          f"at least one {dm['at_least_one']}, per env {dm['per_env']}, M_L {dm['M_L']:.6g}, "
          f"M_CF {dm['M_CF']:.6g}, flagged {dm['flagged']}; {s['steps_per_episode']:.0f} steps/episode")  # fmt: skip
    if "mirror" in s:
        mi = s["mirror"]
        print(f"  mirror (self-mirror design): {mi['pairs_flipped']} of {mi['pairs_compared']} cell pairs "
              "differ in success")  # fmt: skip
    return 0


def cmd_assemble(a: argparse.Namespace) -> int:
    asm = rz.assemble(a.folder, log=_log)
    s = rz.summary(asm) | {"cost": rz.cost(a.folder), "run_key": asm.manifest["run_key"]}
    print(json.dumps(s, indent=1, sort_keys=True))
    if a.write:
        folder = Path(a.folder)
        d = asm.result
        np.savez_compressed(folder / "result.npz", first_time=d.first_time, min_dist=d.min_dist,
                            status=d.status, steps=asm.steps, rows_done=asm.rows_done,
                            weights=rz.job_from_manifest(asm.manifest).weights)  # fmt: skip
        (folder / "summary.json").write_text(json.dumps(s, indent=1, sort_keys=True) + "\n")
        print(f"wrote {folder / 'result.npz'} and {folder / 'summary.json'} "
              f"({'complete' if asm.complete else 'PARTIAL'})", file=sys.stderr)  # fmt: skip
    return 0


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("run", help="compute (or resume) a design's rows")
    r.add_argument("--design-l1", nargs=2, type=float, required=True, metavar=("X", "Y"))
    r.add_argument("--design-l2", nargs=2, type=float, required=True, metavar=("X", "Y"))
    r.add_argument("--weights", type=int, required=True, help="weights per synapse (121: the paper's grid)")
    r.add_argument("--out", type=Path, required=True)
    r.add_argument("--body", type=Path, default=Path("config/empirical_morphology.yaml"))
    r.add_argument("--steps", type=int, default=None, help="override the body's horizon in steps (tests)")
    r.add_argument("--no-early-stop", action="store_true", help="run every episode to contact or horizon")
    r.add_argument("--max-rows", type=int, default=None, help="stop after this many new rows")
    r.set_defaults(fn=cmd_run)
    s = sub.add_parser("status", help="progress, cost and metrics so far")
    s.add_argument("folder", type=Path)
    s.set_defaults(fn=cmd_status)
    m = sub.add_parser("assemble", help="the rows done as one design's result and metrics (JSON)")
    m.add_argument("folder", type=Path)
    m.add_argument("--write", action="store_true", help="also write result.npz and summary.json in the folder")
    m.set_defaults(fn=cmd_assemble)
    a = ap.parse_args(argv)
    try:
        return a.fn(a)
    except rz.RefineError as e:
        print(f"refine_design: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
