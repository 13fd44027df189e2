#!/usr/bin/env bash
# The main job until the cell exists (issue 5): set up, then run the composite sheet through the
# paper's five-stage clamp protocol and write one PLY per stage plus summary.json to out/demo.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
./build/twin/twin solve twin/scenarios/composite_five_stages.json --out out/demo "$@"
