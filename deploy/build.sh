#!/usr/bin/env bash
# Configures and builds tlsmon in ./build (RelWithDebInfo) on every core.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo "$@"
cmake --build build -j "$(nproc)"
