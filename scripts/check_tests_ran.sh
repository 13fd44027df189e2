#!/usr/bin/env bash
# Checks that a CTest run executed every test it should have, and prints "declared N, ran N".
#   scripts/check_tests_ran.sh BUILD_DIR JUNIT_FILE...          the whole suite
#   scripts/check_tests_ran.sh --selected BUILD_DIR JUNIT_FILE...  a run selected by -L/-R
# JUNIT_FILE: what `ctest --output-junit` wrote (one per ctest call of the run).
#
# Whole suite: every Catch2 test case that the build declares (each executable's own list, for
# the spec it was registered with: BUILD_DIR/test_declarations/, scripts/cmake/test_registration.cmake)
# must have its CTest entry, and every CTest entry must have run and passed. A skipped entry
# counts as not run, so a skip fails this check. "declared" is the Catch cases plus the entries
# that are not Catch cases (scripts, smoke runs); "ran" is the entries that ran and passed.
# Selected: only the second half (the entries the junit files list ran and passed).
set -euo pipefail
selected=0
if [[ "${1:-}" == --selected ]]; then selected=1; shift; fi
build="${1:?usage: check_tests_ran.sh [--selected] BUILD_DIR JUNIT_FILE...}"; shift
(($#)) || { echo "check_tests_ran.sh: no junit file given" >&2; exit 2; }
for f in "$@"; do
  [[ -s "$f" ]] || { echo "check_tests_ran.sh: $f: missing or empty (ctest --output-junit)" >&2; exit 2; }
done

# JUnit as CTest 3.25 writes it: one <testcase ... status="run|fail|notrun|disabled"> per entry.
sum() { awk '{ n += $1 } END { print n + 0 }'; }
entries=$({ grep -c '<testcase ' "$@" /dev/null || true; } | awk -F: '{ print $NF }' | sum)
passed=$(grep -h '<testcase ' "$@" | grep -c 'status="run"' || true)
not_passed=$(grep -h '<testcase ' "$@" | grep -v 'status="run"' | sed -E 's/.*name="([^"]*)".*status="([^"]*)".*/  \2: \1/' || true)
# A failed entry whose junit status still says run would be missed: count failures too.
failures=$({ grep -c '<failure' "$@" /dev/null || true; } | awk -F: '{ print $NF }' | sum)

if ((selected)); then
  echo "selected ${entries}, ran ${passed}"
  if ((passed != entries || failures > 0)); then
    echo "check_tests_ran.sh: entries that did not run and pass:" >&2
    printf '%s\n' "$not_passed" >&2
    exit 1
  fi
  exit 0
fi

# The Catch cases the build declares, with the prefix and spec of their registration.
declared_file=$(mktemp)
registered_file=$(mktemp)
trap 'rm -f "$declared_file" "$registered_file"' EXIT
shopt -s nullglob
declarations=("$build"/test_declarations/*.txt)
((${#declarations[@]})) || { echo "check_tests_ran.sh: no $build/test_declarations/*.txt (configure with tests)" >&2; exit 2; }
for d in "${declarations[@]}"; do
  mapfile -t line < "$d"
  exe="${line[0]}" prefix="${line[1]:-}" spec="${line[2]:-}"
  [[ -x "$exe" ]] || { echo "check_tests_ran.sh: $exe (declared in $d) is not built" >&2; exit 2; }
  args=(--list-test-names-only)
  [[ -n "$spec" ]] && args=("$spec" "${args[@]}")
  # --list-test-names-only exits with the number of cases listed.
  "$exe" "${args[@]}" | awk -v p="$prefix" 'BEGIN { sub(/ +$/, "", p) } NF { print p $0 }' >> "$declared_file" || true
done
sort -o "$declared_file" "$declared_file"
ctest --test-dir "$build" -N | sed -n -E 's/^ *Test +#[0-9]+: //p' | sort > "$registered_file"

missing=$(comm -23 "$declared_file" "$registered_file")
if [[ -n "$missing" ]]; then
  echo "check_tests_ran.sh: declared test cases with no CTest entry (they never run):" >&2
  printf '  %s\n' "$missing" >&2
  exit 1
fi
catch_cases=$(wc -l < "$declared_file")
other=$(comm -13 "$declared_file" "$registered_file" | wc -l)
declared=$((catch_cases + other))
echo "declared ${declared} (${catch_cases} Catch2 cases, ${other} other entries), ran ${passed}"
if ((entries != declared)); then
  echo "check_tests_ran.sh: the junit files list ${entries} entries, the build registers ${declared}" >&2
  exit 1
fi
if ((passed != declared || failures > 0)); then
  echo "check_tests_ran.sh: entries that did not run and pass:" >&2
  printf '%s\n' "$not_passed" >&2
  exit 1
fi
