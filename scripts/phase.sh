# Sourced by the set-up, test and CI scripts: `phase NAME CMD...` runs CMD and prints how long it
# took as "phase: NAME S s", so a CI log shows where its time went (configure, each build, each
# test run). CMD's status is the phase's.
phase() {
  local name="$1" start=$SECONDS status=0
  shift
  "$@" || status=$?
  echo "phase: ${name} $((SECONDS - start)) s$( ((status)) && echo " (exit ${status})")"
  return "$status"
}
