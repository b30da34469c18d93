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
# The ode model's C core (morphlearn.ode._core) builds against Debian's libode-dev (ODE 0.16,
# double precision; the Debian 12 package pinned): installed here when missing and run as root
# (CI, fresh machines); otherwise, or when apt fails (offline), one line says what to install and
# every other model works without it.
ODE_HINT="libode-dev missing: the ode model needs it (sudo apt-get install libode-dev, then bash tools/setup.sh again)"
if [ ! -f /usr/include/ode/ode.h ]; then
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
    { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libode-dev=2:0.16.2-1 >/dev/null; } ||
      echo "$ODE_HINT"
  else
    echo "$ODE_HINT"
  fi
fi
# --reinstall-package: rebuild the C extension every time (a library installed since is picked up)
.venv/bin/uv pip install -q --python .venv/bin/python --no-deps --reinstall-package morphlearn -e .
.venv/bin/python -m compileall -q src
echo "morphlearn environment ready in .venv (activate: source .venv/bin/activate)"
