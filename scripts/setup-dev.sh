#!/usr/bin/env bash
# Installs everything the test suite needs: the package with its dev extras, Debian's chromium
# for the browser tests, and Blender-as-a-module in its own venv for the export consumer tests.
set -euo pipefail
cd "$(dirname "$0")/.."
PYTHON="${PYTHON:-python3}"
"$PYTHON" -m pip install --disable-pip-version-check -q -e '.[dev]'

if ! command -v chromium >/dev/null 2>&1; then
    SUDO=""
    [ "$(id -u)" -eq 0 ] || SUDO="sudo"
    $SUDO apt-get update -q
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q chromium
fi

if [ -f scripts/setup_blender.sh ]; then
    bash scripts/setup_blender.sh
fi
