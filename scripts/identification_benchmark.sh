#!/usr/bin/env bash
# Identification benchmark (issue 3): the paper's method (screening + ISRES) and ours
# (equilibrium tangents + Levenberg-Marquardt) on the composite protocol: one lab trial (seed 1,
# five stages) to train, another (seed 2) to test. Prints wall time, simulations, estimates and train/test errors.
# The trials' sheet is the lab's default truth: the reference spline shell (docs/reference_sheet.md),
# physics the twin does not share, converging, its own error in each truth's lab.json;
# TRUTH_MODEL=independent the lab's finite-difference plate (issue 33), TRUTH_MODEL=twin the
# twin's own model (6760 triangles, the benchmark before issue 33). Making the two trials takes minutes.
# Usage: [TRUTH_MODEL=spline_shell|independent|twin] bash scripts/identification_benchmark.sh [TWIN_TRIANGLES (default 1500)]
set -euo pipefail
cd "$(dirname "$0")/.."
triangles="${1:-1500}"
truth_model="${TRUTH_MODEL:-spline_shell}"
dir=out/identification/$truth_model
mkdir -p "$dir"
for seed in 1 2; do
  # Trials made by another lab (an older truth, another model) are made again.
  if ! grep -qs "\"truth_model\": \"$truth_model\"" "$dir/composite_$seed.truth/lab.json"; then
    rm -rf "$dir/composite_$seed" "$dir/composite_$seed.truth"
  fi
  if [ ! -f "$dir/composite_$seed/trial.json" ]; then
    ./build/sim_hw/scanner_lab --specimen composite --seed "$seed" --truth-model "$truth_model" \
      --out "$dir/composite_$seed" --no-scans
  fi
done
./build/twin/twin identify --train "$dir/composite_1" --test "$dir/composite_2" --method both \
  --triangles "$triangles" --out "$dir/composite_identified.json" --residuals "$dir/residuals" --quiet
echo
echo "lab truth (never read by identification):"
grep -E '"(tensile_stiffness(_u)?_N_m|shear_stiffness_N_m|bending_rigidity(_u)?_Nm)"' "$dir/composite_1.truth/material.json"
# The error budget beside the figures above: the scanner's noise and the truth's own error per
# stage of the test trial (the twin's discretisation is identify's own "discretisation" line).
if command -v jq > /dev/null; then
  jq -r '"scanner noise \(.marker_noise_m * 1e3) mm per coordinate (1 sigma); truth: \(.reference)"' \
    "$dir/composite_2.truth/lab.json"
  jq -r '.truth_error[]? | "truth error, test stage \(.stage): \(.summary)"' "$dir/composite_2.truth/lab.json"
fi
