#!/usr/bin/env bash
# Install everything the project needs on a fresh machine (Python 3.11 with pip).
set -euo pipefail
cd "$(dirname "$0")/.."
PY="${PYTHON:-python3}"
"$PY" -m pip install --disable-pip-version-check -q -r requirements.txt
"$PY" -m pip install --disable-pip-version-check -q --no-deps -e .
