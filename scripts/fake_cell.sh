#!/usr/bin/env bash
# The cell on fake hardware, as the shop floor starts the real one: the fake world
# (build/sim_hw/cell_world: true sheet, three simulated D415s served as emulated V4L2 devices,
# three iiwa arms, grippers, the operator) and the cell controller (build/cell/cell_controller)
# as separate processes on the LCM bus of the cell config, plus the terminal monitor recording
# its own summary. The cell runs the config's experiment (the paper's four-grasp experiment by
# default) and prints one status line per second, then the predicted-vs-observed table.
#
#   scripts/fake_cell.sh [--config CELL.json] [--world WORLD.json] [--out DIR] [-- CELL_ARGS...]
#
# Needs LCM multicast on loopback (run it through scripts/with_loopback_lcm.sh where the host has
# no multicast route; scripts/run_demo.sh does). Writes DIR (default out/cell): world.log,
# monitor.log, experiment.json, v4l2_emulation.env. Exit status: the cell controller's.
set -uo pipefail
cd "$(dirname "$0")/.."
config=cell/examples/fake_cell.json
world=sim_hw/examples/fake_world.json
out=out/cell
cell_args=()
while (($#)); do
  case "$1" in
    --config) config=$2; shift 2 ;;
    --world) world=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --) shift; cell_args=("$@"); break ;;
    *) echo "fake_cell.sh: unknown option '$1' (see the header of $0)" >&2; exit 2 ;;
  esac
done
for exe in build/sim_hw/cell_world build/cell/cell_controller build/cell/cell_monitor; do
  [[ -x $exe ]] || { echo "fake_cell.sh: $exe is missing: run scripts/setup.sh first" >&2; exit 2; }
done
mkdir -p "$out"
env_file=$out/v4l2_emulation.env
rm -f "$env_file"

# On "clock": "sim" (the fake cell's default) the world's clock waits for every cycle of the
# controller (lockstep), so a run repeats whatever the machine's speed.
world_args=() monitor_args=()
if grep -Eq '"clock"[[:space:]]*:[[:space:]]*"sim"' "$config"; then
  world_args+=(--lockstep cell_controller)
  monitor_args+=(--sim-clock)
fi
build/sim_hw/cell_world --config "$config" --world "$world" --emulation-env "$env_file" "${world_args[@]}" \
  > "$out/world.log" 2>&1 &
world_pid=$!
monitor_pid=
cleanup() {
  [[ -n $monitor_pid ]] && kill -INT "$monitor_pid" 2>/dev/null
  kill -TERM "$world_pid" 2>/dev/null
  wait 2>/dev/null
}
trap cleanup EXIT
trap 'exit 130' INT TERM

echo "fake world starting (log: $out/world.log) ..."
for _ in $(seq 1200); do
  [[ -s $env_file ]] && break
  if ! kill -0 "$world_pid" 2>/dev/null; then
    echo "fake_cell.sh: the fake world stopped during start-up:" >&2
    tail -n 20 "$out/world.log" >&2
    exit 1
  fi
  sleep 0.1
done
[[ -s $env_file ]] || { echo "fake_cell.sh: the fake world did not come up in 120 s" >&2; exit 1; }
echo "fake world up: $(tail -n 1 "$out/world.log")"

build/cell/cell_monitor --summary "${monitor_args[@]}" > "$out/monitor.log" 2>&1 &
monitor_pid=$!

# The cell reads its cameras through the real V4L2 back-end, from the emulated devices.
mapfile -t emulation < "$env_file"
env "${emulation[@]}" build/cell/cell_controller --config "$config" --out "$out" \
  --exit-after-experiment "${cell_args[@]}"
status=$?

kill -INT "$monitor_pid" 2>/dev/null
wait "$monitor_pid" 2>/dev/null
monitor_pid=
echo
echo "terminal monitor summary ($out/monitor.log):"
sed -n '/summary/,$p' "$out/monitor.log" | head -n 30
exit $status
