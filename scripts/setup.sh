#!/usr/bin/env bash
# One idempotent set-up step for a fresh Debian 12 machine: install exactly the Debian packages
# the project uses (no recommends), then configure and build (Release, -j2) into build/.
# Re-running it only rebuilds what changed. Set PREPREG_SKIP_APT=1 to skip the install step
# (for machines where the packages are already present and apt is not usable).
set -euo pipefail
cd "$(dirname "$0")/.."

source scripts/packages.sh
source scripts/phase.sh
phase "install packages" bash scripts/install_packages.sh "${PROJECT_PACKAGES[@]}"
# Ninja for a new tree (when installed); a tree configured before keeps its generator (CMake
# refuses a change).
generator=()
[[ -f build/CMakeCache.txt ]] || ! command -v ninja > /dev/null || generator=(-G Ninja)
phase "configure Release" cmake -S . -B build "${generator[@]}" -DCMAKE_BUILD_TYPE=Release
phase "build Release" cmake --build build -j2
