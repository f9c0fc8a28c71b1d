#!/usr/bin/env bash
# Builds every libFuzzer target (fuzz/<name>.cpp -> fuzz_<name>) with clang in build-fuzz/
# and runs each for N seconds (first argument, default 60) on a seed corpus copied from the
# shared test data into a temporary folder. Prints the executions per target; exits
# non-zero when a target crashes (the reproducer is kept in build-fuzz/crashes/).
#
#   fuzz/run.sh [SECONDS]        environment: JOBS (build jobs, default 2),
#                                TLSMON_DATA_DIR (default ../shared/data)
set -euo pipefail

seconds=${1:-60}
root=$(cd "$(dirname "$0")/.." && pwd)
build=$root/build-fuzz
data=${TLSMON_DATA_DIR:-$root/../shared/data}
jobs=${JOBS:-2}
max_len=65536  # seeds are cut to this size, so what is fuzzed is what is in the corpus

names=()
for src in "$root"/fuzz/*.cpp; do names+=("$(basename "$src" .cpp)"); done
[ ${#names[@]} -gt 0 ] || { echo "fuzz/run.sh: no fuzz/*.cpp" >&2; exit 1; }

CXX=${CXX:-clang++} cmake -S "$root" -B "$build" -DTLSMON_FUZZ=ON \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTLSMON_DATA_DIR="$data" >/dev/null
cmake --build "$build" -j"$jobs" --target "${names[@]/#/fuzz_}"

# Seed files of a target: the data files of its format.
seed_patterns() {
  case "$1" in
    ascii) echo "*.xyz *.pts" ;;
    las) echo "*.las *.laz" ;;
    *) echo "*.$1" ;;
  esac
}

work=$(mktemp -d /tmp/tlsmon-fuzz.XXXXXX)
trap 'rm -rf "$work"' EXIT
mkdir -p "$build/crashes"

failed=()
summary=()
for name in "${names[@]}"; do
  corpus=$work/$name
  mkdir -p "$corpus"
  for pattern in $(seed_patterns "$name"); do
    while IFS= read -r -d '' f; do
      head -c "$max_len" "$f" >"$corpus/$(printf '%s' "$f" | sha1sum | cut -c1-16)"
    done < <(find "$data" -type f -name "$pattern" -print0)
  done
  seeds=$(find "$corpus" -type f | wc -l)
  echo "== fuzz_$name: $seconds s, $seeds seed files"
  log=$work/$name.log
  status=0
  "$build/fuzz/fuzz_$name" "$corpus" -max_total_time="$seconds" -max_len="$max_len" \
    -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$build/crashes/$name-" >"$log" 2>&1 || status=$?
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  if [ "$status" -ne 0 ]; then
    tail -n 40 "$log"
    failed+=("fuzz_$name")
    summary+=("fuzz_$name: CRASH (exit $status) after ${runs:-?} executions")
  else
    summary+=("fuzz_$name: ${runs:-?} executions in $seconds s, no crash")
  fi
done

echo "== summary"
printf '%s\n' "${summary[@]}"
if [ ${#failed[@]} -gt 0 ]; then
  echo "crashes in: ${failed[*]} (reproducers in $build/crashes/)" >&2
  exit 1
fi
