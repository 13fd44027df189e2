#!/bin/bash
# The twin's own error against a lab trial: one evaluation at the lab's true material (no fit),
# for each membrane / bending model and resolution; prints the residual RMS per coordinate.
#   scripts/twin_at_true_material.sh TRIAL_DIR TRUE_MATERIAL.json [OUT_DIR] [TRIANGLES...]
# e.g. scripts/twin_at_true_material.sh out/issue33/composite_1 out/issue33/composite_1.truth/material.json
set -euo pipefail
trial=${1:?trial directory}; material=${2:?true material file}; out=${3:-out/twin_at_true_material}
shift $(( $# < 3 ? $# : 3 ))
sizes=("$@"); [ ${#sizes[@]} -gt 0 ] || sizes=(1500 3000 6000)
twin=${TWIN:-build/twin/twin}
mkdir -p "$out"
printf '%-10s %-22s %-10s %s\n' triangles model twin_tris "residual RMS per coordinate"
for n in "${sizes[@]}"; do
  for model in "hinge linear" "hinge quadratic" "plate linear"; do
    set -- $model
    log="$out/${1}_${2}_${n}.log"
    "$twin" identify --train "$trial" --start "$material" --parameters bending_Nm --max-evaluations 1 \
      --no-discretisation-check --quiet --triangles "$n" --bending-model "$1" --membrane-model "$2" \
      --out "$out/${1}_${2}_${n}.json" > "$log" 2>&1 || true
    tris=$(grep -oE 'twin mesh [0-9]+' "$log" | grep -oE '[0-9]+' || echo '?')
    if grep -q 'simulation failed' "$log"; then
      rms="failed: $(grep -oE 'simulation failed: .*' "$log" | head -1)"
    else
      rms=$(grep -oE 'residual RMS per coordinate [0-9.]+ mm' "$log" | grep -oE '[0-9.]+ mm' || echo '?')
    fi
    printf '%-10s %-22s %-10s %s\n' "$n" "$1, $2" "$tris" "$rms"
  done
done
