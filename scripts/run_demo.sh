#!/usr/bin/env bash
# The main job: set up, then run the cell on fake hardware (scripts/fake_cell.sh): the fake
# world and the cell controller as separate processes on the LCM bus, the paper's four-grasp
# experiment, a live status line per second, then the predicted-vs-observed table and the
# terminal monitor's summary. Output in out/cell/. Arguments are passed to fake_cell.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
# LCM's loopback multicast (udpm, ttl=0) needs a multicast route. Where the host has one, run in
# the host's network namespace, so lcm-spy (scripts/lcm_spy.sh) and cell_monitor can watch;
# otherwise in a private namespace with the route on lo.
if ip route get 239.255.76.67 >/dev/null 2>&1; then
  exec bash scripts/fake_cell.sh "$@"
fi
echo "run_demo.sh: no multicast route here; running the cell in a private network namespace"
exec bash scripts/with_loopback_lcm.sh bash scripts/fake_cell.sh "$@"
