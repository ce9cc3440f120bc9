#!/usr/bin/env bash
# The README's first command: set up animstudio and render the shipped demo script with the
# shipped Kohonen weights (no training step, no download) to exports/demo.usda.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
animstudio render scripts_gait/demo.gait -o exports/demo.usda
