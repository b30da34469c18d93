"""A scripted hostile pass on issue 57's forger and write classes: 109 attacks (forged chunks,
stores, tables, commits, commands, subsets, links; results_dir, render_only and the write guard's
targets), each on a copy under /tmp, and whether each held (refused in one line, no traceback,
nothing written, no committed byte changed). From the project root:
``PYTHONPATH=src python tools/hostile_forger_pass.py`` (about a minute); tests/test_hostile_forger.py
holds the issue's own attacks."""

import contextlib
import io
import json
import os
import shutil
import traceback
from pathlib import Path

import pandas as pd

from morphlearn import config, metrics, provenance, store
from morphlearn.apps import cli

ROOT = Path.cwd()
TMP = Path("/tmp/morphlearn-hostile-forger")
results = []


def digests(root):
    return {p.relative_to(root).as_posix(): provenance.sha256_file(p) for p in sorted(root.rglob("*")) if p.is_file()}


BEFORE = {b: digests(ROOT / "results" / b) for b in ("ode-paper", "survey")}


def run_cli(*args):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            rc = cli.main(list(args))
        except SystemExit as e:
            rc = e.code
        except BaseException:
            rc = "TRACEBACK"
            err.write(traceback.format_exc())
    return rc, out.getvalue() + err.getvalue()


def copy(name):
    b = TMP / name
    if b.exists():
        shutil.rmtree(b)
    shutil.copytree(
        ROOT / "results" / name,
        b,
        symlinks=True,
        ignore=shutil.ignore_patterns("logs", "benchmarks", "*.html", ".snakemake*"),
    )
    for n in ("reproduction.html",):
        if (ROOT / "results" / name / n).exists():
            shutil.copy2(ROOT / "results" / name / n, b / n)
    return b


def man(b):
    return json.loads((b / "bundle.json").read_text())


def setman(b, m):
    (b / "bundle.json").write_text(json.dumps(m, indent=1, sort_keys=True) + "\n")


def edit(b, f):
    m = man(b)
    f(m)
    setman(b, m)


def reseal(b):
    files = {
        p.relative_to(b).as_posix(): provenance.sha256_file(p)
        for p in sorted(b.rglob("*"))
        if p.is_file() and not p.is_symlink() and p.name != "bundle.json"
    }
    edit(b, lambda m: m.update(files=files))


def row(b, model, d, **v):
    t = pd.read_csv(b / model / "metrics.csv")
    for k, x in v.items():
        t.loc[t.design == d, k] = x
    t.to_csv(b / model / "metrics.csv", index=False, float_format=metrics.CSV_FLOAT_FORMAT)


def table(b, model, f):
    p = b / model / "metrics.csv"
    f(pd.read_csv(p)).to_csv(p, index=False, float_format=metrics.CSV_FLOAT_FORMAT)


def bundle_attack(name, base, f):
    b = copy(base)
    try:
        f(b)
    except Exception as e:
        results.append((name, "SETUP-ERROR", repr(e)))
        return
    rc, out = run_cli("check-bundle", str(b))
    held = rc == 1 and "Traceback" not in out
    results.append((name, "held" if held else "FAILED", out.strip().splitlines()[0][:220] if out.strip() else ""))


Z = "ode/merged.zarr"


def zmeta(b, var, f):
    p = b / Z / var / "zarr.json"
    m = json.loads(p.read_text())
    f(m)
    p.write_text(json.dumps(m))


A = []  # (name, base, f)
A += [
    ("D4 one chunk deleted (min_dist 3)", "ode-paper", lambda b: ((b / Z / "min_dist/c/3/0/0/0").unlink(), reseal(b)))
]
A += [
    ("D4 chunk truncated to 0 bytes", "ode-paper", lambda b: ((b / Z / "status/c/5/0/0/0").write_bytes(b""), reseal(b)))
]
A += [
    (
        "D4 chunk swapped with another design's",
        "ode-paper",
        lambda b: (shutil.copy2(b / Z / "first_time/c/1/0/0/0", b / Z / "first_time/c/2/0/0/0"), reseal(b)),
    )
]
A += [
    (
        "D4 chunk of garbage bytes",
        "ode-paper",
        lambda b: ((b / Z / "first_time/c/0/0/0/0").write_bytes(os.urandom(3000)), reseal(b)),
    )
]
A += [("D4 status variable deleted", "ode-paper", lambda b: (shutil.rmtree(b / Z / "status"), reseal(b)))]
A += [
    (
        "D4 status dtype int16",
        "ode-paper",
        lambda b: (zmeta(b, "status", lambda m: m.update(data_type="int16")), reseal(b)),
    )
]
A += [
    (
        "D4 chunk shape (2,4,121,121)",
        "ode-paper",
        lambda b: (
            zmeta(b, "min_dist", lambda m: m["chunk_grid"]["configuration"].update(chunk_shape=[2, 4, 121, 121])),
            reseal(b),
        ),
    )
]
A += [
    (
        "D4 dims renamed, 121 kept",
        "ode-paper",
        lambda b: (
            [zmeta(b, v, lambda m: m.update(dimension_names=["design", "env", "a", "b"])) for v in store.VARS],
            reseal(b),
        ),
    )
]
A += [
    (
        "D4 shape 1e9 designs",
        "ode-paper",
        lambda b: ([zmeta(b, v, lambda m: m.update(shape=[10**9, 4, 121, 121])) for v in store.VARS], reseal(b)),
    )
]
A += [
    (
        "D4 20000x20000 no chunks",
        "ode-paper",
        lambda b: (
            [
                (
                    zmeta(
                        b,
                        v,
                        lambda m: (
                            m.update(shape=[10, 4, 20000, 20000], dimension_names=["design", "env", "p", "q"]),
                            m["chunk_grid"]["configuration"].update(chunk_shape=[1, 4, 20000, 20000]),
                        ),
                    ),
                    shutil.rmtree(b / Z / v / "c"),
                )
                for v in store.VARS
            ],
            reseal(b),
        ),
    )
]
A += [("D4 merged.zarr deleted", "ode-paper", lambda b: (shutil.rmtree(b / Z), reseal(b)))]
A += [("D4 merged.zarr emptied", "ode-paper", lambda b: (shutil.rmtree(b / Z), (b / Z).mkdir(), reseal(b)))]
A += [
    (
        "D4 every chunk of the survey theory store deleted",
        "survey",
        lambda b: ([shutil.rmtree(b / "theory/merged.zarr" / v / "c") for v in store.VARS], reseal(b)),
    )
]
A += [("D5 flagged -1", "ode-paper", lambda b: (row(b, "ode", 234, flagged=-1), reseal(b)))]
A += [
    (
        "D5 flagged +1 (held design)",
        "ode-paper",
        lambda b: (
            row(b, "ode", 6552, flagged=int(pd.read_csv(b / "ode/metrics.csv").set_index("design").flagged[6552]) + 1),
            reseal(b),
        ),
    )
]
A += [
    (
        "D5 flagged +3 survey theory held design",
        "survey",
        lambda b: (row(b, "theory", man(b)["subsets"]["theory"]["designs"][0], flagged=3), reseal(b)),
    )
]
A += [("D5 n_45+1, at_least_one+1, M_CF consistent", "ode-paper", lambda b: (_consistent(b), reseal(b)))]


def _consistent(b):
    t = pd.read_csv(b / "ode/metrics.csv").set_index("design").loc[160]
    a = int(t.at_least_one) + 1
    row(
        b,
        "ode",
        160,
        n_45=int(t.n_45) + 1,
        at_least_one=a,
        M_CF=float(metrics.CSV_FLOAT_FORMAT % (int(t.generalists) / a)),
    )


A += [
    (
        "D5 model column -> theory",
        "ode-paper",
        lambda b: (table(b, "ode", lambda t: t.assign(model="theory")), reseal(b)),
    )
]
A += [("D5 l1x + 1e-6", "ode-paper", lambda b: (table(b, "ode", lambda t: t.assign(l1x=t.l1x + 1e-6)), reseal(b)))]
A += [
    (
        "D5 flagged renamed flag",
        "ode-paper",
        lambda b: (table(b, "ode", lambda t: t.rename(columns={"flagged": "flag"})), reseal(b)),
    )
]
A += [
    (
        "D5 design as 160.0",
        "ode-paper",
        lambda b: (
            (b / "ode/metrics.csv").write_text((b / "ode/metrics.csv").read_text().replace("ode,160,", "ode,160.0,")),
            reseal(b),
        ),
    )
]
A += [("D5 M_L column deleted", "ode-paper", lambda b: (table(b, "ode", lambda t: t.drop(columns=["M_L"])), reseal(b)))]
A += [
    (
        "D5 all coordinates deleted (survey theory)",
        "survey",
        lambda b: (table(b, "theory", lambda t: t.drop(columns=["l1x", "l1y", "l2x", "l2y"])), reseal(b)),
    )
]
A += [
    (
        "D5 model deleted (survey empirical)",
        "survey",
        lambda b: (table(b, "empirical", lambda t: t.drop(columns=["model"])), reseal(b)),
    )
]
A += [("D5 flagged as text", "ode-paper", lambda b: (table(b, "ode", lambda t: t.assign(flagged="none")), reseal(b)))]
A += [
    (
        "D7 made_by commit random hex",
        "ode-paper",
        lambda b: edit(b, lambda m: m["made_by"].update(git_commit="1234567890" * 4)),
    )
]
A += [
    (
        "D7 made_by commit short real hash",
        "ode-paper",
        lambda b: edit(b, lambda m: m["made_by"].update(git_commit=m["made_by"]["git_commit"][:7])),
    )
]
A += [
    (
        "D7 made_by commit uppercase",
        "ode-paper",
        lambda b: edit(b, lambda m: m["made_by"].update(git_commit=m["made_by"]["git_commit"].upper())),
    )
]
A += [("D7 made_by commit HEAD", "ode-paper", lambda b: edit(b, lambda m: m["made_by"].update(git_commit="HEAD")))]
A += [
    (
        "D7 made_by commit -dirty",
        "ode-paper",
        lambda b: edit(b, lambda m: m["made_by"].update(git_commit=m["made_by"]["git_commit"] + "-dirty")),
    )
]
A += [("D7 made_by commit a number", "ode-paper", lambda b: edit(b, lambda m: m["made_by"].update(git_commit=123)))]
A += [
    (
        "D7 rendered_by commit forged (survey)",
        "survey",
        lambda b: edit(b, lambda m: m["rendered_by"].update(git_commit="ab" * 20)),
    )
]
A += [
    (
        "D7 rendered_by command with ; rm",
        "survey",
        lambda b: edit(b, lambda m: m["rendered_by"].update(command=m["rendered_by"]["command"] + "; rm -rf ~")),
    )
]
A += [
    (
        "D7 rendered_by command of other configs",
        "survey",
        lambda b: edit(
            b,
            lambda m: m["rendered_by"].update(
                command="snakemake --cores 2 --config render_only=True results_dir=results/survey --forceall"
            ),
        ),
    )
]
A += [
    (
        "D7 design_commits key forged (survey9)",
        "survey9-mujoco",
        lambda b: edit(
            b, lambda m: [s["simulated_by"].update(design_commits={"cd" * 20: 1}) for s in m["subsets"].values()]
        ),
    )
]
A += [
    ("D7 simulated_by emptied", "ode-paper", lambda b: edit(b, lambda m: m["subsets"]["ode"].update(simulated_by={})))
]
A += [
    (
        "D7 subsets designs reversed",
        "ode-paper",
        lambda b: edit(b, lambda m: m["subsets"]["ode"].update(designs=m["subsets"]["ode"]["designs"][::-1])),
    )
]
A += [
    (
        "D7 subsets designs with a string",
        "ode-paper",
        lambda b: edit(b, lambda m: m["subsets"]["ode"].update(designs=["160"])),
    )
]
A += [
    (
        "D7 subsets extra model",
        "ode-paper",
        lambda b: edit(b, lambda m: m["subsets"].update(theory={"designs": [1], "of": 1, "simulated_by": {}})),
    )
]
A += [("D7 subsets removed", "ode-paper", lambda b: edit(b, lambda m: m["subsets"].pop("ode")))]
A += [
    (
        "D7 configs claimed paper.yaml (command matches)",
        "ode-paper",
        lambda b: edit(
            b,
            lambda m: m["made_by"].update(
                configs=["config/paper.yaml", "config.yaml"],
                command="snakemake --cores 2 --configfile config/paper.yaml",
            ),
        ),
    )
]
A += [
    (
        "D7 results_dir changed",
        "ode-paper",
        lambda b: edit(b, lambda m: m["made_by"].update(results_dir="results/elsewhere")),
    )
]
A += [
    (
        "D7 command + --forceall",
        "ode-paper",
        lambda b: edit(b, lambda m: m["made_by"].update(command=m["made_by"]["command"] + " --forceall")),
    )
]
A += [
    (
        "D7 command --configfile /etc/passwd",
        "ode-paper",
        lambda b: edit(b, lambda m: m["made_by"].update(command="snakemake --cores 2 --configfile /etc/passwd")),
    )
]
A += [
    (
        "D7 command $(reboot)",
        "ode-paper",
        lambda b: edit(b, lambda m: m["made_by"].update(command="snakemake $(reboot)")),
    )
]
A += [("D7 command empty", "ode-paper", lambda b: edit(b, lambda m: m["made_by"].update(command="")))]
A += [
    (
        "D7 configs ../../etc",
        "ode-paper",
        lambda b: edit(b, lambda m: m["made_by"].update(configs=["config/../../etc/x.yaml"])),
    )
]
A += [("D7 made_by a list", "ode-paper", lambda b: edit(b, lambda m: m.update(made_by=[1])))]
A += [("D7 survey subset: best design's arrays dropped", "survey", None)]
A += [("D15 link in merged.zarr -> /etc/passwd", "ode-paper", lambda b: os.symlink("/etc/passwd", b / Z / "evil"))]
A += [
    (
        "D15 listed file replaced by a link inside",
        "ode-paper",
        lambda b: (
            shutil.move(b / "README.md", b / "ode/README.md.real"),
            os.symlink("ode/README.md.real", b / "README.md"),
            reseal(b),
        ),
    )
]
A += [("D15 dir link in figures-like folder", "ode-paper", lambda b: os.symlink("/", b / "ode/root"))]
A += [
    (
        "D15 bundle.json a link",
        "ode-paper",
        lambda b: (shutil.move(b / "bundle.json", b / "ode/m.json"), os.symlink("ode/m.json", b / "bundle.json")),
    )
]
A += [("D15 fifo", "ode-paper", lambda b: os.mkfifo(b / "fifo"))]
A += [("D15 link loop ode/self -> .", "ode-paper", lambda b: os.symlink(".", b / "ode/self"))]
A += [("D15 link to a listed dir inside merged.zarr", "ode-paper", lambda b: os.symlink("first_time", b / Z / "ft2"))]


def survey_drop(b):
    held = man(b)["subsets"]["theory"]["designs"]
    shutil.rmtree(b / "theory/merged.zarr")
    store.write_subset(ROOT / "results/survey/theory/merged.zarr", held[1:], b / "theory/merged.zarr")
    edit(b, lambda m: m["subsets"]["theory"].update(designs=held[1:]))
    row(b, "theory", held[0], flagged=0)
    reseal(b)


TMP.mkdir(parents=True, exist_ok=True)
for name, base, f in A:
    bundle_attack(name, base, f or survey_drop)

# -- write guard ------------------------------------------------------------------------------
proj = TMP / "clone"
if proj.exists():
    shutil.rmtree(proj)
for rel in ("results/survey", "results/coopt", "results/refine/canonical_121"):
    shutil.copytree(ROOT / rel, proj / rel)
for rel in ("src/morphlearn", "tools", "config", "workflow", "notebooks", ".git", ".venv", ".snakemake", "other"):
    (proj / rel).mkdir(parents=True, exist_ok=True)
os.symlink("/etc", proj / "results/etc")
os.symlink("../src", proj / "results/src")
os.symlink("survey", proj / "results/survey-link")
os.symlink("/tmp", proj / "results/tmplink")
(proj / "results/broken.json").write_text("[]")
shutil.copytree(proj / "results/survey", proj / "results/badmanifest")
(proj / "results/badmanifest/bundle.json").write_text("[]")
os.chdir(proj)
snap = digests(proj)


def guard(name, f, want_refused=True):
    try:
        f()
        refused = False
        msg = ""
    except config.ConfigError as e:
        refused = True
        msg = str(e)
    except Exception as e:
        results.append((name, "FAILED", "traceback " + repr(e)))
        return
    ok = refused == want_refused and (not refused or ("allowed:" in msg and "\n" not in msg))
    results.append((name, "held" if ok else "FAILED", msg[:200] if msg else "(allowed)"))


for rd in (
    ".",
    "..",
    "results/../.git",
    "results/./.snakemake",
    "/tmp/../etc",
    "results/survey/../survey",
    "RESULTS/x",
    "~/x",
    "results/etc",
    "results/etc/x",
    "results/src",
    "results/src/x",
    "results/survey-link",
    "results/survey-link/x",
    "results/tmplink/x",
    "other",
    "/usr/lib/x",
    "/proc/self",
    "/dev/shm/x",
    ".venv/lib",
    "results/.hidden",
    "results/coopt",
    "results/coopt/x",
    "results/badmanifest",
):
    guard(f"D10 results_dir={rd}", lambda rd=rd: config.check_results_dir(rd))
guard("D10 results_dir=results/new (allowed)", lambda: config.check_results_dir("results/new"), False)
guard("D10 results_dir=/tmp/scratch (allowed)", lambda: config.check_results_dir("/tmp/h57b-scratch"), False)
for cfgs in (
    [],
    ["config.yaml"],
    ["config/survey.yaml"],
    ["config/survey.yaml", "config.yaml", "config/paper.yaml"],
    ["config/paper.yaml", "config.yaml"],
):
    guard(
        f"D8 render_only survey with configs {cfgs}", lambda c=cfgs: config.check_results_dir("results/survey", True, c)
    )
guard(
    "D8 render_only survey with its configs (allowed)",
    lambda: config.check_results_dir("results/survey", True, ["config.yaml", "config/survey.yaml"]),
    False,
)
guard(
    "D8 render_only coopt (no configs recorded)",
    lambda: config.check_results_dir("results/coopt", True, ["config/coopt.yaml", "config.yaml"]),
)
guard(
    "D8 render_only bundle with bundle.json []",
    lambda: config.check_results_dir("results/badmanifest", True, ["config/survey.yaml", "config.yaml"]),
)
guard(
    "D8 render_only inside a bundle",
    lambda: config.check_results_dir("results/survey/theory", True, ["config/survey.yaml", "config.yaml"]),
)
guard(
    "D8 render_only via a link to the bundle",
    lambda: config.check_results_dir("results/survey-link", True, ["config.yaml"]),
)

for dest in (
    ".snakemake/x",
    "results/survey/../survey/y",
    "config/x",
    "workflow/x",
    "notebooks/x",
    "/usr/x",
    "results/src/x",
    "./.git",
    "results/.rerender-x",
    "results/coopt/y",
    "results/etc",
    "results/tmplink/x",
    "/",
    "other/x",
):
    # the guard every writer shares (refine export, which D9 attacked, is gone: issue 58)
    why = config.write_refusal(dest)
    results.append((f"D9 write guard -> {dest}", "held" if why else "FAILED", (why or "(allowed)")[:200]))
after = digests(proj)
results.append(
    (
        "no byte changed in the clone by the write attacks",
        "held" if after == snap else "FAILED",
        str(set(after) ^ set(snap))[:200],
    )
)
os.chdir(ROOT)
for b in ("ode-paper", "survey"):
    results.append(
        (f"committed results/{b} unchanged", "held" if digests(ROOT / "results" / b) == BEFORE[b] else "FAILED", "")
    )

held = sum(r[1] == "held" for r in results)
for r in results:
    print(f"{r[1]:8} {r[0]}: {r[2]}")
print(f"\n{held} of {len(results)} held")
