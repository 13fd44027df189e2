#!/usr/bin/env bash
# Runs CMD in a private network namespace where LCM's loopback multicast works:
#   scripts/with_loopback_lcm.sh CMD [ARGS...]
# Inside: lo is up and 224.0.0.0/4 is routed to it, so udpm://239.255.76.67:7667?ttl=0 reaches
# every process started by CMD (and nothing outside the namespace). This machine's normal
# namespace has no multicast route on lo, so udpm LCM fails there ("no route"/no delivery).
# Needs root (unshare -n, ip); without root it tries a user namespace (unshare -rn), which works
# where unprivileged user namespaces are enabled. Exits with CMD's status.
set -euo pipefail
if (($# == 0)); then
  echo "usage: $0 CMD [ARGS...]  (runs CMD with loopback multicast for LCM udpm, ttl=0)" >&2
  exit 2
fi
for tool in unshare ip; do
  if ! command -v "$tool" >/dev/null; then
    echo "with_loopback_lcm.sh: '$tool' not found (Debian packages util-linux, iproute2)" >&2
    exit 125
  fi
done
inner='ip link set lo up && ip route add 224.0.0.0/4 dev lo && exec "$@"'
if [[ $(id -u) -eq 0 ]]; then
  flags=(-n)
else
  # Unprivileged: map ourselves to root in a new user namespace, which may create the netns.
  if ! unshare -rn true 2>/dev/null; then
    echo "with_loopback_lcm.sh: needs root (unshare -n and ip route), or unprivileged user" \
         "namespaces (unshare -rn failed here); run it as root, e.g. sudo $0 $*" >&2
    exit 125
  fi
  flags=(-rn)
fi
exec unshare "${flags[@]}" -- bash -c "$inner" with_loopback_lcm "$@"
