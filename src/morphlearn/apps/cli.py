"""Command line of morphlearn: evaluate one design in any model (design), check stored results
(verify, check-bundle, compare), re-render a committed bundle and check it (render), start the
explorer (explore), re-render a bundle with new figure code and re-seal what changed
(rerender-bundle, maintainers), read, check or export a refine folder (refine), and run the
workflow after checking its config files (run). 'morphlearn VERB --help' for each."""

from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import sys
import warnings
from collections.abc import Sequence
from pathlib import Path
from typing import Any, NoReturn

import numpy as np

from morphlearn import __version__
from morphlearn import grid as gridmod
from morphlearn.errors import EngineError, UsageError, c_stdout_to_stderr
from morphlearn.metrics import design_metrics
from morphlearn.physics.model import ROBOT_BODIES
from morphlearn.refine import cli as refine_cli


class _Parser(argparse.ArgumentParser):
    """argparse's own refusals (a flag's type, a missing argument) in one line too, exit 2."""

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def _position(name: str, xy: Sequence[float]) -> tuple[float, float]:
    for axis, v in zip("xy", xy, strict=True):
        if not (-0.5 <= v <= 0.5) or not np.isfinite(v):
            raise UsageError(f"{name} {axis} = {v} is outside the body; allowed: [-0.5, 0.5]")
    return float(xy[0]), float(xy[1])


def _exists(path: str | Path, kind: str = "dir", given: str | None = None) -> bool:
    """Whether ``path`` is a folder (``kind`` "dir") or a file; a name the file system cannot hold
    (too long, a NUL byte) is a UsageError naming it (``given``: as the user typed it) in one
    line, not an OSError traceback."""
    try:
        return Path(path).is_dir() if kind == "dir" else Path(path).is_file()
    except (OSError, ValueError) as e:
        why = getattr(e, "strerror", None) or "its name holds a NUL byte"
        name = str(path) if given is None else given
        name = repr(name) if len(name) <= 80 else f"{name[:70]!r}... ({len(name)} characters)"
        raise UsageError(f"{name}: cannot be read ({why})") from None


def _positive(name: str, v: float | None) -> None:
    if v is not None and not (v > 0 and np.isfinite(v)):
        raise UsageError(f"{name} = {v} must be a finite number > 0")


#: Weights per synapse at most (as grid.weights in the config schema).
MAX_WEIGHTS = 1001
#: Options that must be finite numbers > 0 where given.
POSITIVE = ("r", "horizon", "dt")


def cmd_design(a: argparse.Namespace) -> int:
    from morphlearn import models

    l1 = _position("--l1", a.l1)
    l2 = _position("--l2", a.l2)
    if a.weights < 2:  # the grid spans [-1, 1]: its two ends at least
        raise UsageError(
            f"--weights = {a.weights} must be in 2..{MAX_WEIGHTS}: the weights per synapse span [-1, 1], "
            "so at least its two ends (the paper: 121)"
        )
    if a.weights > MAX_WEIGHTS:
        gib = 4 * a.weights**2 * 9 / 2**30  # first_time, min_dist (float32), status (int8) per cell
        raise UsageError(
            f"--weights = {a.weights} must be in 2..{MAX_WEIGHTS} (one design's 4 x {a.weights}"
            f" x {a.weights} results would need {gib:.3g} GiB of memory)"
        )
    for name in POSITIVE:
        _positive(f"--{name}", getattr(a, name))
    model = models.get(a.model)
    model.check_cli(a)
    # another model's options are refused rather than silently ignored
    others: dict[str, list[str]] = {}
    for n, m in models.MODELS.items():
        for o in m.cli_options:
            if o not in model.cli_options:
                others.setdefault(o, []).append(n)
    given = [o for o in others if getattr(a, o) is not None]
    if given:
        owners = sorted({n for o in given for n in others[o]})
        takes = ", ".join(f"--{o}" for o in model.cli_options) or "no model options"
        raise UsageError(
            f"{', '.join(f'--{o}' for o in given)}: option{'s' if len(given) > 1 else ''} of the "
            f"{', '.join(owners[:-1]) + ' and ' if len(owners) > 1 else ''}{owners[-1]} "
            f"model{'s' if len(owners) > 1 else ''}; the {a.model} model takes {takes}"
        )
    from morphlearn.apps import design_output

    # the files it writes are checked before the simulation (minutes to an hour of a core)
    save = a.save and design_output.check_target("--save", a.save, (".npz",))
    plot = a.plot and design_output.check_target("--plot", a.plot, design_output.PLOT_FORMATS)
    w = gridmod.weights(a.weights)
    res = model.evaluate_one(l1, l2, w, a)
    dm = design_metrics(~np.isnan(res.first_time), res.status)
    out = {
        "model": a.model,
        **({"robot": model.cli_robot(a)} if hasattr(model, "cli_robot") else {}),
        "design": {"l1": list(l1), "l2": list(l2)},
        "weights": a.weights,
        "per_env": dm.per_env,
        "generalists": dm.generalists,
        "at_least_one": dm.at_least_one,
        **dm.values,
        "flagged": dm.flagged,
    }
    if save:
        meta = {"model": a.model, "l1": list(l1), "l2": list(l2), **{k: getattr(a, k) for k in ("r", "horizon", "dt")}}
        design_output.save_arrays(save, res, w, {**meta, "robot": out.get("robot"), "morphology": a.morphology})
    if plot:
        title = (
            f"{a.model}, {a.weights} x {a.weights} controllers: {dm.generalists} generalists\n"
            f"l1 = ({l1[0]:g}, {l1[1]:g}), l2 = ({l2[0]:g}, {l2[1]:g})"
        )
        design_output.plot_map(plot, res, w, title)
    if a.json:
        print(json.dumps(out))
    else:
        envs = ", ".join(f"{ang} deg: {c}" for ang, c in zip(gridmod.ENV_ANGLES_DEG, dm.per_env, strict=True))
        vals = "; ".join(f"{m} = {v:.6f}" for m, v in dm.values.items())
        print(f"design l1={l1} l2={l2}, model {a.model}, {a.weights}x{a.weights} controllers")
        print(_what_ran(model, a))
        print(f"successes per environment: {envs}")
        print(f"generalists (O == 4): {dm.generalists}; at least one (O >= 1): {dm.at_least_one}")
        print(f"{vals}; flagged trajectories: {dm.flagged}")
        for what, path in (("outcome arrays", save), ("map", plot)):
            if path:
                print(f"{what}: {path}")
    return 0


def _what_ran(model: Any, a: argparse.Namespace) -> str:
    """The line of ``design``'s text output that says what simulated the design: the theory's
    integrator, or a physics model's engine, robot and body file."""
    if not hasattr(model, "cli_robot"):
        how = f"fixed-step RK4, dt = {a.dt}" if a.dt is not None else "adaptive Dormand-Prince"
        return f"simulated by: the {model.name} (differential equations, {how}; docs/model.md)"
    robot = model.cli_robot(a)
    engine = getattr(model, "engine_label", "") or model.engine
    body = a.morphology or ROBOT_BODIES[robot]
    return f"simulated by: engine {engine}, robot {robot} (body {body})"


def cmd_verify(a: argparse.Namespace) -> int:
    from morphlearn.bundles import verify

    if a.samples < 1:
        raise UsageError(f"--samples = {a.samples}; allowed: an integer >= 1 (cells to re-evaluate)")
    if a.seed < 0:
        raise UsageError(f"--seed = {a.seed}; allowed: an integer >= 0")
    if a.workers < 1:
        raise UsageError(f"--workers = {a.workers}; allowed: an integer >= 1")
    _positive("--time-tol", a.time_tol)
    rep = verify.verify(a.merged, samples=a.samples, seed=a.seed, workers=a.workers, time_tol=a.time_tol)
    print(json.dumps(rep.as_dict(), sort_keys=True) if a.json else verify.format_report(rep))
    return 0 if rep.ok else 1


def cmd_check_bundle(a: argparse.Namespace) -> int:
    from morphlearn.bundles import check as bundle_check
    from morphlearn.bundles import make as bundle
    from morphlearn.bundles import resimulate

    if not _exists(a.bundle):
        raise UsageError(f"{a.bundle}: no such folder (a results bundle, e.g. results/paper)")
    for which in a.resimulate:  # before the bundle is read (the index range is checked with it)
        try:
            resimulate.parse_which(which, "--resimulate")
        except bundle.BundleError as e:
            raise UsageError(str(e)) from None
    if a.seed is not None and not 0 <= a.seed <= resimulate.MAX_SEED:
        raise UsageError(f"--seed = {a.seed}; allowed: an integer 0 to {resimulate.MAX_SEED} (a sample:K draw's)")
    notes: list[str] = []
    problems = bundle_check.check(a.bundle, notes=notes)
    for line in problems:
        print(line)
    for line in notes:
        print(f"{a.bundle}: note: {line}")
    if not problems:
        print(
            f"{a.bundle}: every file listed in {bundle.MANIFEST} is present and unchanged, and what it records "
            "agrees with its stores, configs and commits"
        )
    if a.resimulate:
        print(f"re-simulating {', '.join(a.resimulate)} (the bundle's recorded science)", flush=True)
        with c_stdout_to_stderr():  # pybullet's banner
            again = resimulate.resimulate(a.bundle, a.resimulate, seed=a.seed, say=lambda s: print(s, flush=True))
        for line in again:
            print(line)
        if not again:
            print(f"{a.bundle}: re-simulated designs agree exactly with the stored rows and arrays")
        problems += again
    return 1 if problems else 0


def _render_root(a: argparse.Namespace) -> Path:
    """The project root a render of bundle ``a.bundle`` runs in (render, rerender-bundle): the
    current folder, holding the Snakefile and the bundle, and ``a.cores`` usable."""
    from morphlearn.bundles import make as bundle

    root = Path.cwd()
    if not (root / "Snakefile").is_file():
        raise UsageError("run it from the project's root folder (where the Snakefile is)")
    if not _exists(root / a.bundle / bundle.MANIFEST, "file", a.bundle):
        raise UsageError(f"{a.bundle}: no {bundle.MANIFEST} (a results bundle under the project, e.g. results/paper)")
    if a.cores < 1:  # Snakemake would take 0 or -1 and fail later, after the bundle check
        raise UsageError(f"--cores = {a.cores}; allowed: an integer >= 1 (Snakemake's cores for the render)")
    return root


def cmd_rerender_bundle(a: argparse.Namespace) -> int:
    from morphlearn.bundles import make as bundle
    from morphlearn.bundles import render as bundle_rerender

    root = _render_root(a)
    try:
        changed = bundle_rerender.rerender(a.bundle, root, a.cores)
    except bundle.BundleError as e:
        print(str(e))
        return 1
    print(f"{a.bundle}: re-rendered; {len(changed)} rendered file(s) changed and re-sealed" + (": " if changed else ""))
    for rel in changed:
        print(f"  {rel}")
    return 0


def cmd_render(a: argparse.Namespace) -> int:
    """The reviewer's re-render: a committed bundle's figures and tables rendered from its own
    results (nothing simulated) with the configs that made it, on a copy beside it, and compared
    byte for byte with its bundle.json. The bundle is not touched (re-sealing is rerender-bundle's,
    after a figure's code changed)."""
    from morphlearn.bundles import make as bundle
    from morphlearn.bundles import render as bundle_rerender

    root = _render_root(a)
    files = _listed_files(root / a.bundle / bundle.MANIFEST)
    if not any(f.startswith("figures/") for f in files):
        raise UsageError(f"{a.bundle}: holds no figures (physics only): morphlearn check-bundle {a.bundle}")
    print(f"{a.bundle}: rendering a copy from its results (a minute or two) ...", flush=True)
    try:
        with bundle_rerender.rendered_copy(a.bundle, root, a.cores) as (_, _, changed):
            pass
    except bundle.BundleError as e:
        print(str(e))
        return 1
    if changed:
        for rel in sorted(changed):
            print(f"  {rel}: differs from {bundle.MANIFEST}")
        print(f"{a.bundle}: {len(changed)} rendered file(s) differ: the figure code changed since the bundle was made")
        return 1
    print(f"{a.bundle}: re-rendered; every file is byte-identical to {bundle.MANIFEST}")
    return 0


def _listed_files(mpath: Path) -> dict[str, str]:
    """The files a bundle's manifest lists, or a UsageError naming the file, the key and what is
    allowed (bundles.check.read_manifest)."""
    from morphlearn.bundles import check as bundle_check
    from morphlearn.bundles.make import BundleError

    try:
        return bundle_check.read_manifest(mpath)["files"]
    except BundleError as e:
        raise UsageError(str(e)) from None


#: Voila starts a kernel (about 320 MB) for every page request, and by default keeps it until the
#: server stops: Jupyter Server's own culler ends a kernel idle this long (no cell running, no page
#: connected to it: a bare GET, a closed tab), checked this often (seconds). An open page is kept.
VOILA_CULL = (
    "--MappingKernelManager.cull_idle_timeout=60",
    "--MappingKernelManager.cull_interval=15",
    "--MappingKernelManager.cull_connected=False",
)


def cmd_explore(a: argparse.Namespace) -> int:
    """The interactive explorer (docs/explorer.md) as a web app: Voila on notebooks/explore.ipynb."""
    root = Path.cwd()
    nb = root / "notebooks" / "explore.ipynb"
    if not nb.is_file():
        raise UsageError("run it from the project's root folder (notebooks/explore.ipynb)")
    exe = os.path.join(os.path.dirname(sys.executable), "voila")
    voila = exe if os.path.isfile(exe) else shutil.which("voila")
    if voila is None:
        raise UsageError("voila is not installed: the explorer extra (bash tools/setup.sh installs it)")
    args = [voila, str(nb.relative_to(root)), f"--port={a.port}", *VOILA_CULL] + ([] if a.browser else ["--no-browser"])
    os.execv(voila, args)  # Voila's own exit code and signals from here on
    return 0  # not reached


def cmd_compare(a: argparse.Namespace) -> int:
    """Rank agreement of two metrics tables over the designs both hold (theory vs physics, or one
    body vs another)."""
    from scipy import stats

    from morphlearn.analysis import compare

    if a.top < 1:
        raise UsageError(f"--top = {a.top}; allowed: an integer >= 1 (designs in each top list)")
    if a.resamples < compare.MIN_RESAMPLES:
        raise UsageError(
            f"--resamples = {a.resamples}; allowed: an integer >= {compare.MIN_RESAMPLES} (bootstrap "
            "resamples of a 95 % interval; the config's learners.bootstrap has the same minimum)"
        )
    tables = [compare.read_table(path) for path in (a.a, a.b)]
    both = compare.joined(*tables)
    if len(both) < 3:
        raise UsageError(f"the two tables share {len(both)} designs; need at least 3")
    with warnings.catch_warnings():  # a constant column: the line below says so, in our words
        warnings.simplefilter("ignore", stats.ConstantInputWarning)
        warnings.simplefilter("ignore", stats.DegenerateDataWarning)
        agree = compare.agreement(both, a.resamples)
    out: dict[str, Any] = {"designs": len(both)}
    for m, r in agree.items():  # every registered metric
        defined = not np.isnan(r.rho)  # NaN: a model gives every shared design the same value (JSON: null)
        out[m] = {k: (v if defined else None) for k, v in (("rho", r.rho), ("low", r.low), ("high", r.high))}
        shared = compare.top_shared(both, m, a.top)  # by the joined rows: two grids index designs apart
        out[m]["top_shared"] = shared
        print(f"{m}: Spearman rho {r.text()}; top {a.top} by {m} shared: {shared}")
    if a.json:
        print(json.dumps(out, allow_nan=False))
    return 0


class _Version(argparse.Action):
    """``--version``: package version and git commit (looked up only when asked: git is a subprocess)."""

    def __call__(self, parser: argparse.ArgumentParser, *_: object) -> None:
        from morphlearn.provenance import git_commit

        print(f"morphlearn {__version__} (commit {git_commit()})")
        parser.exit()


def configfiles_of(args: Sequence[str]) -> list[str]:
    """The files a Snakemake command line names with ``--configfile``/``--configfiles`` (each
    takes the values up to the next option)."""
    out: list[str] = []
    taking = False
    for arg in args:
        name, eq, value = arg.partition("=")
        if name in ("--configfile", "--configfiles"):
            taking = not eq
            if eq:
                out.append(value)
        elif arg.startswith("-"):
            taking = False
        elif taking:
            out.append(arg)
    return out


RUN_HELP = """usage: morphlearn run [TARGET ...] [SNAKEMAKE OPTIONS ...]

Run the workflow: Snakemake with the same arguments, after checking the files its --configfile
options name (an empty, binary or non-mapping file is refused in one line, exit 2, before
Snakemake reads it). A bundle is made from committed code only (the bundle rule refuses a dirty
worktree).

examples:
  morphlearn run --cores 2                                   the reduced workflow (config.yaml)
  morphlearn run all bundle --cores 2 --configfile config/ode_paper.yaml
  morphlearn run --cores 2 --configfile my.yaml --config results_dir=results/mine
  morphlearn run --profile profiles/slurm --configfile config/paper.yaml    on a SLURM cluster
  morphlearn run -n --cores 2 --configfile my.yaml           dry run: the jobs it would run

The options used most: --cores N, --configfile FILE ..., --config KEY=VALUE ..., --profile DIR,
--keep-going, -n (dry run). Every option is Snakemake's: snakemake --help lists them all
(.venv/bin/snakemake --help). Config keys: config/README.md; outputs, resuming: docs/workflow.md.
"""


def cmd_run(args: Sequence[str]) -> int:
    """Snakemake, after the config files it would read first are checked: Snakemake loads its
    ``--configfile`` files before the workflow starts, so an empty, binary or non-mapping one
    stopped in Snakemake's words (exit 1, no file name); here it is refused in one line, exit 2."""
    if any(x in ("-h", "--help") for x in args):
        print(RUN_HELP, end="")  # Snakemake's own ~1,000 lines: snakemake --help, as it says
        return 0

    from morphlearn.config import ConfigError, check_files

    try:
        check_files(configfiles_of(args))  # the workflow's own first check, before Snakemake reads them
    except ConfigError as e:
        print(f"morphlearn run: config error: {e}", file=sys.stderr)
        return 2
    exe = os.path.join(os.path.dirname(sys.executable), "snakemake")  # the project's environment first
    snakemake = exe if os.path.isfile(exe) else shutil.which("snakemake")
    if snakemake is None:
        print("morphlearn run: error: snakemake is not installed (bash tools/setup.sh)", file=sys.stderr)
        return 2
    os.execv(snakemake, [snakemake, *args])  # Snakemake's own exit code and signals from here on
    return 0  # not reached


DESIGN_HELP = """Evaluate one sensor placement (design) over every controller of the M x M weight grid in
one model, in the four environments, and print its per-environment successes, generalists, M_L
and M_CF (--json: one JSON object). Nothing is stored; a few designs of one's own in physics:
docs/ode.md, "Your own designs in ODE".

examples:
  morphlearn design --l1 0.5 0.5 --l2 0.5 -0.5 --weights 121          the theory (seconds)
  morphlearn design --model ode --l1 -0.5 0.125 --l2 0.5 -0.375 --weights 41
      the paper's best physics design in ODE with the authors' robot (~225 CPU-s at 41 x 41;
      121 x 121, every cell: ~1,800 CPU-s)
"""


def build_parser() -> argparse.ArgumentParser:
    from morphlearn.models import MODELS, REFERENCE

    p = _Parser(prog="morphlearn", description=__doc__)
    p.add_argument("--version", action=_Version, nargs=0, help="print version and git commit, and exit")
    sub = p.add_subparsers(dest="cmd", required=True)
    d = sub.add_parser(
        "design",
        help="evaluate one design over the M x M weight grid",
        description=DESIGN_HELP,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    d.add_argument("--model", choices=list(MODELS), default=REFERENCE, help=f"the model to run ({REFERENCE})")
    d.add_argument(
        "--l1", nargs=2, type=float, required=True, metavar=("X", "Y"), help="sensor 1 on the body, x y in [-0.5, 0.5]"
    )
    d.add_argument(
        "--l2", nargs=2, type=float, required=True, metavar=("X", "Y"), help="sensor 2 on the body, x y in [-0.5, 0.5]"
    )
    d.add_argument("--weights", type=int, default=121, metavar="M", help="weights per synapse (121)")
    d.add_argument("--r", type=float, default=None, help="the theory's light distance (4); theory only")
    d.add_argument("--horizon", type=float, default=None, help="the theory's simulated time T (500); theory only")
    d.add_argument(
        "--dt", type=float, default=None, help="the theory's integrator: fixed-step RK4 with this step; theory only"
    )
    d.add_argument(
        "--save",
        default=None,
        metavar="FILE.npz",
        help="also write the outcome arrays (first_time, min_dist, status: 4 environments x M x M) and "
        "the weights to this .npz",
    )
    d.add_argument(
        "--plot",
        default=None,
        metavar="FILE.png",
        help="also draw the design's map: environments solved by each controller, generalists cyan "
        "(.png, .pdf or .svg)",
    )
    d.add_argument(
        "--morphology",
        default=None,
        help="physics models: body parameters YAML (default: "
        + "; ".join(f"{n}: {ROBOT_BODIES[m.robots[0]]}" for n, m in MODELS.items() if hasattr(m, "robots"))
        + ")",
    )
    d.add_argument(
        "--robot",
        default=None,
        choices=sorted(ROBOT_BODIES),
        help="physics models: which robot the engine builds (default: the engine's own; ode: authors; "
        "docs/authors_robot.md)",
    )
    d.add_argument("--json", action="store_true", help="print one JSON object")
    d.set_defaults(func=cmd_design)
    v = sub.add_parser(
        "verify",
        help="re-evaluate random stored cells with the scipy reference solver",
        description="Re-evaluates a random sample of a theory run's stored cells (merged.zarr) with "
        "scipy's reference solver and reports how many agree: success, first-success time within "
        "--time-tol.",
    )
    v.add_argument("--merged", required=True, metavar="PATH", help="a merged.zarr made by the workflow")
    v.add_argument("--samples", type=int, default=200, metavar="N", help="cells to re-evaluate (200)")
    v.add_argument("--seed", type=int, default=0, metavar="S", help="random seed of the sample (0)")
    v.add_argument("--workers", type=int, default=1, metavar="K", help="processes for the reference (1)")
    v.add_argument(
        "--time-tol", type=float, default=0.05, metavar="DT", help="first-success times agree within this (0.05)"
    )
    v.add_argument("--json", action="store_true", help="print one JSON object")
    v.set_defaults(func=cmd_verify)
    b = sub.add_parser(
        "check-bundle",
        help="compare a results bundle's files with its bundle.json",
        description="Compares every file of a committed results bundle with the SHA-256 its bundle.json "
        "lists (and, with --resimulate, re-simulates some of its designs and compares them exactly); "
        "changes nothing.",
    )
    b.add_argument("bundle", metavar="DIR", help="the bundle folder (e.g. results/paper)")
    b.add_argument(
        "--resimulate",
        nargs="+",
        metavar="WHICH",
        default=[],
        help="also re-simulate these designs and compare them exactly: [MODEL:]WHICH, WHICH one of "
        "canonical, best_M_L, best_M_CF, a design index (held in the bundle or not) or sample:K (K "
        "random rows); MODEL a registered model (default theory: a few seconds a design at paper "
        "resolution; e.g. empirical:12, a pybullet design of the 11 x 11 survey: about 50 CPU-s)",
    )
    b.add_argument(
        "--seed",
        type=int,
        default=None,
        metavar="S",
        help="the seed of the sample:K draws (default: a fresh one each run, printed: give it to replay a draw)",
    )
    b.set_defaults(func=cmd_check_bundle)
    g = sub.add_parser(
        "render",
        help="re-render a committed bundle's figures and tables from its results and check them (reviewers)",
        description=cmd_render.__doc__,
    )
    g.add_argument("bundle", metavar="DIR", help="the bundle, relative to the project root (e.g. results/paper)")
    g.add_argument("--cores", type=int, default=2, metavar="N", help="Snakemake cores (2)")
    g.set_defaults(func=cmd_render)
    x = sub.add_parser(
        "explore", help="start the interactive explorer (a Voila web app)", description=cmd_explore.__doc__
    )
    x.add_argument("--port", type=int, default=8866, metavar="N", help="the port it serves on (8866)")
    x.add_argument("--browser", action="store_true", help="also open a browser (default: print the address only)")
    x.set_defaults(func=cmd_explore)
    r = sub.add_parser(
        "rerender-bundle",
        help="maintainers: re-render a bundle with the current code and RE-SEAL it (rewrites bundle.json "
        "for the rendered files that changed)",
        description="Re-renders a bundle's figures and tables with the current code and rewrites the "
        "SHA-256 of every rendered file that changed in its bundle.json (records rendered_by); data "
        "files and the README are never re-sealed. For a figure's code change; a reviewer re-renders "
        "with 'morphlearn render', which changes nothing.",
    )
    r.add_argument("bundle", metavar="DIR", help="the bundle, relative to the project root (e.g. results/survey)")
    r.add_argument("--cores", type=int, default=2, metavar="N", help="Snakemake cores (2)")
    r.set_defaults(func=cmd_rerender_bundle)
    c = sub.add_parser(
        "compare",
        help="rank agreement (Spearman, bootstrap interval) of two metrics tables",
        description="How alike two metrics tables rank their designs: Spearman's rho of M_L and of M_CF "
        "over the designs both hold (by coordinates) with a bootstrap interval, and the designs their "
        "top-K share.",
    )
    c.add_argument("a", metavar="METRICS_A", help="a metrics.csv (e.g. results/survey/theory/metrics.csv)")
    c.add_argument("b", metavar="METRICS_B", help="another, on the same design grid")
    c.add_argument("--resamples", type=int, default=2000, metavar="N", help="bootstrap resamples (2000)")
    c.add_argument("--top", type=int, default=10, metavar="K", help="also count shared top-K designs (10)")
    c.add_argument("--json", action="store_true", help="also print one JSON object")
    c.set_defaults(func=cmd_compare)
    refine_cli.add_parser(sub)
    sub.add_parser(
        "run",
        help="snakemake with the same arguments, after checking the --configfile files (one line, exit 2)",
        add_help=False,
    )
    for parser in (p, d, v):  # argparse takes '-5e-1' for an option: accept every negative number
        parser._negative_number_matcher = _NEGATIVE_NUMBER
    return p


_NEGATIVE_NUMBER = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$")


def main(argv: Sequence[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv[:1] == ["run"]:  # everything after it is Snakemake's, options included
        return cmd_run(argv[1:])
    parser = build_parser()
    a = parser.parse_args(argv)
    try:
        return a.func(a)
    except (UsageError, ValueError) as e:
        print(f"morphlearn {a.cmd}: error: {e}", file=sys.stderr)
        return 2
    except EngineError as e:  # the engine's own error, in one line (never an abort)
        print(f"morphlearn {a.cmd}: engine error: {e}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    raise SystemExit(main())
