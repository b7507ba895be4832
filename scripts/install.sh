#!/usr/bin/env bash
# Install everything the project needs on a fresh machine (Linux x86_64, Python 3.11 with pip): the exact versions of
# requirements.lock, then this checkout's package (editable: the notebooks and tests use this checkout's code).
set -euo pipefail
cd "$(dirname "$0")/.."
PY="${PYTHON:-python3}"
# OpenSeesPy (notebook 03's FE cross-check) links against the system BLAS/LAPACK runtime.
# (the cache is read once, not piped into grep -q: under pipefail, grep's early exit gives ldconfig SIGPIPE and the
# test fails at random; /sbin is not on a non-root user's PATH on Debian)
libs="$(PATH="$PATH:/sbin:/usr/sbin" ldconfig -p 2>/dev/null || true)"
if ! { grep -q 'libblas\.so\.3' <<<"$libs" && grep -q 'liblapack\.so\.3' <<<"$libs"; }; then
  if command -v apt-get >/dev/null 2>&1 && [ "$(id -u)" = 0 ]; then
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libblas3 liblapack3 >/dev/null
  else
    echo "warning: libblas3/liblapack3 missing and apt-get unavailable (not root): OpenSeesPy will not import" >&2
  fi
fi
if ! "$PY" -c 'import sys; sys.exit(sys.version_info[:2] != (3, 11))'; then
  echo "requirements.lock is resolved for Python 3.11, and $PY is Python $("$PY" -c 'import sys; print(sys.version.split()[0])'):" \
       "run PYTHON=python3.11 bash scripts/install.sh, or install without the lock: pip install '.[cluster,docs,fe,notebooks,test]'" >&2
  exit 2
fi
"$PY" -m pip install --disable-pip-version-check -q -r requirements.lock
# the package itself, built with the locked setuptools (no download of another one)
"$PY" -m pip install --disable-pip-version-check -q --no-deps --no-build-isolation -e .
