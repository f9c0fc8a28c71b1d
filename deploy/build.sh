#!/usr/bin/env bash
# Configures and builds tlsmon in ./build (RelWithDebInfo) on every core. Extra arguments go
# to CMake (e.g. -DTLSMON_WERROR=ON). TLSMON_TARGETS="tlsmon" builds only those targets (the
# demo needs the program, tlsmon and tlsmon-analysis, not the tests and benchmarks); unset:
# everything. CMake compiles through ccache when it is installed
# (deploy/install-deps.sh installs it); this script says so, with this build's hit rate.
set -euo pipefail
cd "$(dirname "$0")/.."

if command -v ccache >/dev/null; then
  echo "build: compiling through $(ccache --version | head -1), cache $(ccache --get-config cache_dir)"
  # This build's own counters (the cache may be shared with other builds).
  export CCACHE_STATSLOG=$PWD/build/ccache-stats.log
  mkdir -p build
  rm -f "$CCACHE_STATSLOG"
else
  echo "build: no ccache; every file is compiled"
fi

cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo "$@"
targets=()
for t in ${TLSMON_TARGETS:-}; do targets+=(--target "$t"); done
cmake --build build -j "$(nproc)" "${targets[@]}"

if [ -n "${CCACHE_STATSLOG:-}" ] && [ -f "$CCACHE_STATSLOG" ]; then
  echo "build: ccache for this build:"
  ccache --show-log-stats | grep -E "^(Cacheable|  Hits|  Misses)" || true
fi
