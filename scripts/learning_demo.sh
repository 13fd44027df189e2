#!/usr/bin/env bash
# What the cell learns from its own cameras, shown on the fake cell (issue 35): the four-grasp
# experiment with the config's material (before), the cell's diagnosis of the settled states it
# saw in that run (build/cell/diagnose_observed --config: the same rules and settings the
# running cell uses, run here on both cores instead of its idle background worker), then, when it
# named an effect and adopted it, the same experiment with the learned material (after), and the
# two runs side by side (build/cell/compare_experiments). Takes 15-25 minutes on 2 cores, most of
# it the diagnosis.
#
#   scripts/learning_demo.sh [--config CELL.json] [--world WORLD.json] [--out DIR]
#
# Writes DIR (default out/learning_demo): before/, diagnosis/ (train/, held_out/, report/),
# after/, comparison.txt. Exit status: 0 shown, 3 nothing adopted (no after run), else failure.
set -uo pipefail
cd "$(dirname "$0")/.."
config=cell/examples/fake_cell.json
world=sim_hw/examples/fake_world.json
out=out/learning_demo
while (($#)); do
  case "$1" in
    --config) config=$2; shift 2 ;;
    --world) world=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    *) echo "learning_demo.sh: unknown option '$1' (see the header of $0)" >&2; exit 2 ;;
  esac
done
for exe in build/cell/diagnose_observed build/cell/compare_experiments; do
  [[ -x $exe ]] || { echo "learning_demo.sh: $exe is missing: run scripts/setup.sh first" >&2; exit 2; }
done
rm -rf "$out"
mkdir -p "$out"
cell() {  # the fake cell as run_demo.sh runs it, in a private network namespace without a route
  if ip route get 239.255.76.67 >/dev/null 2>&1; then
    bash scripts/fake_cell.sh "$@"
  else
    bash scripts/with_loopback_lcm.sh bash scripts/fake_cell.sh "$@"
  fi
}

echo "== before: the config's material"
cell --config "$config" --world "$world" --out "$out/before" > "$out/before.log" 2>&1
grep -A6 '^experiment' "$out/before.log"
[[ -f $out/before/experiment.json && -f $out/before/observed_trial/trial.json ]] ||
  { echo "learning_demo.sh: the first run wrote no experiment or observed trial (see $out/before.log)" >&2; exit 1; }

echo "== the cell's diagnosis of the states it saw"
build/cell/diagnose_observed "$out/before/observed_trial" --config "$config" --out "$out/diagnosis" --quiet
status=$?
if ((status == 3)); then
  echo "learning_demo.sh: nothing adopted; the twin keeps the config's material (report: $out/diagnosis/report/report.md)"
  exit 3
fi
((status == 0)) || { echo "learning_demo.sh: the diagnosis failed (exit $status)" >&2; exit 1; }

echo "== after: the learned material"
cell --config "$config" --world "$world" --out "$out/after" -- --material "$out/diagnosis/report/material_augmented.json" \
  > "$out/after.log" 2>&1
grep -A6 '^experiment' "$out/after.log"
[[ -f $out/after/experiment.json ]] ||
  { echo "learning_demo.sh: the second run wrote no experiment (see $out/after.log)" >&2; exit 1; }

echo "== before -> after"
build/cell/compare_experiments "$out/before/experiment.json" "$out/after/experiment.json" | tee "$out/comparison.txt"
