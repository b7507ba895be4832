#!/usr/bin/env bash
# Test command: install, then the unit tests of the package and every notebook under nbval.
#
# Each notebook is first given its smoke parameters (tests/smoke/NN_*.yaml: output folders under build/smoke, smaller
# loops, never weaker physics checks) by papermill --prepare-only; nbval then executes it, and the notebook's own
# asserts are the checks.
#
# Two plain pytest processes share the two cores (TEST_WORKERS=1: one process, everything in order). The first runs
# the notebook chain, 07 then 08 (08 analyses the design that 07 stores in build/smoke/results, and certifies three
# designs' bounds over all frequencies: the longest notebook), then 06c (it reads only data/results/) and the site's
# build (tests/test_site.py), which balance the two; the second runs the other unit tests, the README's new-range
# rerun of notebook 07 (tests/test_new_h_range.py, itself two smoke runs of 07) among them, and the other notebooks.
# pytest runs the files of one process in the order given on its command line, each notebook's cells in order in one
# kernel: nothing here rests on how a plugin distributes tests. Extra arguments go to both processes (e.g. -x, or -k NAME: a process that then selects no test counts as
# passed). Every kernel logs the asserts it runs; once both are done, tests/smoke_asserts_ran.py fails for a notebook one
# of whose asserts never ran (scripts/smoke_asserts.py). The last line sums up the runs.
set -euo pipefail
cd "$(dirname "$0")/.."
PY="${PYTHON:-python3}"
workers="${TEST_WORKERS:-2}"
case "$workers" in 1|2) ;; *) echo "TEST_WORKERS must be 1 (one process) or 2 (two, the default), got '$workers'" >&2; exit 2 ;; esac
[ -n "${NO_INSTALL:-}" ] || bash scripts/install.sh
# the kernels and tests import this checkout's package, whatever checkout is installed in editable mode
export PYTHONPATH="$PWD/lib${PYTHONPATH:+:$PYTHONPATH}"
# One BLAS thread: the models are small (<= 1324 states) and two OpenBLAS threads competing with any other
# process for the 2 cores slow LAPACK down 10-50x; parallelism is at the task level (synthesis threads, Dask).
export OPENBLAS_NUM_THREADS="${OPENBLAS_NUM_THREADS:-1}" OMP_NUM_THREADS="${OMP_NUM_THREADS:-1}"
export MPLBACKEND=Agg
rm -rf build/smoke build/test-logs && mkdir -p build/smoke build/test-logs
# every kernel logs the asserts it runs (scripts/smoke_asserts.py); the last step names those the smoke runs left out
export SMOKE_ASSERT_LOG="$PWD/build/smoke/asserts" SMOKE_ASSERT_SCRIPT="$PWD/scripts/smoke_asserts.py"
export IPYTHONDIR="$PWD/build/smoke/ipython"
unset PYTHONOPTIMIZE  # asserts compiled away would be logged as run
mkdir -p "$IPYTHONDIR/profile_default/startup"
"$PY" scripts/smoke_asserts.py --startup > "$IPYTHONDIR/profile_default/startup/00-smoke-asserts.py"
chain=() late=() others=()
# byte order, whatever the locale (en_US sorts 06b_ before 06_: it ignores '_')
export LC_COLLATE=C
for nb in notebooks/[0-9][0-9]*_*.ipynb; do
  name="$(basename "$nb" .ipynb)"
  args=()
  if [ -f "tests/smoke/$name.yaml" ]; then args=(-f "tests/smoke/$name.yaml"); fi
  "$PY" -m papermill --log-level WARNING --prepare-only "$nb" "build/smoke/$name.ipynb" "${args[@]}"
  case "$name" in
    07_*|08_*) chain+=("build/smoke/$name.ipynb") ;;
    06c_*) late+=("build/smoke/$name.ipynb") ;;
    *) others+=("build/smoke/$name.ipynb") ;;
  esac
done
# (-p no:randomly: a test-order plugin left in a reused environment must not reorder the chain)
pytest=("$PY" -m pytest --nbval-lax --nbval-current-env -p no:cacheprovider -p no:randomly)

# run NAME ARGS...: one pytest process, its report in build/test-logs/NAME.xml; prints "NAME STATUS" for the summary
# (status 5, nothing selected, counts as passed when the caller gave arguments such as -k)
status() { local rc=$1; if [ "$rc" = 5 ] && [ "$nargs" -gt 0 ]; then echo 0; else echo "$rc"; fi; }
nargs=$#
reports=()
if [ "$workers" = 1 ]; then
  "${pytest[@]}" --junitxml=build/test-logs/all.xml tests "${chain[@]}" ${late[@]+"${late[@]}"} "${others[@]}" "$@" && rc=0 || rc=$?
  rc="$(status "$rc")"; reports+=("all=build/test-logs/all.xml=$rc")
else
  chain_rc=0
  # the second process always runs: the site's build at least (the first one leaves tests/test_site.py out)
  # its own session, so that an interrupted run also ends its kernels and Dask workers
  own_session=(); ! command -v setsid >/dev/null || own_session=(setsid -w)
  ${own_session[@]+"${own_session[@]}"} "${pytest[@]}" --junitxml=build/test-logs/chain.xml ${chain[@]+"${chain[@]}"} \
    ${late[@]+"${late[@]}"} tests/test_site.py "$@" > build/test-logs/chain.log 2>&1 &
  chain_pid=$!
  trap 'kill -- -"$chain_pid" 2>/dev/null || true' EXIT INT TERM
  echo "notebooks ${chain[*]##*/} ${late[*]##*/} and the site's build run in a second process (log: build/test-logs/chain.log)"
  "${pytest[@]}" --junitxml=build/test-logs/main.xml tests --ignore=tests/test_site.py "${others[@]}" "$@" && rc=0 || rc=$?
  rc="$(status "$rc")"; reports+=("main=build/test-logs/main.xml=$rc")
  wait "$chain_pid" && chain_rc=0 || chain_rc=$?
  trap - EXIT INT TERM
  chain_rc="$(status "$chain_rc")"; reports+=("chain=build/test-logs/chain.xml=$chain_rc")
  echo "== the second process (${chain[*]##*/} ${late[*]##*/}, the site), exit status $chain_rc:"
  cat build/test-logs/chain.log
  [ "$chain_rc" = 0 ] || [ "$rc" != 0 ] || rc=$chain_rc
fi
# after every notebook: did each of their asserts run under the smoke parameters?
"${pytest[@]}" --junitxml=build/test-logs/asserts.xml tests/smoke_asserts_ran.py "$@" && arc=0 || arc=$?
arc="$(status "$arc")"; reports+=("asserts=build/test-logs/asserts.xml=$arc")
[ "$arc" = 0 ] || [ "$rc" != 0 ] || rc=$arc
"$PY" scripts/test_summary.py "${reports[@]}" || true
exit "$rc"
