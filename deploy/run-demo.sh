#!/usr/bin/env bash
# Fresh Debian 12 machine -> dependencies installed, tlsmon built, the main job run.
set -euo pipefail
cd "$(dirname "$0")/.."
bash deploy/install-deps.sh
bash deploy/build.sh
rm -rf var && mkdir -p var/ingest && { ./build/daemon/tlsmon run --config etc/tlsmon.toml & d=$!; ./build/daemon/tlsmon simulate --preset small --out var/ingest --epochs 8 --realtime 2; sleep 14; kill -TERM $d; wait $d; } && ./build/daemon/tlsmon status --config etc/tlsmon.toml
