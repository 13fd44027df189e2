#!/usr/bin/env bash
# Blind accuracy of the discrepancy workflow (issue 6): for each hidden effect, several blind
# trial sets (`scanner_lab blind --effect E`, seeds distinct per effect), each diagnosed with
# `twin diagnose` on the files alone; then a table of how often the verdict is right.
#
# Usage: bash scripts/blind_accuracy.sh [SETS_PER_EFFECT (default 3)] [OUT (default out/blind_accuracy)]
# Environment: EFFECTS (comma list, default all nine), TRUTH_MODEL (spline_shell, the default:
# the lab's reference shell that shares nothing with the twin and converges; independent: the
# lab's finite-difference plate; twin: the twin's own model, the sets of issue 6), TRIANGLES (default 300: the twin, and the reference sheet of twin truth), BUILD (default build), TWIN / SCANNER_LAB (the executables, default under BUILD),
# FIRST_SEED (default 1), OMP_NUM_THREADS (default 1), JOBS (sets run at once, default 1; 2 on a
# quiet two-core machine), REDIAGNOSE=1 (diagnose again every set, e.g. after rebuilding twin),
# DIAGNOSE_ARGS (more `twin diagnose` options, e.g. "--optimizer lm").
#
# Resumable: a set whose truth exists is not generated again, a set with a verdict.json is not
# diagnosed again; a step that failed left an error file and is retried on the next run. Delete
# OUT (or one set's directory) to start over. Progress lines go to stderr, the table to stdout.
set -uo pipefail
cd "$(dirname "$0")/.."
sets="${1:-3}"
out="${2:-out/blind_accuracy}"
build="${BUILD:-build}"
triangles="${TRIANGLES:-300}"
truth_model="${TRUTH_MODEL:-spline_shell}"
first_seed="${FIRST_SEED:-1}"
jobs="${JOBS:-1}"
effects="${EFFECTS:-none,orthotropic_stiffness,rest_curvature,nonlinear_bending,marker_mass,viscoelastic_relaxation,clamp_grip,clamp_slip,outside_library}"
lab="${SCANNER_LAB:-$build/sim_hw/scanner_lab}"
twin="${TWIN:-$build/twin/twin}"
for exe in "$lab" "$twin"; do
  [ -x "$exe" ] || { echo "blind_accuracy: $exe not built (cmake --build $build --target scanner_lab twin)" >&2; exit 2; }
done
command -v jq > /dev/null || { echo "blind_accuracy: needs jq (apt-get install jq)" >&2; exit 2; }
export OMP_WAIT_POLICY=passive
# One thread each: on a shared two-core machine OpenMP threads cost more than they give.
export OMP_NUM_THREADS="${OMP_NUM_THREADS:-1}"
mkdir -p "$out"

now() { date +%s.%N; }
elapsed() { awk -v a="$1" -v b="$(now)" 'BEGIN { printf "%.1f\n", b - a }'; }

# One set: generate (unless done), diagnose (unless done). Times go to DIR/seconds_*.txt.
run_set() {
  local effect="$1" seed="$2" dir="$3"
  if [ ! -f "$dir/truth/hidden_effect.json" ]; then
    rm -rf "$dir/trials" "$dir/truth" "$dir/report"
    mkdir -p "$dir"
    local t0; t0=$(now)
    if ! "$lab" blind --seed "$seed" --effect "$effect" --truth-model "$truth_model" --triangles "$triangles" \
         --out "$dir/trials" --truth "$dir/truth" > "$dir/generate.log" 2>&1; then
      echo "generate failed: $(tail -1 "$dir/generate.log")" > "$dir/error.txt"
      rm -rf "$dir/truth"
      return
    fi
    elapsed "$t0" > "$dir/seconds_generate.txt"
  fi
  if [ "${REDIAGNOSE:-0}" = 1 ] || [ ! -f "$dir/report/verdict.json" ]; then
    rm -rf "$dir/report"
    local t0; t0=$(now)
    # shellcheck disable=SC2086  # DIAGNOSE_ARGS is a list of options
    if ! "$twin" diagnose --train "$dir/trials/train_1" --train "$dir/trials/train_2" \
         --test "$dir/trials/test_1" --triangles "$triangles" --report "$dir/report" ${DIAGNOSE_ARGS:-} \
         > "$dir/diagnose.log" 2>&1 \
       || [ ! -f "$dir/report/verdict.json" ]; then
      echo "diagnose failed: $(tail -1 "$dir/diagnose.log")" > "$dir/error.txt"
      rm -f "$dir/report/verdict.json"
      return
    fi
    elapsed "$t0" > "$dir/seconds_diagnose.txt"
  fi
  rm -f "$dir/error.txt"
}

IFS=',' read -r -a effect_list <<< "$effects"
# Distinct seeds per effect, so protocols and noise differ between effects too.
seed_of() { echo $((first_seed + 1000 * $1 + $2)); }

# Run the sets, JOBS at a time.
index=0
for effect in "${effect_list[@]}"; do
  index=$((index + 1))
  for ((k = 0; k < sets; k++)); do
    seed=$(seed_of "$index" "$k")
    echo "blind_accuracy: $effect seed $seed ..." >&2
    run_set "$effect" "$seed" "$out/${effect}_$seed" &
    while (($(jobs -rp | wc -l) >= jobs)); do wait -n; done
  done
done
wait

# Per set: effect, verdict class (right / wrong_name / none / unexplained / model_form / failed),
# errors, and the error budget: the base fit's held-out mean error over the noise floor and the
# discretisation error its residual holds (twin/trials/discretisation_check.h).
results="$out/results.tsv"
printf 'effect\tseed\toutcome\tverdict\tnamed\tbefore_mm\tafter_mm\tnoise_floor_mm\tmeets_error_target\tgenerate_s\tdiagnose_s\tshift_mm\tmeets_gap_target\tbase_over_floor\tdiscretisation_mm\ttruth_error_mm\n' > "$results"
index=0
for effect in "${effect_list[@]}"; do
  index=$((index + 1))
  for ((k = 0; k < sets; k++)); do
    seed=$(seed_of "$index" "$k")
    dir="$out/${effect}_$seed"
    gen_s=$(cat "$dir/seconds_generate.txt" 2>/dev/null || echo nan)
    diag_s=$(cat "$dir/seconds_diagnose.txt" 2>/dev/null || echo nan)
    if [ -f "$dir/error.txt" ] || [ ! -f "$dir/report/verdict.json" ]; then
      echo "blind_accuracy: $effect seed $seed: $(cat "$dir/error.txt" 2>/dev/null)" >&2
      printf '%s\t%s\tfailed\t-\t-\tnan\tnan\tnan\tno\t%s\t%s\tnan\tno\tnan\tnan\tnan\n' "$effect" "$seed" "$gen_s" "$diag_s" >> "$results"
      continue
    fi
    truth=$(jq -r '.effect' "$dir/truth/hidden_effect.json")
    shift_mm=$(jq -r '.marker_shift_mm.mean // "nan"' "$dir/truth/hidden_effect.json")
    # The truth's own error: its seen markers' mean change between its two finest levels, over
    # the set's trials and stages (a truth without levels, the plate or the twin, has none).
    truth_mm=$(cat "$dir"/truth/*/lab.json 2>/dev/null |
               jq -s -r '[.[].truth_error[]?.finest_change_mean_m] | if length > 0 then (add / length * 1000 | tostring) else "nan" end')
    jq -r --arg truth "$truth" --arg seed "$seed" --arg g "$gen_s" --arg d "$diag_s" --arg shift "$shift_mm" --arg tru "$truth_mm" '
      (.held_out.before_mean_mm // null) as $b | (.held_out.after_mean_mm // null) as $a |
      (.noise_floor_mm // null) as $f |
      (if $truth == "none" then (if .verdict == "none" or .verdict == "model_form" then "right"
                                 elif .verdict == "effect" then "wrong_name" else "unexplained" end)
       elif $truth == "outside_library" then (if .verdict == "unexplained" or .verdict == "model_form" then "right"
                                              elif .verdict == "effect" then "wrong_name" else "none" end)
       elif .verdict == "effect" then (if .effect == $truth then "right" else "wrong_name" end)
       else .verdict end) as $outcome |
      (if $truth == "none" or $truth == "outside_library" then "-"
       elif ($a != null and $b != null and $f != null and $a <= 0.5 * $b and $a <= 1.5 * $f) then "yes" else "no" end) as $meets |
      (if $truth == "none" or $truth == "outside_library" then "-"
       elif ($a != null and $b != null and $f != null and $b > $f and ($a - $f) <= 0.5 * ($b - $f) and $a <= 1.5 * $f)
       then "yes" else "no" end) as $gap |
      (if $b != null and $f != null and $f > 0 then ($b / $f) else "nan" end) as $over |
      [$truth, $seed, $outcome, .verdict, (.effect // "-"), ($b // "nan"), ($a // "nan"), ($f // "nan"), $meets, $g, $d, $shift, $gap,
       $over, (.discretisation_in_residual_mm // "nan"), $tru]
      | map(tostring) | join("\t")' "$dir/report/verdict.json" >> "$results"
    echo "blind_accuracy: $effect seed $seed: $(tail -1 "$results" | cut -f3-9)" >&2
  done
done

# The table: per effect, sets, right, wrong name, none, unexplained, model_form, failed, mean
# held-out error, and the budget (mean base/floor, mean discretisation error held).
echo
echo "blind accuracy: $sets set(s) per effect, twin of $triangles triangles, $truth_model truth, results in $results"
awk -F'\t' '
  NR == 1 { next }
  { e = $1; order[e] = order[e] ? order[e] : ++n; names[order[e]] = e; sets[e]++; count[e, $3]++
    if ($6 != "nan" && $7 != "nan") { before[e] += $6; after[e] += $7; errs[e]++ }
    if ($9 == "yes") meets[e]++
    # Where halving the error is possible at all: half the base error is not below the floor
    # (the mean marker error noise alone leaves, which no model can go under).
    if ($6 != "nan" && $8 != "nan" && 0.5 * $6 >= $8) { possible[e]++; if ($9 == "yes") met_possible[e]++ }
    if ($13 == "yes") gaps[e]++
    if ($14 != "nan" && $14 != "") { over[e] += $14; overs[e]++ }
    if ($15 != "nan" && $15 != "") { disc[e] += $15; discs[e]++ }
    if ($16 != "nan" && $16 != "") { tru[e] += $16; trus[e]++ }
    if ($12 != "nan" && $12 != "") { shift[e] += $12; shifts[e]++ }
    if ($10 != "nan") { gs += $10; gn++ } if ($11 != "nan") { ds += $11; dn++ } }
  END {
    printf "%-24s %4s %5s %10s %5s %11s %10s %6s %10s %10s %8s %9s %8s %12s %10s %8s %9s\n", "effect", "sets", "right",
           "wrong_name", "none", "unexplained", "model_form", "failed", "before_mm", "after_mm", "err_ok", "shift_mm",
           "gap_ok", "err_possible", "base/floor", "disc_mm", "truth_mm"
    for (i = 1; i <= n; i++) { e = names[i]
      printf "%-24s %4d %5d %10d %5d %11d %10d %6d %10s %10s %8s %9s %8s %12s %10s %8s %9s\n", e, sets[e], count[e, "right"],
             count[e, "wrong_name"], count[e, "none"], count[e, "unexplained"], count[e, "model_form"], count[e, "failed"],
             errs[e] ? sprintf("%.3f", before[e] / errs[e]) : "-", errs[e] ? sprintf("%.3f", after[e] / errs[e]) : "-",
             (e == "none" || e == "outside_library") ? "-" : sprintf("%d/%d", meets[e], sets[e]),
             shifts[e] ? sprintf("%.2f", shift[e] / shifts[e]) : "-",
             (e == "none" || e == "outside_library") ? "-" : sprintf("%d/%d", gaps[e], sets[e]),
             (e == "none" || e == "outside_library") ? "-" : sprintf("%d/%d", met_possible[e], possible[e]),
             overs[e] ? sprintf("%.1f", over[e] / overs[e]) : "-", discs[e] ? sprintf("%.2f", disc[e] / discs[e]) : "-",
             trus[e] ? sprintf("%.2f", tru[e] / trus[e]) : "-" }
    if (gn) printf "mean seconds: generate %.1f (%d sets), diagnose %s\n", gs / gn, gn, dn ? sprintf("%.1f (%d sets)", ds / dn, dn) : "-"
  }' "$results"
