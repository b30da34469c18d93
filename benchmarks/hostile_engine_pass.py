"""A hostile pass on the classes of issue 57 D1-D3, D11-D14 and D16, beyond the attacks of
tests/test_hostile_engine.py: body files and config params of every engine with values of every
kind (NaN, infinities, denormals, huge integers, strings, lists), the ODE core past the validator
and its run_batch called directly, malformed bundle and refine manifests, explorer URL values,
large YAML files and config values, another robot's body file by any spelling. Each instance holds
when it is refused in one line (no traceback, under 20 s) or, being valid, runs.

Usage (from the project root, about 3 minutes)::

    PYTHONPATH=src python benchmarks/hostile_engine_pass.py [-v]
"""

from __future__ import annotations

import contextlib
import io
import json
import sys
import tempfile
import time
import traceback
from pathlib import Path

import numpy as np

from morphlearn import config
from morphlearn.apps import cli, explore
from morphlearn.ode import core
from morphlearn.physics import params as pm

T = Path(tempfile.mkdtemp(prefix="hostile-"))
AUTH = Path("config/authors_body.yaml").read_text().splitlines()
results: list[tuple[str, str, bool, str]] = []


def record(cls: str, what: str, ok: bool, note: str = "") -> None:
    results.append((cls, what, ok, note))


def run_cli(argv: list[str]) -> tuple[int, str, str, float]:
    out, err = io.StringIO(), io.StringIO()
    t0 = time.monotonic()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            rc = cli.main(argv)
        except SystemExit as e:
            rc = int(e.code or 0)
        except BaseException:
            rc = -1
            traceback.print_exc()
    return rc, out.getvalue(), err.getvalue(), time.monotonic() - t0


def one_line_refusal(rc: int, out: str, err: str, dt: float, limit: float = 20) -> tuple[bool, str]:
    lines = [x for x in err.splitlines() if x.strip()]
    ok = rc in (1, 2) and "Traceback" not in err and len(lines) == 1 and len(lines[0]) < 700 and dt < limit
    return ok, (lines[0][:160] if lines else f"rc={rc} out={out[-100:]!r}")


# A. body files through the CLI, every engine
VALUES = [
    ".nan",
    ".inf",
    "-.inf",
    "-1.0",
    "0",
    "1.0e+309",
    "99999999999999999999999999",
    "'x'",
    "true",
    "[1, 2]",
    "{a: 1}",
    "null",
    "1.0e-320",
]
PARAMS = list(pm._RANGES)
for model in ("ode", "empirical", "mujoco"):
    for i, (key, value) in enumerate((k, v) for k in PARAMS for v in VALUES):
        if model != "ode" and i % 7:  # a sample for the slower engines
            continue
        lines = [f"{key}: {value}" if x.startswith(f"{key}:") else x for x in AUTH]
        f = T / f"b_{model}_{i}.yaml"
        f.write_text("\n".join(lines) + "\n")
        rc, out, err, dt = run_cli(
            [
                "design",
                "--model",
                model,
                "--robot",
                "authors",
                "--l1",
                "0.5",
                "0.5",
                "--l2",
                "0.5",
                "-0.5",
                "--weights",
                "2",
                "--morphology",
                str(f),
            ]
        )
        try:
            pm.load_params(f)
            valid = True  # inside the ranges: it must run (exit 0, no traceback)
        except ValueError:
            valid = False
        if valid:
            ok, note = rc == 0 and "Traceback" not in err and "M_L" in out, f"valid, ran: rc={rc}"
        else:
            ok, note = one_line_refusal(rc, out, err, dt)
        record("A body file (CLI)", f"{model} {key}={value}", ok, note)

# B. config params, every physics section
base = config.read("config.yaml")
for model in ("ode", "empirical", "mujoco"):
    for key in PARAMS:
        for v in (float("nan"), float("inf"), -1, 0, 10**30, 1e300, "1e10", True, [1], None):
            try:
                config.validate(config.deep_merge(base, {model: {"params": {key: v}}}))
                try:
                    pm._check(key, v)
                    valid = True
                except ValueError:
                    valid = False
                record("B config params", f"{model}.{key}={v!r}", valid, "accepted" + (" (valid)" if valid else ""))
            except config.ConfigError as e:
                record(
                    "B config params", f"{model}.{key}={v!r}", "\n" not in str(e) and len(str(e)) < 700, str(e)[:120]
                )
            except Exception as e:
                record("B config params", f"{model}.{key}={v!r}", False, repr(e)[:120])


# C. past the validator: the engine's handler (no abort; an error or a finite result)
def unchecked(**kw: float) -> pm.EmpiricalParams:
    p = object.__new__(pm.EmpiricalParams)
    for k, v in {**pm.load_params("config/authors_body.yaml").to_dict(), **kw, "steps": 200}.items():
        object.__setattr__(p, k, v)
    return p


for kw in [
    dict(body_mass=0.0),
    dict(wheel_mass=-5.0),
    dict(castor_mass=1e-300),
    dict(wheel_radius=1e6),
    dict(wheel_radius=-1.0),
    dict(gravity=-9.81),
    dict(gravity=1e200),
    dict(dt=-0.05),
    dict(dt=1e-300),
    dict(light_radius=1e8),
    dict(max_speed=1e300),
    dict(max_torque=1e300),
    dict(wheel_setback=1e9),
    dict(light_distance=1e300),
    dict(body_mass=1e300, castor_mass=1e-300),
]:
    try:
        ep, _ = core.run(unchecked(**kw), (0.5, 0.5), (0.5, -0.5), np.array([[1.0, -1.0]]), [0], stop_at_success=False)
        record("C engine handler", str(kw), True, f"ran, finite={bool(ep.finite.all())}")
    except core.OdeEngineError as e:
        record("C engine handler", str(kw), "\n" not in str(e), str(e)[:120])
    except Exception as e:
        record("C engine handler", str(kw), isinstance(e, ValueError), repr(e)[:120])

# D. run_batch directly
good = list(core.params_tuple(pm.load_params("config/authors_body.yaml")))
z = np.zeros


def rb(p: list, n: int, sizes: tuple = (8, 4, 4, 2, 2, 2, 2), path: object = None) -> None:
    bufs = [
        z(sizes[0]),
        z(sizes[1]),
        z(sizes[2]),
        z(sizes[3], np.int64),
        z(sizes[4]),
        z(sizes[5], np.int64),
        z(sizes[6], np.uint8),
    ]
    core.core().run_batch(tuple(p), n, *bufs, True, path)


for what, call in [
    ("n = -1", lambda: rb(good, -1)),
    ("n = 2**62", lambda: rb(good, 2**62)),
    ("n = 2**63", lambda: rb(good, 2**63)),
    ("steps = 2**63-1 with path", lambda: rb([*good[:10], 2**63 - 1, good[11]], 2, path=z(4))),
    ("steps = 0", lambda: rb([*good[:10], 0, good[11]], 2)),
    ("steps = -5", lambda: rb([*good[:10], -5, good[11]], 2)),
    ("inf dt", lambda: rb([*good[:9], float("inf"), *good[10:]], 2)),
    ("nan success radius", lambda: rb([*good[:11], float("nan")], 2)),
    ("short buffers", lambda: rb(good, 2, sizes=(7, 4, 4, 2, 2, 2, 2))),
    ("11-tuple params", lambda: rb(good[:11], 2)),
    ("params a list of str", lambda: rb(["x"] * 12, 2)),
    (
        "non-contiguous sensors",
        lambda: core.core().run_batch(
            tuple(good), 2, z(16)[::2], z(4), z(4), z(2, np.int64), z(2), z(2, np.int64), z(2, np.uint8), True, None
        ),
    ),
]:
    try:
        call()
        record("D run_batch", what, False, "accepted")
    except (ValueError, TypeError, OverflowError) as e:
        record("D run_batch", what, "\n" not in str(e), f"{type(e).__name__}: {e}"[:120])
    except Exception as e:
        record("D run_batch", what, False, repr(e)[:120])

# E. manifests: render and refine status
bundle_shapes = [
    '{"files": null}',
    '{"files": {"a": null}}',
    '{"files": {"figures/a.png": ["x"]}}',
    "NaN",
    '{"files": {}, "files": 5}',
    "\xff\xfe",
    "",
    "{" * 200 + "}" * 200,
    '{"a":' * 150 + "1" + "}" * 150,
    "true",
]
for i, text in enumerate(bundle_shapes):
    b = T / f"bundle{i}"
    b.mkdir()
    (b / "bundle.json").write_bytes(text.encode("latin-1"))
    ok, note = one_line_refusal(*run_cli(["render", str(b)]))
    record("E render manifest", text[:30], ok, note)
big = T / "bundlebig"
big.mkdir()
with open(big / "bundle.json", "wb") as fh:
    fh.truncate(10 * 2**20 + 1)
record("E render manifest", "10 MB + 1 byte", *one_line_refusal(*run_cli(["render", str(big)])))
ident = {"design": {"l1": [0.5, 0.5], "l2": [0.5, -0.5]}, "weights": 5, "params": {}, "levers": {}}
refine_shapes = [
    {"run_key": "x", "identity": {**ident, "design": {"l1": "ab", "l2": [0.5, -0.5]}}},
    {"run_key": "x", "identity": {**ident, "design": {"l1": [1e308, 0], "l2": [0.5, -0.5]}}},
    {"run_key": "x", "identity": {**ident, "weights": -5}},
    {"run_key": "x", "identity": {**ident, "weights": "7"}},
    {"run_key": "x", "identity": {**ident, "weights": 1.5}},
    {"run_key": "x", "identity": {**ident, "params": {"steps": -1}}},
    {"run_key": "x", "identity": {**ident, "params": {"colour": 1}}},
    {"run_key": "x", "identity": {**ident, "levers": {"early_stop": 5}}},
    {"run_key": "x", "identity": {**ident, "levers": []}},
    {"run_key": "x", "identity": {**ident, "design": []}},
    {"run_key": ["x"], "identity": ident},
    {"run_key": "x", "identity": ident},  # a well-formed identity whose key does not match
    {"run_key": "x", "identity": {**ident, "params": {"light_distance": 1e10}}},
]
for i, man in enumerate(refine_shapes):
    d = T / f"refine{i}"
    d.mkdir()
    (d / "manifest.json").write_text(json.dumps(man))
    for action in ("status", "assemble"):
        ok, note = one_line_refusal(*run_cli(["refine", action, str(d)]))
        record("E refine manifest", f"{action} {json.dumps(man)[:60]}", ok, note)

# F. explorer URL values
for q in [
    "design=-1",
    "design=1e3",
    "design=0x10",
    "design= 5",
    "design=٣",
    "design=" + "1" * 10,
    "w=1,2,3",
    "w=",
    "w=0x1p0,0",
    "w=1_0,0",
    "w=,",
    "w=nan,0",
    "w=0,-inf",
    "w=1.0000001,0",
    "w=" + "1" * 5000 + ",0",
    "metric=" + "x" * 5000,
    "design=5&design=" + "9" * 5000,
]:
    try:
        v = explore.parse_view(q)
        fine = (v.design is None or v.design < 10**9) and (v.w is None or all(-1 <= x <= 1 for x in v.w))
        record("F explorer URL", q[:40], fine, f"accepted {v.design} {v.w}")
    except explore.ExploreError as e:
        record("F explorer URL", q[:40], len(str(e)) < 300, str(e)[:120])
    except Exception as e:
        record("F explorer URL", q[:40], False, repr(e)[:120])

# G. YAML size classes
for name, text in [
    ("200,000 unknown keys", "".join(f"k{i}: 1\n" for i in range(200_000))),
    ("one 2 MB key", "k" * 2_000_000 + ": 1\n"),
    ("50,000 unknown ode.params keys", "ode:\n  params:\n" + "".join(f"    p{i}: 1\n" for i in range(50_000))),
    ("1,100,000 plain scalars", "x: [" + ",".join(["1"] * 1_100_000) + "]\n"),
    ("a long unknown key", "k" * 100_000 + ": 1\n"),
]:
    f = T / "g.yaml"
    f.write_text(text)
    t0 = time.monotonic()
    try:
        config.load(f)
        record("G YAML", name, False, "accepted")
    except (config.ConfigError, ValueError) as e:
        dt = time.monotonic() - t0
        record("G YAML", name, len(str(e)) < 1000 and dt < 20, f"{dt:.1f} s: {str(e)[:100]}")

if "-v" in sys.argv:  # every refusal of the engine, manifest, URL and YAML classes, as said
    for cls, what, _, note in results:
        if cls[0] in "CDEFG":
            print("  ", cls, "|", what[:50], "|", note[:150])

# H. config values of any size, at several keys
for keyp in (
    ("grid", "weights"),
    ("sweep", "shards"),
    ("ode", "params", "steps"),
    ("theory", "r"),
    ("results_dir",),
    ("ode", "morphology"),
    ("analysis", "top"),
):
    for v in (2**63, 2**64, 10**100, 10**5000, "x" * 5000, "x" * 1_000_000, [10**5000], {"a": 10**5000}):
        patch: dict = v  # type: ignore[assignment]
        label = (
            f"int of {v.bit_length()} bits"
            if isinstance(v, int)
            else (f"str of {len(v)}" if isinstance(v, str) else type(v).__name__)
        )
        for k in reversed(keyp):
            patch = {k: patch}
        t0 = time.monotonic()
        try:
            config.validate(config.deep_merge(base, patch))
            record("H config sizes", f"{'.'.join(keyp)}={label}", False, "accepted")
        except config.ConfigError as e:
            ok = "\n" not in str(e) and len(str(e)) < 700 and time.monotonic() - t0 < 10
            record("H config sizes", f"{'.'.join(keyp)}={label}", ok, str(e)[:120])
        except Exception as e:
            record("H config sizes", f"{'.'.join(keyp)}={label}", False, repr(e)[:120])

# I. another robot's body file, by any spelling
link = T / "link.yaml"
link.symlink_to(Path("config/empirical_morphology.yaml").resolve())
for model, robot in (("ode", "authors"), ("empirical", "authors"), ("mujoco", "authors")):
    for path in (
        "config/empirical_morphology.yaml",
        "./config/empirical_morphology.yaml",
        str(Path("config/empirical_morphology.yaml").resolve()),
        "config//empirical_morphology.yaml",
        "config/../config/empirical_morphology.yaml",
        str(link),
    ):
        rc, out, err, dt = run_cli(
            [
                "design",
                "--model",
                model,
                "--robot",
                robot,
                "--l1",
                "0.5",
                "0.5",
                "--l2",
                "0.5",
                "-0.5",
                "--weights",
                "2",
                "--morphology",
                path,
            ]
        )
        ok, note = one_line_refusal(rc, out, err, dt)
        record("I other robot's body", f"{model} {path[-40:]}", ok and "body file" in note, note)
for model, robot, path in (
    ("empirical", "project", "config/authors_body.yaml"),
    ("mujoco", "project", "./config/authors_body.yaml"),
):
    rc, out, err, dt = run_cli(
        [
            "design",
            "--model",
            model,
            "--robot",
            robot,
            "--l1",
            "0.5",
            "0.5",
            "--l2",
            "0.5",
            "-0.5",
            "--weights",
            "2",
            "--morphology",
            path,
        ]
    )
    ok, note = one_line_refusal(rc, out, err, dt)
    record("I other robot's body", f"{model} {robot} {path}", ok and "body file" in note, note)

by: dict[str, list[int]] = {}
for cls, what, ok, note in results:
    by.setdefault(cls, [0, 0])
    by[cls][0] += 1
    by[cls][1] += ok
    if not ok:
        print("NOT HELD:", cls, "|", what, "|", note)
for cls, (n, held) in by.items():
    print(f"{cls}: {held}/{n} held")
print(f"total: {sum(h for _, h in by.values())}/{sum(n for n, _ in by.values())} held")
