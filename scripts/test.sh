#!/usr/bin/env bash
# The README's test command: set up (install, configure, build), then run every test.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
ctest --test-dir build --output-on-failure -j2
