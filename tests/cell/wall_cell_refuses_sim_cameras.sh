#!/usr/bin/env bash
# A cell on "clock": "wall" given the fake world's cameras (PREPREG_V4L2_EMULATION_CLOCK=sim, as
# cell_world's --emulation-env writes) refuses to start, exit 1, naming the setting to change.
#   wall_cell_refuses_sim_cameras.sh CELL_CONTROLLER SOURCE_DIR
set -euo pipefail
controller=$1 source_dir=$2
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
# The fake cell's config (with the files it names) on the wall.
cp -r "$source_dir/cell/examples/." "$dir/"
sed -i 's/"clock": "sim"/"clock": "wall"/' "$dir/fake_cell.json"
grep -q '"clock": "wall"' "$dir/fake_cell.json"
set +e
PREPREG_V4L2_EMULATION_CLOCK=sim "$controller" --config "$dir/fake_cell.json" > "$dir/out" 2>&1
status=$?
set -e
cat "$dir/out"
[[ $status -eq 1 ]] || { echo "expected exit 1, got $status"; exit 1; }
grep -q 'set cell.clock to "sim"' "$dir/out" || { echo "the message does not name cell.clock"; exit 1; }
echo "refused as expected"
