#!/usr/bin/env bash
# The README's test command: installs what the tests need (idempotent), then runs the whole suite.
# Extra arguments go to pytest (e.g. scripts/test.sh tests/script -x).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup-dev.sh
PYTHON="${PYTHON:-python3}"
exec "$PYTHON" -m pytest "$@"
