#!/usr/bin/env bash
# Fresh Debian 12 machine -> dependencies installed, tlsmon built, the main job run.
set -euo pipefail
cd "$(dirname "$0")/.."
bash deploy/install-deps.sh
bash deploy/build.sh
./build/daemon/tlsmon info ../shared/data/ptx/pumpA_from_e57.ptx
