#!/usr/bin/env bash
# Speed-up of `twin batch` over MPI ranks (issue 38): one batch of lab materials, diagnosed
# serially on one thread, serially on every core, and by `mpirun -np RANKS` with one thread per
# rank; prints each run's wall time and checks the MPI run's material and verdict files against
# the serial ones. The trials are the scanner lab's composite with the twin's own model
# (`--truth-model twin --reference-triangles 300`), one training and one held-out trial per
# material (seeds 2k-1 and 2k), as docs/batch.md's example: they time the batch, not the
# diagnosis. Making the trials takes a minute or two.
# Usage: bash scripts/batch_mpi_speedup.sh [MATERIALS (default 4)] [RANKS (default 2)]
set -euo pipefail
cd "$(dirname "$0")/.."
materials="${1:-4}"
ranks="${2:-2}"
dir=out/batch_speedup
mkdir -p "$dir/trials"
entries=()
for ((k = 1; k <= materials; ++k)); do
  for seed in $((2 * k - 1)) $((2 * k)); do
    if [ ! -f "$dir/trials/composite_$seed/trial.json" ]; then
      ./build/sim_hw/scanner_lab --specimen composite --seed "$seed" --truth-model twin --reference-triangles 300 \
        --reference-clamp-refinement none --no-scans --out "$dir/trials/composite_$seed" > /dev/null
    fi
  done
  entries+=("{\"name\": \"lot_$k\", \"train\": [\"trials/composite_$((2 * k - 1))\"], \"test\": [\"trials/composite_$((2 * k))\"]}")
done
(IFS=,; echo "{\"materials\": [${entries[*]}], \"diagnose\": {\"triangles\": 300}}") > "$dir/manifest.json"

root=()
[[ $(id -u) -eq 0 ]] && root=(--allow-run-as-root)
run() {  # NAME COMMAND...: a fresh output directory, wall time
  local name=$1
  shift
  rm -rf "$dir/$name"
  local start end
  start=$(date +%s.%N)
  OMP_WAIT_POLICY=passive "$@" batch "$dir/manifest.json" --out "$dir/$name" --quiet > "$dir/$name.log" 2>&1
  end=$(date +%s.%N)
  awk -v n="$name" -v a="$start" -v b="$end" 'BEGIN { printf "%-36s %8.1f s\n", n, b - a }'
}
echo "$materials materials, $(nproc) cores"
run serial_1_thread ./build/twin/twin --threads 1
run serial_all_cores ./build/twin/twin
run "mpirun_np_${ranks}_1_thread_each" mpirun "${root[@]}" --mca btl_vader_single_copy_mechanism none -np "$ranks" \
  ./build/twin/twin --threads 1
grep -h "^| lot_" "$dir/serial_1_thread/summary.md"
for ((k = 1; k <= materials; ++k)); do
  for f in material.json verdict.json; do
    cmp -s "$dir/serial_1_thread/lot_$k/$f" "$dir/mpirun_np_${ranks}_1_thread_each/lot_$k/$f" ||
      echo "lot_$k/$f differs between the serial and the MPI run"
  done
done
