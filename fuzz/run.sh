#!/usr/bin/env bash
# Builds every libFuzzer target (fuzz/<name>.cpp -> fuzz_<name>) with clang in build-fuzz/
# and runs each for N seconds (first argument, default 60) on a seed corpus copied from the
# shared test data into a temporary folder. Prints the executions per target; exits
# non-zero when a target crashes (the reproducer is kept in build-fuzz/crashes/).
#
#   fuzz/run.sh [SECONDS [TARGET...]]   TARGET: e.g. ply pcd (default: every fuzz/*.cpp)
#                                environment: JOBS (build jobs, default 2),
#                                TLSMON_DATA_DIR (default ../shared/data)
#   fuzz/run.sh --replay BUILD [TARGET...]   no fuzzing: runs each target once over the
#                                same seed corpus, as built in the configured folder BUILD
#                                (CI: the sanitizer build, where the targets have
#                                fuzz/replay/main.cpp as main)
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
replay=false
if [ "${1:-}" = --replay ]; then
  replay=true
  build=$(cd "${2:?fuzz/run.sh --replay BUILD}" && pwd)
  shift 2
else
  seconds=${1:-60}
  build=$root/build-fuzz
  [ $# -eq 0 ] || shift
fi
data=${TLSMON_DATA_DIR:-$root/../shared/data}
jobs=${JOBS:-2}
max_len=65536  # seeds are cut to this size, so what is fuzzed is what is in the corpus

names=("$@")
if [ ${#names[@]} -eq 0 ]; then
  for src in "$root"/fuzz/*.cpp; do names+=("$(basename "$src" .cpp)"); done
fi
[ ${#names[@]} -gt 0 ] || { echo "fuzz/run.sh: no fuzz/*.cpp" >&2; exit 1; }

$replay || CXX=${CXX:-clang++} cmake -S "$root" -B "$build" -DTLSMON_FUZZ=ON \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTLSMON_DATA_DIR="$data" >/dev/null
cmake --build "$build" -j"$jobs" --target "${names[@]/#/fuzz_}"

# Seed files of a target: the data files of its format. The shared data has no PLY or PCD
# files, so write_seeds adds a few small ones of every encoding for those targets.
seed_patterns() {
  case "$1" in
    ascii) echo "*.xyz *.pts" ;;
    las) echo "*.las *.laz" ;;
    *) echo "*.$1" ;;
  esac
}

write_seeds() {  # target corpus-folder
  local xyz='property float x\nproperty float y\nproperty float z\n'
  case "$1" in
    ply)
      printf "ply\nformat ascii 1.0\nelement vertex 2\n${xyz}property uchar intensity\nproperty list uchar int l\nend_header\n1 2 3 50 2 7 8\nnan 0 0 0 0\n" >"$2/ascii.ply"
      printf "ply\nformat binary_little_endian 1.0\nelement face 1\nproperty list uchar int v\nelement vertex 1\n${xyz}property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n\x01\x05\x00\x00\x00\x00\x00\x80\x3f\x00\x00\x00\x40\x00\x00\x40\x40\x0a\x14\x1e" >"$2/binary.ply"
      printf "ply\nformat binary_big_endian 1.0\nelement vertex 1\n${xyz}element camera 1\nproperty float view_px\nproperty int viewportx\nproperty int viewporty\nend_header\n\x3f\x80\x00\x00\x40\x00\x00\x00\x40\x40\x00\x00\x41\x20\x00\x00\x00\x00\x00\x01\x00\x00\x00\x01" >"$2/big.ply"
      ;;
    pcd)
      local head='VERSION 0.7\nFIELDS x y z intensity rgb\nSIZE 4 4 4 1 4\nTYPE F F F U U\nCOUNT 1 1 1 1 1\n'
      printf "# .PCD v0.7\n${head}WIDTH 2\nHEIGHT 1\nVIEWPOINT 1 2 3 1 0 0 0\nPOINTS 2\nDATA ascii\n1 2 3 50 16711680\nnan nan nan 0 0\n" >"$2/ascii.pcd"
      printf "${head}WIDTH 1\nHEIGHT 2\nPOINTS 2\nDATA binary\n\x00\x00\x80\x3f\x00\x00\x00\x40\x00\x00\x40\x40\x32\x00\x00\xff\x00\x00\x00\xc0\x7f\x00\x00\xc0\x7f\x00\x00\xc0\x7f\x00\x00\x00\x00\x00" >"$2/binary.pcd"
      # 2 points of 17 bytes = 34 bytes: a literal run of 8, then a back reference of 26
      printf "${head}WIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA binary_compressed\n\x0c\x00\x00\x00\x22\x00\x00\x00\x07\x00\x00\x80\x3f\x00\x00\x80\x3f\xe0\x11\x07\x00" >"$2/compressed.pcd"
      ;;
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
  write_seeds "$name" "$corpus"
  seeds=$(find "$corpus" -type f | wc -l)
  log=$work/$name.log
  status=0
  if $replay; then
    echo "== fuzz_$name: replaying $seeds seed files"
    "$build/fuzz/fuzz_$name" -runs=0 -artifact_prefix="$build/crashes/$name-" "$corpus" \
      >"$log" 2>&1 || status=$?
    if [ "$status" -ne 0 ]; then
      tail -n 60 "$log"
      # The replay main names each input before running it: keep the last one.
      last=$(sed -n 's/^Running: //p' "$log" | tail -1)
      [ -z "$last" ] || cp "$last" "$build/crashes/$name-$(basename "$last")"
      failed+=("fuzz_$name")
      summary+=("fuzz_$name: CRASH (exit $status) replaying the seeds")
    else
      summary+=("fuzz_$name: $seeds seeds replayed, no report")
    fi
    continue
  fi
  echo "== fuzz_$name: $seconds s, $seeds seed files"
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
