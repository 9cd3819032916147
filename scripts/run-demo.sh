#!/usr/bin/env bash
# Installs dependencies, builds, and runs the main job: the crowd sample on its built-in default
# scene (200 mannequins in a plaza, capes, skirts, dresses and ponchos, a moving camera, budgeted
# LOD). Writes crowd_out/: frames/ (PNG), crowd.mp4, summary.json, frames.csv, summary.png.
# Extra arguments go to cc_crowd (see cc_crowd --help; e.g. --characters 1000 --no-render, --scaling).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
./build/samples/crowd/cc_crowd "$@"
