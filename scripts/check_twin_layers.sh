#!/usr/bin/env bash
# The twin's parts depend one way: base <- mesh <- model <- solvers <- trials <- distributed <- diagnosis <- batch, and
# tools/ and bench/ on top; the twin as a whole depends on no hardware, LCM or PCL. Prints every
# include that breaks that and exits 1; exits 0 when there is none.
#   scripts/check_twin_layers.sh [SOURCE_DIR]
set -uo pipefail
cd "${1:-$(dirname "$0")/..}"
parts=(base mesh model solvers trials distributed diagnosis batch)
status=0
report() { echo "$1"; status=1; }
for ((i = 0; i < ${#parts[@]}; ++i)); do
  part=${parts[i]}
  [ -d "twin/$part" ] || report "twin/$part: missing (a part of the twin moved without this check)"
  for ((j = i + 1; j < ${#parts[@]}; ++j)); do
    while IFS= read -r hit; do
      report "$hit: twin/$part must not include twin/${parts[j]} (a later part)"
    done < <(grep -rn "#include \"twin/${parts[j]}/" "twin/$part" 2>/dev/null)
  done
  while IFS= read -r hit; do
    report "$hit: twin/$part must not include the twin's tools or benchmarks"
  done < <(grep -rnE '#include "twin/(tools|bench)/' "twin/$part" 2>/dev/null)
done
# Every source of the twin sits in a part (or in tools/, bench/).
while IFS= read -r loose; do
  report "$loose: a twin source outside its parts"
done < <(find twin -maxdepth 1 \( -name '*.h' -o -name '*.cc' \))
while IFS= read -r hit; do
  report "$hit: the twin depends on no hardware, LCM or PCL"
done < <(grep -rnE '#include ("(drivers|tracking|cell|sim_hw)/|<(lcm|pcl)/)' twin 2>/dev/null)
exit $status
