#!/usr/bin/env python
"""One empirical (pybullet) design on an exhaustive weight grid, resumable row by row.

  run:       refine_design.py run --design-l1 0.5 0.5 --design-l2 0.5 -0.5 --weights 121 \\
                 --out /work/runs/refine/canonical_121/
             (the same command resumes: finished rows are verified and skipped)
  status:    refine_design.py status /work/runs/refine/canonical_121/
  assemble:  refine_design.py assemble /work/runs/refine/canonical_121/ [--write]
             (metrics of the rows done; --write also saves result.npz and summary.json there)
  export:    refine_design.py export /work/runs/refine/canonical_121/ results/refine/canonical_121/
             (a small bundle for git: manifest, verified rows, logs, summary.json, README.md;
             re-export to add later rows)
  bundle:    refine_design.py bundle results/refine/canonical_121 [more folders] --out results/refine-pybullet
             (complete folders of one engine -> a results bundle a run reads with
             empirical.results_from / mujoco.results_from on the 9-position grid)
  seed:      refine_design.py seed results/refine/canonical_121 --configfile config/refine_pybullet.yaml
             (a folder's episodes, complete or not, as its design's partial file in that config's
             design cache: the workflow simulates only the rest of its path, e.g. the adaptive
             grid's; morphlearn.seed)

Levers: early stop (exact, docs/empirical_levers.md) on unless --no-early-stop; never the
adaptive weight grid (this is the reference it is measured against). See
morphlearn.resumable for the folder layout.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

from morphlearn import configure
from morphlearn import resumable as rz
from morphlearn.physics.options import SweepOptions
from morphlearn.physics.params import load_params


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
    job = rz.Job(
        l1=tuple(a.design_l1),
        l2=tuple(a.design_l2),
        m=a.weights,
        params=params,
        options=SweepOptions(early_stop=not a.no_early_stop),
        engine=a.engine,
    )
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
    print(
        f"{a.folder}: design l1={ident['design']['l1']} l2={ident['design']['l2']}, "
        f"{ident['weights']} x {ident['weights']} weights, levers {ident['levers'] or 'none'}"
    )
    print(
        f"  rows {s['rows_done']}/{s['rows']} ({s['fraction_done']:.1%}), {s['episodes']} episodes, "
        f"{'complete' if s['complete'] else 'PARTIAL'}"
    )
    if c["rows_logged"]:
        left = (s["rows"] - s["rows_done"]) * 4 * s["rows"] / c["episodes_per_wall_s"]
        print(
            f"  cost: {c['episodes_per_wall_s']:.2f} episodes/wall-s, {c['episodes_per_cpu_s']:.2f} episodes/CPU-s "
            f"over {c['rows_logged']} rows logged; ~{left / 3600:.2f} h left at that rate"
        )
    dm = s["metrics_over_rows_done"]
    print(
        f"  over the rows done: generalists {dm['generalists']} of {s['episodes'] // 4} cells, "
        f"at least one {dm['at_least_one']}, per env {dm['per_env']}, M_L {dm['M_L']:.6g}, "
        f"M_CF {dm['M_CF']:.6g}, flagged {dm['flagged']}; {s['steps_per_episode']:.0f} steps/episode"
    )
    if "mirror" in s:
        mi = s["mirror"]
        print(
            f"  mirror (self-mirror design): {mi['pairs_flipped']} of {mi['pairs_compared']} cell pairs "
            "differ in success"
        )
    return 0


def cmd_assemble(a: argparse.Namespace) -> int:
    asm = rz.assemble(a.folder, log=_log)
    s = rz.summary(asm) | {"cost": rz.cost(a.folder), "run_key": asm.manifest["run_key"]}
    print(json.dumps(s, indent=1, sort_keys=True))
    if a.write:
        folder = Path(a.folder)
        d = asm.result
        np.savez_compressed(
            folder / "result.npz",
            first_time=d.first_time,
            min_dist=d.min_dist,
            status=d.status,
            steps=asm.steps,
            rows_done=asm.rows_done,
            weights=rz.job_from_manifest(asm.manifest).weights,
        )
        (folder / "summary.json").write_text(json.dumps(s, indent=1, sort_keys=True) + "\n")
        print(
            f"wrote {folder / 'result.npz'} and {folder / 'summary.json'} "
            f"({'complete' if asm.complete else 'PARTIAL'})",
            file=sys.stderr,
        )
    return 0


README = """# {title}: one {engine} design, exhaustive {m} x {m} weights ({state})

Made by `tools/refine_design.py` (morphlearn.resumable): every (env, w1, w2) episode of
design l1 = {l1}, l2 = {l2} with the body `{body}` (sha256 {body_sha}...), early stop on (exact:
docs/empirical_levers.md), no adaptive weight grid, no mirror derivation (every cell simulated).

**{state}**: {rows_done} of {m} w1 rows ({frac:.1%}), {episodes} of {total} episodes, exported
{now}. Rows were computed coarse to fine (the 11-point weights first, then farthest-first), so
the rows present are a spread-out sample of w1.

- Resume / finish: `nice -n 5 python tools/refine_design.py run --design-l1 {l1x} {l1y}
  --design-l2 {l2x} {l2y} --weights {m}{engine_flag} --out {src}` (finished rows are verified and skipped),
  then `python tools/refine_design.py export {src} <this folder>`. Without the original folder,
  give this folder as `--out` (it is a valid run folder) or copy it there first.
- Read: `python tools/refine_design.py status <this folder>` or `assemble <this folder>`; or
  `numpy.load("rows/row_XXX.npz")`: arrays `first_time`, `min_dist` (float32), `status` (int8),
  `steps` (int16), shape (4 envs [45, 135, 225, 315 deg], {m} w2), for w1 = weights[XXX]
  (`manifest.json` `weight_values`); `meta` holds the run key and the arrays' SHA-256.
- Code: created at commit {created_commit}; each row's commit is in `progress.jsonl`, each start
  in `runs.jsonl`. Run key {run_key}.

## Numbers over the rows done

- Generalists (success in all 4 environments): **{gen}** of {cells} cells; at least one
  environment {any1}; per environment {per_env}; M_L {ml:.6g}, M_CF {mcf:.6g}; flagged {flagged}.{paper}
{mirror}- Cost: {eps_wall:.2f} episodes per wall-second on a shared 2-core VM (nice 5), {eps_cpu:.2f}
  episodes per CPU-second, {spe:.0f} physics steps per episode (horizon {steps}).

`summary.json` holds these numbers as the `assemble` command prints them.
"""


def cmd_export(a: argparse.Namespace) -> int:
    import shutil
    from datetime import UTC, datetime

    src, dest = Path(a.folder), Path(a.dest)
    asm = rz.assemble(src, log=_log)
    s = rz.summary(asm) | {"cost": rz.cost(src), "run_key": asm.manifest["run_key"]}
    job = rz.job_from_manifest(asm.manifest)
    # exported in place (the run folder is the bundle): only the README and summary are written,
    # never the rows, which removing and copying onto themselves would destroy
    if dest.resolve() != src.resolve():
        if (dest / "rows").exists():
            shutil.rmtree(dest / "rows")
        (dest / "rows").mkdir(parents=True)
        for i in np.flatnonzero(asm.rows_done):
            shutil.copyfile(rz.row_path(src, int(i)), rz.row_path(dest, int(i)))
        for name in ("manifest.json", "progress.jsonl", "runs.jsonl"):
            if (src / name).exists():
                shutil.copyfile(src / name, dest / name)
    (dest / "summary.json").write_text(json.dumps(s, indent=1, sort_keys=True) + "\n")
    man, dm, c = asm.manifest, s["metrics_over_rows_done"], s["cost"]
    mi = s.get("mirror")
    mirror = (
        (
            f"- Mirror flips (the design is its own mirror image; cell (env, i, j) against "
            f"(mirror env, j, i), both rows done): **{mi['pairs_flipped']} of {mi['pairs_compared']}** "
            "cell pairs differ in success.\n"
        )
        if mi
        else ""
    )
    state = "complete" if asm.complete else "PARTIAL"
    title = "canonical design" if (job.l1, job.l2) == ((0.5, 0.5), (0.5, -0.5)) else "design"
    (dest / "README.md").write_text(
        README.format(
            title=title,
            engine=job.engine,
            paper="\n  The paper reports 1 generalist of 14641 for the canonical design in its physics."
            if title == "canonical design"
            else "",
            engine_flag="" if job.engine == "pybullet" else f" --engine {job.engine}",
            m=job.m,
            state=state,
            l1=list(job.l1),
            l2=list(job.l2),
            body=man["body_file"],
            body_sha=str(man["body_file_sha256"])[:12],
            rows_done=s["rows_done"],
            frac=s["fraction_done"],
            episodes=s["episodes"],
            total=4 * job.m**2,
            now=datetime.now(UTC).strftime("%Y-%m-%d %H:%M UTC"),
            l1x=job.l1[0],
            l1y=job.l1[1],
            l2x=job.l2[0],
            l2y=job.l2[1],
            src=src,
            created_commit=man["created_commit"],
            run_key=man["run_key"],
            gen=dm["generalists"],
            cells=s["episodes"] // 4,
            any1=dm["at_least_one"],
            per_env=dm["per_env"],
            ml=dm["M_L"],
            mcf=dm["M_CF"],
            flagged=dm["flagged"],
            mirror=mirror,
            eps_wall=c["episodes_per_wall_s"],
            eps_cpu=c["episodes_per_cpu_s"],
            spe=s["steps_per_episode"],
            steps=job.params.steps,
        )
    )
    size = sum(p.stat().st_size for p in dest.rglob("*") if p.is_file())
    print(f"exported {s['rows_done']}/{job.m} rows ({state}) to {dest}: {size / 1e6:.2f} MB", file=sys.stderr)
    return 0


def cmd_bundle(a: argparse.Namespace) -> int:
    """A results bundle of complete folders (morphlearn.refine_bundle), for ``<model>.results_from``."""
    import time

    from morphlearn import refine_bundle

    t0 = time.perf_counter()
    man = refine_bundle.build(a.folders, a.out)  # its README and bundle.json name this command
    size = sum(p.stat().st_size for p in a.out.rglob("*") if p.is_file())
    model = man["made_by"]["model"]
    print(
        f"bundle {a.out}: {model} designs {man['subsets'][model]['designs']}, {len(man['files'])} files, "
        f"{size / 1e6:.2f} MB, {time.perf_counter() - t0:.1f} s; check: morphlearn check-bundle {a.out}",
        file=sys.stderr,
    )
    return 0


def cmd_adaptive(a: argparse.Namespace) -> int:
    """The adaptive weight grid's misses at each ``--near``, replayed on a complete exhaustive folder."""
    from morphlearn import metrics
    from morphlearn.physics.refine import misses, simulated_mask
    from morphlearn.results import STATUS_OK

    asm = rz.assemble(a.folder, log=_log)
    if not asm.complete:
        raise rz.RefineError(
            f"{a.folder}: {int(asm.rows_done.sum())} of {len(asm.rows_done)} rows; the replay needs them all"
        )
    job = rz.job_from_manifest(asm.manifest)
    r = asm.result
    succ = metrics.success(r.first_time, r.min_dist, rz.thresholds(job.params))
    out = [misses(succ, r.min_dist, job.params.contact_distance, near) for near in a.near]
    # The levers' cost from the physics steps each cell took (the chunks record them) at the
    # folder's measured CPU-s per step: with early stop off a failure runs the whole horizon and a
    # success stops at contact as it does now; the adaptive grid runs only the cells it simulates.
    steps = asm.steps.astype(np.int64)
    horizon = round(job.params.horizon / job.params.dt)
    ended_early = succ | (r.status != STATUS_OK)
    no_levers = int(np.where(ended_early, steps, horizon).sum())
    cost = json.loads((a.folder / "summary.json").read_text())["cost"] if (a.folder / "summary.json").exists() else {}
    per_step = cost.get("cpu_s", float("nan")) / int(steps.sum())
    levers = {
        "cpu_s_per_step": per_step,
        "exhaustive_no_early_stop": {"steps": no_levers, "cpu_s": no_levers * per_step},
        "exhaustive_early_stop": {"steps": int(steps.sum()), "cpu_s": int(steps.sum()) * per_step},
    }
    for near in a.near:
        sim = simulated_mask(succ, r.min_dist, job.params.contact_distance, near)
        n = int(steps[sim].sum())
        levers[f"adaptive_near_{near:g}_early_stop"] = {"steps": n, "cpu_s": n * per_step}
    report = {"folder": str(a.folder), "engine": job.engine, "weights": job.m, "replays": out, "cost": levers}
    print(json.dumps(report, indent=1))
    return 0


def cmd_seed(a: argparse.Namespace) -> int:
    """The folder's episodes as the partial file of its design in a workflow config's design cache."""
    from morphlearn.config import ConfigError
    from morphlearn.seed import seed

    try:
        s = configure.load(a.base, a.configfile)
    except ConfigError as e:
        raise rz.RefineError(f"config {a.base} + {a.configfile}: {e}") from None
    r = seed(a.folder, s)
    if r.finished:
        print(f"design {r.design} is already finished in the design cache; nothing written", file=sys.stderr)
        return 0
    print(
        f"design {r.design}: {r.rows} complete rows in {a.folder}; {r.seeded} episodes seeded, {r.kept} already "
        f"in the partial file, {r.near_threshold} left to simulate (float32 closest approach at the "
        f"near threshold) -> {r.path}",
        file=sys.stderr,
    )
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
    r.add_argument("--engine", choices=rz.ENGINES, default="pybullet", help="physics engine (default: pybullet)")
    r.set_defaults(fn=cmd_run)
    s = sub.add_parser("status", help="progress, cost and metrics so far")
    s.add_argument("folder", type=Path)
    s.set_defaults(fn=cmd_status)
    m = sub.add_parser("assemble", help="the rows done as one design's result and metrics (JSON)")
    m.add_argument("folder", type=Path)
    m.add_argument("--write", action="store_true", help="also write result.npz and summary.json in the folder")
    m.set_defaults(fn=cmd_assemble)
    e = sub.add_parser("export", help="copy the verified rows, manifest and logs to a bundle folder with a README")
    e.add_argument("folder", type=Path)
    e.add_argument("dest", type=Path)
    b = sub.add_parser(
        "bundle", help="a results bundle of complete folders of one engine and settings (<model>.results_from)"
    )
    b.add_argument("folders", type=Path, nargs="+", help="complete refine folders (designs of the 9-position grid)")
    b.add_argument("--out", type=Path, required=True, help="the bundle folder (absent, empty or a refine bundle)")
    b.set_defaults(fn=cmd_bundle)
    ad = sub.add_parser("adaptive", help="replay the adaptive weight grid on a complete folder: what it misses")
    ad.add_argument("folder", type=Path)
    ad.add_argument("--near", type=float, nargs="+", default=[4.0, 1.5], help="near thresholds (contact distances)")
    sd = sub.add_parser("seed", help="a folder's episodes as its design's partial file in a workflow's design cache")
    sd.add_argument("folder", type=Path)
    sd.add_argument("--configfile", type=Path, nargs="+", required=True, help="the workflow run's config file(s)")
    sd.add_argument("--base", type=Path, default=Path("config.yaml"), help="the base config (default: config.yaml)")
    sd.set_defaults(fn=cmd_seed)
    e.set_defaults(fn=cmd_export)
    ad.set_defaults(fn=cmd_adaptive)
    a = ap.parse_args(argv)
    if a.cmd == "adaptive" and not all(v > 0 for v in a.near):
        ap.error(f"--near {a.near}: every threshold must be > 0 (contact distances)")
    try:
        return a.fn(a)
    except rz.RefineError as e:
        print(f"refine_design: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
