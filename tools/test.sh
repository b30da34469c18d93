#!/usr/bin/env bash
# The project's checks: linters, workflow lint, then the test suite.
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$PWD/.venv/bin:$PATH"
echo "== ruff (the package, tests, scripts and notebooks/*.ipynb: ruff lints notebooks natively)"; ruff check .
echo "== ruff format (Python files; notebooks keep their own layout)"; ruff format --check --exclude '*.ipynb' .
echo "== snakefmt"; snakefmt --check Snakefile workflow/rules/
echo "== import contracts (pyproject.toml [tool.importlinter])"; lint-imports --no-cache >/dev/null
echo "== snakemake --lint"; snakemake --lint --cores 1 >/dev/null
echo "== dry run of the full config"; snakemake -n --configfile config/full.yaml --quiet rules >/dev/null
# --durations: every run (CI included) prints its slowest tests, so the suite's time is watched, not guessed.
# pytest-xdist: one worker per core, at most 4 (most tests run a toy workflow on one core); a worker
# takes whole test files, the longest first (tests/conftest.py groups and orders them).
# MORPHLEARN_TEST_WORKERS=0 runs in-process.
workers=${MORPHLEARN_TEST_WORKERS:-$(python -c 'import os; print(min(4, len(os.sched_getaffinity(0))))')}
echo "== pytest ($workers workers)"; python -m pytest -q -ra --durations=40 -n "$workers" --dist loadgroup --no-loadscope-reorder "$@"
