#!/usr/bin/env bash
# Installs crowdcloth's build and test dependencies from Debian 12 packages.
# Skips apt entirely when every package is already present.
set -euo pipefail
packages=(build-essential cmake ninja-build pkg-config git
          libeigen3-dev libembree-dev libtbb-dev libassimp-dev libsuitesparse-dev
          libosmesa6-dev libgtest-dev libgmock-dev libbenchmark-dev libstb-dev libbullet-dev
          libcli11-dev nlohmann-json3-dev ffmpeg python3-matplotlib
          clang libclang-rt-14-dev  # the sanitizer and fuzzer build (scripts/configure-sanitizers.sh)
          cppcheck clang-tidy)      # static analysis (scripts/run-analysis.sh)
missing=()
for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
    echo "install-deps: all ${#packages[@]} packages present"
    exit 0
fi
echo "install-deps: installing ${missing[*]}"
sudo_cmd=""
[ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
$sudo_cmd apt-get update
DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y --no-install-recommends "${missing[@]}"
