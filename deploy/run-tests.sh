#!/usr/bin/env bash
# Fresh Debian 12 machine -> dependencies installed, tlsmon built, the whole suite run.
# With CI=true (as .ci/run is run) warnings are errors (-DTLSMON_WERROR=ON); a user's build
# keeps them as warnings, so a newer compiler's new warning never stops it.
set -euo pipefail
cd "$(dirname "$0")/.."
bash deploy/install-deps.sh
cmake_args=()
if [ "${CI:-}" = true ]; then cmake_args+=(-DTLSMON_WERROR=ON); fi
bash deploy/build.sh "${cmake_args[@]}"
cd build
ctest --output-on-failure -j "$(nproc)" --timeout 900
