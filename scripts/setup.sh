#!/usr/bin/env bash
# Installs animstudio (and the Python packages it needs) into the current Python.
# Idempotent: a second run only checks that everything is in place.
set -euo pipefail
cd "$(dirname "$0")/.."
PYTHON="${PYTHON:-python3}"
"$PYTHON" -m pip install --disable-pip-version-check -q -e .
