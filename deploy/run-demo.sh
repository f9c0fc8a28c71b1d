#!/usr/bin/env bash
# Fresh Debian 12 machine -> dependencies installed, tlsmon built, the main job run:
# the daemon watches var/ingest (etc/tlsmon.toml) while the built-in simulator drops a scan
# of the `small` bridge-pier scene into it every 2 s, as the scanner would every 15 min.
# Then the epoch database is shown. EPOCHS=N changes the number of scans (default 8).
set -euo pipefail
cd "$(dirname "$0")/.."
bash deploy/install-deps.sh
bash deploy/build.sh

tlsmon=./build/daemon/tlsmon
epochs=${EPOCHS:-8}
rm -rf var && mkdir -p var/ingest

"$tlsmon" run --config etc/tlsmon.toml &
daemon=$!
trap 'kill -TERM $daemon 2>/dev/null || true' EXIT

# The series starts now: the scans come every 2 s but are stamped 15 min apart, so an older
# start would make the first scans look late and raise the system.stale alarm at once.
start=$(date -u +%Y-%m-%dT%H:%M:%SZ)
"$tlsmon" simulate --preset small --out var/ingest --epochs "$epochs" --realtime 2 --start "$start"
# The last scan counts as complete after ingest.stable_seconds (10 s) without change.
for _ in $(seq 60); do
  compgen -G 'var/ingest/*.ptx' >/dev/null || break
  sleep 1
done
kill -TERM $daemon && wait $daemon
trap - EXIT

"$tlsmon" status --config etc/tlsmon.toml
"$tlsmon" query epochs --config etc/tlsmon.toml
