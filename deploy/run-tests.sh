#!/usr/bin/env bash
# Fresh Debian 12 machine -> dependencies installed, tlsmon built, the whole suite run, the
# Debian package built and checked (deploy/build-package.sh).
# With CI=true (as .ci/run is run) warnings are errors (-DTLSMON_WERROR=ON), and after the
# suite a second build under AddressSanitizer + UndefinedBehaviorSanitizer runs the core,
# formats and storage tests and replays the fuzz corpora (deploy/run-sanitizers.sh). A
# user's build keeps warnings as warnings, so a newer compiler's new warning never stops it.
# CI also checks that every C++ source is formatted as .clang-format says, before building.
set -euo pipefail
cd "$(dirname "$0")/.."
bash deploy/install-deps.sh --tests
if [ "${CI:-}" = true ]; then
  git ls-files -z '*.cpp' '*.hpp' | xargs -0 clang-format --dry-run -Werror
fi
# Explicitly on: a build folder configured by run-demo.sh has them off.
cmake_args=(-DTLSMON_TESTS=ON -DTLSMON_BENCH=ON)
if [ "${CI:-}" = true ]; then cmake_args+=(-DTLSMON_WERROR=ON); fi
bash deploy/build.sh "${cmake_args[@]}"
(cd build && ctest --output-on-failure -j "$(nproc)" --timeout 900)
# The Debian package: built, inspected (dpkg-deb, lintian), installed and purged again.
bash deploy/build-package.sh --install
if [ "${CI:-}" = true ]; then bash deploy/run-sanitizers.sh; fi
