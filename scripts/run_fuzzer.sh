#!/usr/bin/env bash
# Runs one libFuzzer harness of tests/fuzz on its committed corpus (docs/fuzzing.md):
#   scripts/run_fuzzer.sh NAME [--seconds S] [--build DIR] [--jobs N] [-- extra libFuzzer flags]
# First every committed input (corpus/NAME/ and its regressions/) runs once and must pass; then
# the harness fuzzes for S seconds (default 20), keeping what it finds new in a scratch corpus
# (the committed one is never written; merge by hand: docs/fuzzing.md). A crash, leak, timeout or
# sanitizer report fails the run and leaves the input in DIR/fuzz/NAME/ (artifact_prefix).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
name="${1:?usage: run_fuzzer.sh NAME [--seconds S] [--build DIR] [-- flags]}"; shift
seconds=20 build="$here/build-asan" extra=()
while (($#)); do
  case "$1" in
    --seconds) seconds="$2"; shift 2 ;;
    --build) build="$2"; shift 2 ;;
    --) shift; extra=("$@"); break ;;
    *) echo "run_fuzzer.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
exe="$build/tests/fuzz/fuzz_$name"
corpus="$here/tests/fuzz/corpus/$name"
[[ -x "$exe" ]] || { echo "run_fuzzer.sh: no $exe (configure with -DPREPREG_FUZZ=ON, build fuzz_$name)" >&2; exit 2; }
[[ -d "$corpus" ]] || { echo "run_fuzzer.sh: no corpus $corpus" >&2; exit 2; }
# Dictionaries: tests/fuzz/dicts/NAME.dict, else json.dict for the harnesses that read JSON.
dict=()
case "$name" in
  lcm_*|v4l2_frames|xyz) ;;
  mesh) dict=(-dict="$here/tests/fuzz/dicts/mesh.dict") ;;
  *) dict=(-dict="$here/tests/fuzz/dicts/json.dict") ;;
esac
[[ -f "$here/tests/fuzz/dicts/$name.dict" ]] && dict=(-dict="$here/tests/fuzz/dicts/$name.dict")
out="$build/fuzz/$name"
mkdir -p "$out/new"
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:allocator_may_return_null=0}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
common=(-timeout=10 -rss_limit_mb=2048 -artifact_prefix="$out/" "${dict[@]}" "${extra[@]}")
# 1. Every committed input once (the regressions among them).
# libFuzzer's progress lines ("#1024 NEW cov: ...") and INFO lines are dropped, so that a finding's
# message (above its stack) and the final stats are what is left to show.
quiet() { { grep -v -E '^(#[0-9]+[[:space:]]|INFO: )' || true; } | tail -n "$1"; }
mapfile -t inputs < <(find "$corpus" -type f | sort)
echo "run_fuzzer.sh: $name: ${#inputs[@]} committed inputs"
"$exe" "${common[@]}" -runs=0 "$corpus" 2>&1 | quiet 60
# 2. Fuzzing from them for the given time.
"$exe" "${common[@]}" -max_total_time="$seconds" -print_final_stats=1 "$out/new" "$corpus" 2>&1 | quiet 80
