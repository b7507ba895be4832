#!/usr/bin/env bash
# The project's site: the README, the pages of docs/, the kept executed notebooks of notebooks/executed/ (shown with
# their outputs as the main job left them, never executed here), the benchmarks' table and the API reference
# generated from the package's docstrings, built by Sphinx (docs/conf.py) into build/site/ (git-ignored).
#
#   bash scripts/site.sh                    # install from the lock, then build; open build/site/index.html
#   bash scripts/site.sh --no-install --out DIR
#
# Any Sphinx warning (a broken link or image, a docstring Sphinx cannot read, a page in no table of contents) fails
# the build, after all of them are listed.
set -euo pipefail
PY="${PYTHON:-python3}"
out=""
while [ $# -gt 0 ]; do
  case "$1" in
    --out) [ $# -ge 2 ] || { echo "--out needs a folder" >&2; exit 2; }; out="$2"; shift 2 ;;
    --no-install) NO_INSTALL=1; shift ;;
    *) echo "unknown argument $1 (use --out DIR, --no-install)" >&2; exit 2 ;;
  esac
done
case "$out" in "") ;; /*) ;; *) out="$PWD/$out" ;; esac
cd "$(dirname "$0")/.."
out="${out:-$PWD/build/site}"
[ -n "${NO_INSTALL:-}" ] || bash scripts/install.sh
export PYTHONPATH="$PWD/lib${PYTHONPATH:+:$PYTHONPATH}"
# the output folder is replaced: refuse one that holds anything but an earlier build (never the checkout or build/)
if [ -e "$out" ] && [ ! -f "$out/.buildinfo" ] && [ -n "$(ls -A "$out" 2>/dev/null || echo file)" ]; then
  echo "--out $out exists and is no earlier build of the site (no .buildinfo): give a new or empty folder" >&2; exit 2
fi
# autosummary's pages are regenerated from the package every time (a removed module leaves no page behind)
rm -rf docs/api "$out"
"$PY" -m sphinx -b html -c docs -W --keep-going -q -d "$out/.doctrees" . "$out"
# the site's front page is docs/index (the source folder is the repository): the root of the site leads there
printf '<!DOCTYPE html>\n<meta charset="utf-8">\n<meta http-equiv="refresh" content="0; url=docs/index.html">\n<title>trusscodesign</title>\n<a href="docs/index.html">trusscodesign</a>\n' > "$out/index.html"
echo "site in $out (open $out/index.html)"
