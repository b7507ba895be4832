#!/usr/bin/env bash
# Test command: install, then the unit tests of lib/ and every notebook under nbval.
#
# Each notebook is first given its smoke parameters (tests/smoke/NN_*.yaml: output folders
# under build/smoke, smaller loops, never weaker physics checks) by papermill --prepare-only;
# nbval then executes it, and the notebook's own asserts are the checks.
set -euo pipefail
cd "$(dirname "$0")/.."
PY="${PYTHON:-python3}"
# the nbval kernels (run in build/smoke) import this checkout's lib, whatever checkout is installed in editable mode
export PYTHONPATH="$PWD${PYTHONPATH:+:$PYTHONPATH}"
[ -n "${NO_INSTALL:-}" ] || bash scripts/install.sh
# One BLAS thread: the models are small (<= 1324 states) and two OpenBLAS threads competing with any other
# process for the 2 cores slow LAPACK down 10-50x; parallelism is at the task level (synthesis threads, Dask).
export OPENBLAS_NUM_THREADS="${OPENBLAS_NUM_THREADS:-1}" OMP_NUM_THREADS="${OMP_NUM_THREADS:-1}"
export MPLBACKEND=Agg
rm -rf build/smoke && mkdir -p build/smoke
for nb in notebooks/[0-9][0-9]_*.ipynb; do
  name="$(basename "$nb" .ipynb)"
  args=()
  if [ -f "tests/smoke/$name.yaml" ]; then args=(-f "tests/smoke/$name.yaml"); fi
  "$PY" -m papermill --log-level WARNING --prepare-only "$nb" "build/smoke/$name.ipynb" "${args[@]}"
done
# Two pytest-xdist workers (TEST_WORKERS; 0: one process): each test module and each notebook stays on one worker,
# and notebooks 07 and 08 (08 reads what 07 stores) run first, in order, on one worker (tests/conftest.py)
"$PY" -m pytest tests build/smoke --nbval-lax --nbval-current-env -p no:cacheprovider \
  -n "${TEST_WORKERS:-2}" --dist loadgroup --no-loadscope-reorder "$@"
