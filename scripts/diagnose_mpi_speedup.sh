#!/usr/bin/env bash
# Speed-up of one `twin diagnose` over MPI ranks (issue 38): the refit searches spread over the
# ranks (docs/batch.md, "Inside one diagnosis"). One training and one held-out trial of a
# composite whose warp bends at 0.4 of its weft, simulated by the scanner lab's independent
# sheet model (not the twin's), diagnosed with the default options serially on one thread and
# under `mpirun -np RANKS` with one thread per rank; prints each wall time, the per-search lines
# of the MPI run, and compares the two runs' verdict and material files.
# Usage: bash scripts/diagnose_mpi_speedup.sh [RANKS (default 2)] [EXTRA DIAGNOSE OPTIONS...]
set -euo pipefail
cd "$(dirname "$0")/.."
ranks="${1:-2}"
shift || true
dir=out/diagnose_speedup
mkdir -p "$dir"
cat > "$dir/truth.json" <<'JSON'
{
  "name": "composite, warp bending 0.4 of weft",
  "surface_density_kg_m2": 0.3, "thickness_m": 0.0003, "poisson_ratio": 0.3,
  "tensile_stiffness_N_m": 6000, "shear_stiffness_N_m": 2500,
  "bending_given_as": "rigidity", "bending_rigidity_Nm": {"weft": 0.0008, "warp": 0.00032},
  "viscosity": {"tensile_Ns_m": 5.0, "shear_Ns_m": 5.0, "mass_damping_1_s": 1.0}
}
JSON
for seed in 1 2; do
  if [ ! -f "$dir/trial_$seed/trial.json" ]; then
    ./build/sim_hw/scanner_lab --specimen composite --seed "$seed" --truth-model independent --material-file "$dir/truth.json" --no-scans \
      --out "$dir/trial_$seed" > /dev/null
  fi
done

root=()
[[ $(id -u) -eq 0 ]] && root=(--allow-run-as-root)
run() {  # NAME COMMAND...: a fresh report directory, wall time
  local name=$1
  shift
  rm -rf "$dir/$name"
  local start end
  start=$(date +%s.%N)
  OMP_WAIT_POLICY=passive "$@" diagnose --train "$dir/trial_1" --test "$dir/trial_2" --report "$dir/$name" \
    "${extra[@]}" > "$dir/$name.log" 2>&1
  end=$(date +%s.%N)
  awk -v n="$name" -v a="$start" -v b="$end" 'BEGIN { printf "%-36s %8.1f s\n", n, b - a }'
}
extra=("$@")
echo "1 diagnosis, $(nproc) cores"
run serial_1_thread ./build/twin/twin --threads 1
run "mpirun_np_${ranks}_1_thread_each" mpirun "${root[@]}" --oversubscribe --bind-to none \
  --mca btl_vader_single_copy_mechanism none -np "$ranks" ./build/twin/twin --threads 1
grep -h "refit searches over\|(rank [0-9]*):" "$dir/mpirun_np_${ranks}_1_thread_each.log" || true
grep -h "^verdict\|^  verdict\|named\|effect:" "$dir/serial_1_thread.log" | head -3 || true
for f in verdict.json material_augmented.json; do
  if [ -f "$dir/serial_1_thread/$f" ]; then
    cmp -s "$dir/serial_1_thread/$f" "$dir/mpirun_np_${ranks}_1_thread_each/$f" &&
      echo "$f: the same bytes in both runs" || echo "$f differs between the serial and the MPI run"
  fi
done
