"""theory.backend cuda and mujoco.backend warp: the shard job asks SLURM for one GPU; the CPU
backends ask for none.

Checked on the submission the SLURM executor plugin really makes, through profiles/slurm: a fake
``sbatch`` on PATH records its arguments and refuses the job (so nothing runs), and a fake
``sacctmgr``, ``sinfo`` and ``squeue`` answer the plugin's start-up checks. tests/test_slurm.py runs a real (GPU-less)
SLURM.
"""

import os
import shlex
from pathlib import Path

import pytest
import yaml
from conftest import copy_workflow, snakemake

FAKE_SBATCH = '#!/bin/sh\nprintf "%s\\n" "$*" >> "$SBATCH_RECORD"\necho "fake sbatch: refused" >&2\nexit 1\n'
FAKE_SACCTMGR = "#!/bin/sh\necho acct\n"
FAKE_SINFO = "#!/bin/sh\nprintf 'PARTITION\\ncompute*\\n'\n"  # the default partition


THEORY = "results/theory/shards/shard_0.nc"
MUJOCO_WARP = {"enabled": True, "results_from": None, "backend": "warp", "designs": [[[0.5, 0.5], [0.5, -0.5]]]}


@pytest.mark.parametrize(
    "target, setting, gpus",
    [
        (THEORY, {"theory": {"backend": "cuda"}}, ["--gpus=1"]),
        (THEORY, {"theory": {"backend": "auto"}}, []),
        ("results/mujoco/shards/shard_0.nc", {"mujoco": MUJOCO_WARP}, ["--gpus=1"]),
    ],
)
def test_shard_submission_requests_gpu_only_for_gpu_backends(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, target: str, setting: dict, gpus: list[str]
) -> None:
    wd = copy_workflow(tmp_path / "wd")
    (wd / "extra.yaml").write_text(yaml.safe_dump(setting))  # a file: --config would pass numbers as strings
    fakes = tmp_path / "bin"
    fakes.mkdir()
    for name, text in (
        ("sbatch", FAKE_SBATCH),
        ("sacctmgr", FAKE_SACCTMGR),
        ("sinfo", FAKE_SINFO),
        ("squeue", "#!/bin/sh\n"),
    ):
        (fakes / name).write_text(text)
        (fakes / name).chmod(0o755)
    record = tmp_path / "sbatch_args.txt"
    monkeypatch.setenv("PATH", f"{fakes}{os.pathsep}{os.environ['PATH']}")
    monkeypatch.setenv("SBATCH_RECORD", str(record))
    monkeypatch.setenv("MORPHLEARN_SLURM_ACCOUNT", "acct")
    proc = snakemake(
        wd,
        target,
        "--profile",
        "profiles/slurm",
        # the plugin waits this long (default 40 s) before its first status check, even after a
        # refused submission: a wait on the wall clock, not a setting the submission depends on
        "--slurm-init-seconds-before-status-checks",
        "1",
        "--configfile",
        "config/smoke.yaml",
        "extra.yaml",
        check=False,
    )
    assert proc.returncode != 0  # the fake sbatch refused: nothing ran
    assert record.exists(), proc.stderr[-3000:]
    args = shlex.split(record.read_text().splitlines()[0])
    assert args[args.index("-A") + 1] == "acct", args  # the profile's submission, account and all
    assert [a for a in args if a.startswith(("--gpus", "--gres"))] == gpus, args
