#!/usr/bin/env bash
# Fresh-machine set-up: a virtual environment in .venv with the exact versions of requirements.lock.
set -euo pipefail
cd "$(dirname "$0")/.."
PY=${PYTHON:-python3}
[ -x .venv/bin/python ] || "$PY" -m venv .venv
.venv/bin/python -m pip install -q --disable-pip-version-check uv==0.13.9
# --compile-bytecode, and compileall for the package: every Python process (each Snakemake start,
# rule job, notebook kernel) then loads bytecode instead of compiling its imports from source, which
# it would do every time where PYTHONDONTWRITEBYTECODE is set (this project's machines: a smoke
# config's dry run took 27.6 s without and 12.5 s with it).
.venv/bin/uv pip install -q --compile-bytecode --python .venv/bin/python -r requirements.lock
.venv/bin/uv pip install -q --python .venv/bin/python --no-deps -e .
.venv/bin/python -m compileall -q src
echo "morphlearn environment ready in .venv (activate: source .venv/bin/activate)"
