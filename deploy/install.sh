#!/usr/bin/env bash
# Installs tlsmon as a service: the program (tlsmon and, beside it, tlsmon-analysis, which
# carries out the measuring commands), the configuration (paths rewritten to
# /var/lib/tlsmon), the folders, a `tlsmon` system user and the systemd unit.
# Run as root after deploy/build.sh. Idempotent: an existing /etc/tlsmon/tlsmon.toml is
# kept (the new default is written beside it as tlsmon.toml.default).
set -euo pipefail
cd "$(dirname "$0")/.."

BIN=build/tlsmon
ANALYSIS=build/tlsmon-analysis
PREFIX=${PREFIX:-/usr/local}
STATE=/var/lib/tlsmon
for f in "$BIN" "$ANALYSIS"; do
  [ -x "$f" ] || { echo "install: $f missing; run deploy/build.sh first" >&2; exit 1; }
done
[ "$(id -u)" -eq 0 ] || { echo "install: run as root" >&2; exit 1; }

id -u tlsmon >/dev/null 2>&1 ||
  useradd --system --home-dir "$STATE" --no-create-home --shell /usr/sbin/nologin tlsmon

install -D -m 0755 "$BIN" "$PREFIX/bin/tlsmon"
install -D -m 0755 "$ANALYSIS" "$PREFIX/bin/tlsmon-analysis"
# The dashboard's files, where the daemon looks for them (../share/tlsmon/web beside bin/).
rm -rf "$PREFIX/share/tlsmon/web"
install -d -m 0755 "$PREFIX/share/tlsmon/web"
cp -r build/web/. "$PREFIX/share/tlsmon/web/"
install -d -m 0750 -o tlsmon -g tlsmon "$STATE" "$STATE/ingest" "$STATE/archive" \
  "$STATE/quarantine"
# The scanner's export user must be able to write into the ingest folder: add it to the
# tlsmon group, or make this folder a mount of the scanner's share.
chmod 0770 "$STATE/ingest"

install -d -m 0755 /etc/tlsmon
config=$(sed -e "s|\"\.\./var/ingest\"|\"$STATE/ingest\"|" \
             -e "s|\"\.\./var/archive\"|\"$STATE/archive\"|" \
             -e "s|\"\.\./var/quarantine\"|\"$STATE/quarantine\"|" \
             -e "s|\"\.\./var/tlsmon.sqlite\"|\"$STATE/tlsmon.sqlite\"|" etc/tlsmon.toml)
if [ -e /etc/tlsmon/tlsmon.toml ]; then
  printf '%s\n' "$config" > /etc/tlsmon/tlsmon.toml.default
  echo "install: kept /etc/tlsmon/tlsmon.toml (new default: tlsmon.toml.default)"
else
  printf '%s\n' "$config" > /etc/tlsmon/tlsmon.toml
fi
"$PREFIX/bin/tlsmon" check-config /etc/tlsmon/tlsmon.toml >/dev/null

install -D -m 0644 docs/configuration.md "$PREFIX/share/doc/tlsmon/configuration.md"
install -D -m 0644 deploy/tlsmon.service /etc/systemd/system/tlsmon.service
if [ -d /run/systemd/system ]; then
  systemctl daemon-reload
  systemctl enable tlsmon.service
  echo "install: done; start with: systemctl start tlsmon"
else
  echo "install: done (systemd is not running here; the unit is installed)"
fi
