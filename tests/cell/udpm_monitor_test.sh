#!/usr/bin/env bash
# The monitor as a real process on real LCM (udpm, ttl=0) inside scripts/with_loopback_lcm.sh:
# a publisher process sends 20 cycles (and one undecodable message), cell_monitor listens for a
# few seconds and must report all 20 cycles, none missing, and the dropped message.
#   udpm_monitor_test.sh PUBLISHER CELL_MONITOR   (run inside with_loopback_lcm.sh)
set -euo pipefail
publisher="$1"
monitor="$2"
url='udpm://239.255.76.67:7667?ttl=0'
out="$(mktemp)"
trap 'rm -f "$out"' EXIT
# The monitor runs until told to stop once the publisher has exited (loopback multicast has then
# put every datagram in its socket, and it handles what arrived before it stops), not for a
# fixed time a busy machine may not publish in; --max-seconds only ends a run that hangs.
"$monitor" --lcm "$url" --max-seconds 120 --summary >"$out" 2>&1 &
monitor_pid=$!
# The monitor subscribes before it says it listens; publish only then (on a loaded machine its
# start-up alone has taken over a second, and a fixed delay lost the first cycles).
for _ in $(seq 200); do
  grep -q "^cell_monitor: listening on " "$out" && break
  kill -0 "$monitor_pid" 2>/dev/null || break
  sleep 0.1
done
grep -q "^cell_monitor: listening on " "$out" || { cat "$out"; echo "cell_monitor did not start listening within 20 s"; exit 1; }
"$publisher" --lcm "$url" --cycles 20 --hz 20 --delay-s 0.1
kill -INT "$monitor_pid"
wait "$monitor_pid"
cat "$out"
grep -q "^summary: 20 cycles (0..19), 0 missing" "$out"
grep -q "^cycle 3 DEGRADED .*cams 2/3 cam_right (LOST)" "$out"
grep -q "dropped 1 undecodable, 0 rejected" "$out"
grep -q "recomputed error: 20 cycles, 0 disagree" "$out"
echo "udpm monitor test: OK"
