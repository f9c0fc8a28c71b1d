#!/usr/bin/env bash
# CI's second build: AddressSanitizer + UndefinedBehaviorSanitizer (gcc) in build-asan/.
# Builds and runs the core, formats and storage unit tests, and replays every fuzz target
# once over its seed corpus (no fuzzing: fuzz/run.sh --replay). Any sanitizer report stops
# the program and fails this script. deploy/run-tests.sh runs it when CI=true, after the
# normal suite; alone: bash deploy/run-sanitizers.sh
set -euo pipefail
cd "$(dirname "$0")/.."
build=build-asan
export ASAN_OPTIONS=halt_on_error=1
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1

tests=(tests_core tests_formats tests_storage)
fuzzers=()
for src in fuzz/*.cpp; do fuzzers+=("fuzz_$(basename "$src" .cpp)"); done

# Debug keeps the assertions; -O1 keeps every sanitizer check and runs the tests on real
# files several times faster than -O0. Warnings are the normal build's business.
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-g -O1" \
  -DTLSMON_SANITIZE=ON -DTLSMON_BENCH=OFF >/dev/null
cmake --build "$build" -j "$(nproc)" --target "${tests[@]}" "${fuzzers[@]}"

for t in "${tests[@]}"; do
  echo "== $t under ASan+UBSan"
  (cd "$build/tests" && "./$t" --gtest_brief=1)
done
JOBS=$(nproc) bash fuzz/run.sh --replay "$build"
echo "sanitizers: ${tests[*]} and ${#fuzzers[@]} fuzz corpora ran without a report"
