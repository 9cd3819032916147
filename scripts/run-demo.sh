#!/usr/bin/env bash
# Installs dependencies, builds, and runs the main job: the crowd sample on its built-in default
# scene (200 mannequins in a plaza, capes and skirts, a moving camera, budgeted LOD). Frames go to
# crowd_out/frames (PNG; crowd_out/crowd.mp4 when ffmpeg is present), stats to crowd_out/.
# Extra arguments go to cc_crowd (e.g. --characters 1000 --no-render, --scaling, --tradeoff).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
./build/samples/crowd/cc_crowd "$@"
