#!/usr/bin/env bash
# Prepare .venv-blender: Blender as a Python module (bpy), the real consumer the Blender
# integration tests (tests/blender/) import our USD and BVH exports into.
#
# bpy lives in its own virtual environment because it pins numpy<2 (the main environment uses
# numpy 2) and its wheels are tied to one Python minor version: Blender 4.2-5.0 ship Python 3.11,
# the same minor version as animstudio's, so `python3 -m venv` with the project's interpreter works.
#
# Idempotent: does nothing if .venv-blender already imports bpy.
# Usage: scripts/setup_blender.sh [VENV_DIR]   (default: .venv-blender at the repository root)
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
VENV="${1:-$ROOT/.venv-blender}"
PYTHON="${PYTHON:-python3}"
# The bpy release the tests were written against; override with BPY_SPEC=bpy==x.y.z.
BPY_SPEC="${BPY_SPEC:-bpy==4.5.4}"

if [ -x "$VENV/bin/python" ] && "$VENV/bin/python" -c "import bpy" >/dev/null 2>&1; then
    echo "setup_blender: $VENV already imports bpy ($("$VENV/bin/python" -c 'import bpy; print(bpy.app.version_string)' 2>/dev/null | tail -n 1))"
    exit 0
fi

minor="$("$PYTHON" -c 'import sys; print(f"{sys.version_info[0]}.{sys.version_info[1]}")')"
if [ "$minor" != "3.11" ]; then
    echo "setup_blender: $PYTHON is Python $minor; bpy 4.2-5.0 wheels need Python 3.11 (set PYTHON=python3.11)" >&2
    exit 1
fi

echo "setup_blender: creating $VENV with $PYTHON ($minor) and installing $BPY_SPEC"
"$PYTHON" -m venv "$VENV"
"$VENV/bin/python" -m pip install --quiet --upgrade pip
"$VENV/bin/python" -m pip install --quiet "$BPY_SPEC"
"$VENV/bin/python" -c "import bpy; print('setup_blender: bpy', bpy.app.version_string, 'ready')"
