#!/usr/bin/env bash
# The project's checks: linters, workflow lint, then the test suite.
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$PWD/.venv/bin:$PATH"
echo "== ruff (the package, tests, scripts and notebooks/*.ipynb: ruff lints notebooks natively)"; ruff check .
echo "== ruff format (Python files; notebooks keep their own layout)"; ruff format --check --exclude '*.ipynb' .
echo "== snakefmt"; snakefmt --check Snakefile workflow/rules/
echo "== snakemake --lint"; snakemake --lint --cores 1 >/dev/null
echo "== dry run of the full config"; snakemake -n --configfile config/full.yaml --quiet rules >/dev/null
# --durations: every run (CI included) prints its slowest tests, so the suite's time is watched, not guessed.
echo "== pytest"; python -m pytest -q -ra --durations=40 "$@"
