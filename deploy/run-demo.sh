#!/usr/bin/env bash
# Fresh Debian 12 machine -> dependencies installed, tlsmon built, the main job run:
# `tlsmon demo` starts the daemon (Modbus on 127.0.0.1:1502) on a fresh database in var/demo,
# feeds it a simulated day of the `small` bridge-pier scene (one scan every 2 s, stamped
# 15 min apart: thermal bending, scanner drift, a knocked target, a step of the pier's top
# band), prints a line per epoch, stops the daemon and scores the run against the
# simulator's truth in var/demo/report/. Arguments go to `tlsmon demo` (e.g. --epochs 24);
# EPOCHS=N is kept as a shorthand for --epochs N.
set -euo pipefail
cd "$(dirname "$0")/.."
bash deploy/install-deps.sh
# The program only: neither the test suite nor the benchmarks are configured or built.
TLSMON_TARGETS=tlsmon bash deploy/build.sh -DTLSMON_TESTS=OFF -DTLSMON_BENCH=OFF

args=(--workdir var/demo)
[ -n "${EPOCHS:-}" ] && args+=(--epochs "$EPOCHS")
exec ./build/tlsmon demo "${args[@]}" "$@"
