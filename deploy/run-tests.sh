#!/usr/bin/env bash
# Fresh Debian 12 machine -> dependencies installed, tlsmon built, the whole suite run.
set -euo pipefail
cd "$(dirname "$0")/.."
bash deploy/install-deps.sh
bash deploy/build.sh
cd build
ctest --output-on-failure -j "$(nproc)" --timeout 900
