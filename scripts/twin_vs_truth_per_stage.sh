#!/bin/bash
# The twin at the lab's true material against a trial's markers, stage by stage (no fit): per
# stage the mean / max distance from each seen marker to the twin's same material point, for
# each resolution, and between successive resolutions (the twin's own discretisation; with
# three, whether it converges). On a trial made with `scanner_lab --marker-noise-m 0` the first
# is the twin's distance from the truth itself; where it exceeds the twin's discretisation change and the
# truth's own error (printed when the material's directory has the lab.json that gives it),
# the difference is model form (the residual files say where on the sheet).
#   scripts/twin_vs_truth_per_stage.sh TRIAL_DIR TRUE_MATERIAL.json [OUT_DIR] [TRIANGLES...]
# e.g. scripts/twin_vs_truth_per_stage.sh out/ref/composite_1 out/ref/composite_1.truth/material.json out/ref/twin 1500 6000
set -euo pipefail
trial=${1:?trial directory}; material=${2:?true material file}; out=${3:-out/twin_vs_truth_per_stage}
shift $(( $# < 3 ? $# : 3 ))
sizes=("$@"); [ ${#sizes[@]} -gt 0 ] || sizes=(1500 6000)
twin=${TWIN:-build/twin/twin}
name=$(basename "$trial")
mkdir -p "$out"
for n in "${sizes[@]}"; do
  log="$out/twin_$n.log"
  # A resolution already run on this trial (its result newer than the trial) is reused.
  if [ "$out/twin_$n.json" -nt "$trial/trial.json" ] && [ -d "$out/$n" ]; then continue; fi
  "$twin" identify --train "$trial" --start "$material" --parameters bending_Nm --max-evaluations 1 \
    --no-discretisation-check --quiet --triangles "$n" --residuals "$out/$n" --out "$out/twin_$n.json" > "$log" 2>&1 ||
    { echo "twin identify at $n triangles failed: see $log" >&2; exit 1; }
  if grep -q 'simulation failed' "$log"; then echo "$n triangles: $(grep -oE 'simulation failed: .*' "$log" | head -1)" >&2; exit 1; fi
done
stages() { ls "$out/${sizes[0]}/train/$name" | sed -n 's/_residuals\.csv$//p'; }
# Mean / max (mm) of column 13 (correspondence_m) over the rows where it is a number.
distance() {
  awk -F, 'NR > 1 && $13 != "nan" && $13 != "" { s += $13; if ($13 > m) m = $13; k++ }
           END { if (k) printf "%.2f / %.2f mm (%d markers)", 1e3 * s / k, 1e3 * m, k; else printf "no markers" }' "$1"
}
# Mean / max (mm) of the distance between two files' predicted markers (columns 7-9), row by row,
# over the rows whose correspondence is a number (seen markers).
between() {
  paste -d, "$1" "$2" | awk -F, 'NR > 1 && $13 != "nan" && $13 != "" {
      d = sqrt(($7 - $21)^2 + ($8 - $22)^2 + ($9 - $23)^2); s += d; if (d > m) m = d; k++ }
    END { if (k) printf "%.2f / %.2f mm", 1e3 * s / k, 1e3 * m; else printf "no markers" }'
}
# The truth's own error at a stage, when the material sits in a truth directory whose lab.json
# has it (the reference shell's: its seen markers' change between its two finest levels).
lab_json="$(dirname "$material")/lab.json"
truth_error() {
  [ -f "$lab_json" ] && command -v jq > /dev/null || return 0
  jq -r --arg s "$1" '.truth_error[]? | select(.stage == $s) |
    "  | truth itself: \(.finest_change_mean_m * 1e3 * 100 | round / 100) / \(.finest_change_max_m * 1e3 * 100 | round / 100) mm" +
    (if .one_branch then "" else " (levels on two branches)" end)' "$lab_json"
}
echo "$name at the true material: markers vs the twin's same material points, mean / max per stage"
for s in $(stages); do
  line="stage $s:"
  for n in "${sizes[@]}"; do
    tris=$(grep -oE 'twin mesh [0-9]+' "$out/twin_$n.log" | grep -oE '[0-9]+' | head -1 || echo "$n")
    line+="  twin $tris: $(distance "$out/$n/train/$name/${s}_residuals.csv")"
  done
  # The twin's own change between successive resolutions (with three, its order shows).
  for ((k = 1; k < ${#sizes[@]}; k++)); do
    a=${sizes[k-1]}; b=${sizes[k]}
    line+="  | twin $a vs $b: $(between "$out/$a/train/$name/${s}_residuals.csv" "$out/$b/train/$name/${s}_residuals.csv")"
  done
  echo "$line$(truth_error "$s")"
done
