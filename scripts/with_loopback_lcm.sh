#!/usr/bin/env bash
# Runs CMD in a private network namespace where LCM's loopback multicast works:
#   scripts/with_loopback_lcm.sh CMD [ARGS...]
# Inside: lo is up and 224.0.0.0/4 is routed to it, so udpm://239.255.76.67:7667?ttl=0 reaches
# every process started by CMD (and nothing outside the namespace). This machine's normal
# namespace has no multicast route on lo, so udpm LCM fails there ("no route"/no delivery).
# Needs root (unshare -n, ip); without root it tries a user namespace (unshare -rn), which works
# where unprivileged user namespaces are enabled. Exits with CMD's status, except that a CMD status
# of 125 becomes 1: 125 is reserved for "skipped, no namespace possible here" (CTest's
# SKIP_RETURN_CODE of the tests that use this script), and a Catch2 executable exits with its
# count of failed assertions, which could be 125. Under CI=true there are no skips: a machine
# that cannot make the namespace fails the test instead (scripts/setup.sh installs iproute2).
set -euo pipefail
skip() {
  echo "with_loopback_lcm.sh: $*" >&2
  if [[ "${CI:-}" == true ]]; then
    echo "with_loopback_lcm.sh: CI=true, so this is a failure, not a skip" >&2
    exit 1
  fi
  exit 125
}
if (($# == 0)); then
  echo "usage: $0 CMD [ARGS...]  (runs CMD with loopback multicast for LCM udpm, ttl=0)" >&2
  exit 2
fi
for tool in unshare ip; do
  if ! command -v "$tool" >/dev/null; then
    skip "'$tool' not found (Debian packages util-linux, iproute2)"
  fi
done
inner='ip link set lo up && ip route add 224.0.0.0/4 dev lo && exec "$@"'
if [[ $(id -u) -eq 0 ]]; then
  flags=(-n)
else
  # Unprivileged: map ourselves to root in a new user namespace, which may create the netns.
  if ! unshare -rn true 2>/dev/null; then
    skip "needs root (unshare -n and ip route), or unprivileged user" \
         "namespaces (unshare -rn failed here); run it as root, e.g. sudo $0 $*"
  fi
  flags=(-rn)
fi
status=0
unshare "${flags[@]}" -- bash -c "$inner" with_loopback_lcm "$@" || status=$?
if ((status == 125)); then status=1; fi
exit "$status"
