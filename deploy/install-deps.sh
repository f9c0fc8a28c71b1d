#!/usr/bin/env bash
# Installs the Debian 12 packages tlsmon builds and runs with; with --tests also those the
# test suite is built with (GoogleTest, clang for the fuzz targets, clang-format for CI's
# format check) and drives (a headless browser and its WebDriver, a JSON Schema validator for
# the API's OpenAPI description, curl and openssl for the HTTP and HTTPS tests, an SMTP
# server and an MQTT broker with its clients for the notification tests, PostgreSQL 15 for the
# central database's tests (each starts a cluster of its own), and independent
# readers for the export tests: GDAL's ogrinfo for GeoJSON, copc.js from the npm registry
# for LAS; lintian and help2man for the Debian package). Idempotent: when everything is
# already installed it changes nothing and asks no mirror.
set -euo pipefail

packages=(
  build-essential cmake pkg-config ccache mold git
  libeigen3-dev libspdlog-dev libfmt-dev libsqlite3-dev sqlite3 libsqlitecpp-dev libssl-dev
  libpcl-dev libopencv-dev libmodbus-dev libsystemd-dev libtbb-dev libcurl4-openssl-dev libmosquitto-dev
  libtomlplusplus-dev libcli11-dev nlohmann-json3-dev libcpp-httplib-dev libpugixml-dev libboost-dev libpng-dev
  libproj-dev libpq-dev
  mbpoll gnuplot-nox libjs-dygraphs
)
if [ "${1:-}" = --tests ]; then
  packages+=(libgtest-dev libgmock-dev clang libclang-rt-dev clang-format help2man)
  packages+=(chromium chromium-driver python3-selenium python3-jsonschema curl openssl
             python3-aiosmtpd mosquitto mosquitto-clients gdal-bin lintian postgresql-15)
  # Node.js runs the independent LAS reader; a machine's own Node.js and npm are kept.
  if ! command -v node > /dev/null || ! command -v npm > /dev/null; then packages+=(nodejs npm); fi
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("$p")
  fi
done
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
else
  echo "install-deps: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -q
  $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

# The export tests' LAS reader, at the version package-lock.json pins (tests/export).
if [ "${1:-}" = --tests ]; then
  checks="$(cd "$(dirname "$0")/.." && pwd)/tests/export"
  if [ ! -f "$checks/node_modules/copc/package.json" ]; then
    echo "install-deps: installing copc.js for the export tests"
    npm ci --prefix "$checks" --no-audit --no-fund
  fi
fi
