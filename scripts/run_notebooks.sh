#!/usr/bin/env bash
# Main job: execute every notebook in order with papermill.
#
#   bash scripts/run_notebooks.sh                       # paper settings: figures/ and data/results/
#   bash scripts/run_notebooks.sh --params p.yaml --out runs/my_study
#   bash scripts/run_notebooks.sh --params study_dir/ --out runs/my_study
#   bash scripts/run_notebooks.sh --resume                # after a stop: skips the notebooks this job ran to the end
#   bash scripts/run_notebooks.sh --only 04b_large_trusses,08_worst_case_mu   # these notebooks alone, in order
#
# Executed copies go to <out>/notebooks (default runs/latest), each with an HTML copy beside it. With --out, figures and
# results JSON go to <out>/figures and <out>/results, leaving the committed ones untouched. Without --out and --params
# (the paper's run), the executed copies are also kept with the project in notebooks/executed/ (scripts/keep_executed.py).
# --params takes a YAML file of parameters applied to every notebook (each name must be declared by at least one
# notebook; the others ignore it), or a folder: its all.yaml (if any)
# applies to every notebook, then NN_name.yaml (if any) to that notebook alone, overriding
# all.yaml (the layout of tests/smoke/); a per-notebook file's names must be that notebook's, and a file named after
# no notebook is refused (scripts/check_params.py). --resume continues the job stopped in the output folder (give the
# same --out and --params): it skips the notebooks, from the first on, that this job ran to the end with their current
# code (an executed copy newer than the job's start, every cell run, none failed: scripts/keep_executed.py), and runs
# every notebook from the first one that was not, since a later notebook may read an earlier one's results. --only
# runs the notebooks named (comma-separated, without .ipynb), in order, and keeps only those: whether one of them reads
# another notebook's results, and whether that one is up to date, is then the caller's to judge. Several notebooks
# share parameter names with different meanings (h, n_grid, h_values, n_compare, seed, ...): give those per notebook.
set -euo pipefail
PY="${PYTHON:-python3}"
usage="use --out DIR, --params FILE.yaml|DIR, --resume, --only NAME[,NAME...], --no-install"
out="" params="" resume="" only=""
while [ $# -gt 0 ]; do
  case "$1" in
    --out|--params|--only) [ $# -ge 2 ] || { echo "$1 needs a value ($usage)" >&2; exit 2; }
                    case "$1" in --out) out="$2" ;; --params) params="$2" ;; *) only="$2" ;; esac; shift 2 ;;
    --no-install) NO_INSTALL=1; shift ;;
    --resume) resume=1; shift ;;
    *) echo "unknown argument $1 ($usage)" >&2; exit 2 ;;
  esac
done
# paths given on the command line are the caller's, not the project folder's (the script changes folder below)
case "$out" in ""|/*) ;; *) out="$PWD/$out" ;; esac
case "$params" in ""|/*) ;; *) params="$PWD/$params" ;; esac
[ -z "$params" ] || [ -e "$params" ] || { echo "no parameter file or folder $params" >&2; exit 2; }
[ -z "$resume" ] || [ -z "$only" ] || { echo "--resume and --only exclude each other ($usage)" >&2; exit 2; }
cd "$(dirname "$0")/.."
export LC_COLLATE=C  # byte order, whatever the locale (en_US sorts 06b_ before 06_: it ignores '_')
notebooks=(notebooks/[0-9][0-9]*_*.ipynb)
if [ -n "$only" ]; then
  chosen=()
  for name in ${only//,/ }; do
    [ -f "notebooks/$name.ipynb" ] || { echo "--only: no notebook $name; the notebooks are: $(basename -a -s .ipynb "${notebooks[@]}" | tr '\n' ' ')" >&2; exit 2; }
  done
  for nb in "${notebooks[@]}"; do
    case ",$only," in *",$(basename "$nb" .ipynb),"*) chosen+=("$nb") ;; esac
  done
  notebooks=("${chosen[@]}")
fi
# the kernels (run in notebooks/) import this checkout's package, whatever checkout is installed in editable mode
export PYTHONPATH="$PWD/lib${PYTHONPATH:+:$PYTHONPATH}"
[ -n "${NO_INSTALL:-}" ] || bash scripts/install.sh
# every parameter name and per-notebook file checked against the notebooks before anything runs
[ -z "$params" ] || "$PY" scripts/check_params.py "$params" || { echo "(parameters refused: nothing was run)" >&2; exit 2; }
# One BLAS thread: the models are small (<= 1324 states) and two OpenBLAS threads competing with any other
# process for the 2 cores slow LAPACK down 10-50x; parallelism is at the task level (synthesis threads, Dask).
export OPENBLAS_NUM_THREADS="${OPENBLAS_NUM_THREADS:-1}" OMP_NUM_THREADS="${OMP_NUM_THREADS:-1}"
extra=()
if [ -n "$out" ]; then
  extra+=(-p figures_dir "$out/figures" -p results_dir "$out/results")
  nbdir="$out/notebooks"
else
  nbdir="runs/latest/notebooks"
fi
[ -z "$params" ] || [ -d "$params" ] || extra+=(-f "$params")
mkdir -p "$nbdir"
stamp="$nbdir/.job-start"  # when the job began: a resumed job skips only copies it wrote itself
if [ -z "$resume" ] && [ -z "$only" ]; then
  touch "$stamp"
elif [ -n "$resume" ] && [ ! -f "$stamp" ]; then
  echo "no stopped job to resume in $nbdir (no $stamp): run without --resume" >&2; exit 2
fi
skipping="$resume"
# A notebook whose final checks fail (e.g. notebook 07's PSO-versus-grid check) has already saved its results and
# figures: the later notebooks still run, and the job exits non-zero at the end naming the failed ones.
failed=() ours=()  # ours: the notebooks this job ran or, resumed, had run (the ones to keep)
for nb in "${notebooks[@]}"; do
  copy="$nbdir/$(basename "$nb")"
  ours+=("$(basename "$nb" .ipynb)")
  if [ -n "$skipping" ] && [ "$copy" -nt "$stamp" ] && "$PY" scripts/keep_executed.py --finished "$copy" "$nb"; then
    echo "== $nb: run to the end by this job, skipped (--resume)"
    continue
  fi
  skipping=""
  echo "== $nb"
  own=()  # a parameter folder's files for this notebook: all.yaml, then its own (later files override earlier ones)
  if [ -d "$params" ]; then
    for f in "$params/all.yaml" "$params/$(basename "$nb" .ipynb).yaml"; do [ ! -f "$f" ] || own+=(-f "$f"); done
  fi
  "$PY" -m papermill --log-level WARNING --cwd notebooks "$nb" "$nbdir/$(basename "$nb")" ${extra[@]+"${extra[@]}"} \
    ${own[@]+"${own[@]}"} || failed+=("$(basename "$nb")")
  # an HTML copy beside the executed one (a failed notebook's too: it shows the error cell)
  [ ! -f "$nbdir/$(basename "$nb")" ] || "$PY" -m nbconvert --log-level WARN --to html "$nbdir/$(basename "$nb")" \
    || echo "warning: no HTML copy of $(basename "$nb")" >&2
done
echo "executed notebooks in $nbdir"
# the paper's run (no --out, no --params) is the one kept with the project: notebooks/executed/ (scripts/keep_executed.py)
if [ -z "$out" ] && [ -z "$params" ]; then
  "$PY" scripts/keep_executed.py "$nbdir" "${ours[@]}" || echo "warning: the executed copies were not kept (see above)" >&2
fi
if [ ${#failed[@]} -gt 0 ]; then
  echo "FAILED (see the error cell of each executed copy in $nbdir): ${failed[*]}" >&2
  exit 1
fi
