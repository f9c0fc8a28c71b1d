#!/usr/bin/env bash
# Builds the Debian package of tlsmon (cmake/TlsmonPackage.cmake) in ./build and checks it:
# its files (dpkg-deb -c), its control data (dpkg-deb -I: Depends computed by
# dpkg-shlibdeps), `lintian` with no error; and, as root with --install, installs it on this
# machine (dpkg -i), runs the installed `tlsmon --version` and `tlsmon check-config` on the
# packaged configuration, finds the unit and the user, then purges it again. Prints the
# package's path. The test command runs it with --install (deploy/run-tests.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
[ -f build/CMakeCache.txt ] || { echo "build-package: run deploy/build.sh first" >&2; exit 1; }
rm -f build/tlsmon_*.deb
(cd build && cpack -G DEB > cpack.log 2>&1) || { cat build/cpack.log >&2; exit 1; }
deb=$(ls build/tlsmon_*.deb)
echo "build-package: $deb ($(du -h "$deb" | cut -f1))"

contents=$(dpkg-deb -c "$deb")
for f in ./usr/bin/tlsmon ./usr/bin/tlsmon-analysis ./lib/systemd/system/tlsmon.service \
         ./etc/tlsmon/tlsmon.toml ./usr/share/tlsmon/web/index.html \
         ./usr/share/doc/tlsmon/copyright ./usr/share/doc/tlsmon/changelog.Debian.gz \
         ./usr/share/doc/tlsmon/configuration.md ./usr/share/man/man1/tlsmon.1.gz \
         ./usr/share/man/man1/tlsmon-analysis.1.gz; do
  grep -q " $f\$" <<< "$contents" || { echo "build-package: $f is not in $deb" >&2; exit 1; }
done
if grep -v ' root/root ' <<< "$contents" | grep -q .; then
  echo "build-package: files not owned by root:" >&2
  grep -v ' root/root ' <<< "$contents" >&2
  exit 1
fi
info=$(dpkg-deb -I "$deb")
grep -q '^ Depends: .*libc6' <<< "$info" || { echo "build-package: no computed Depends" >&2; echo "$info" >&2; exit 1; }
dpkg-deb -I "$deb" conffiles | grep -qx /etc/tlsmon/tlsmon.toml ||
  { echo "build-package: /etc/tlsmon/tlsmon.toml is not a conffile" >&2; exit 1; }
echo "build-package: contents and control data as expected"

# lintian: errors fail the build; warnings are printed for the record.
lintian --fail-on error --tag-display-limit 0 "$deb" || { echo "build-package: lintian found errors" >&2; exit 1; }
echo "build-package: lintian: no errors"

if [ "${1:-}" = --install ] && [ "$(id -u)" -eq 0 ]; then
  if dpkg-query -W tlsmon > /dev/null 2>&1; then
    echo "build-package: a tlsmon package is installed already; not touching it"
    exit 0
  fi
  dpkg -i "$deb"
  trap 'dpkg --purge tlsmon > /dev/null 2>&1 || true' EXIT
  /usr/bin/tlsmon --version
  /usr/bin/tlsmon check-config /etc/tlsmon/tlsmon.toml > /dev/null
  test -f /lib/systemd/system/tlsmon.service
  getent passwd tlsmon > /dev/null
  test "$(stat -c %U:%a /var/lib/tlsmon/ingest)" = tlsmon:770
  dpkg --purge tlsmon > /dev/null
  trap - EXIT
  test ! -e /usr/bin/tlsmon
  test -d /var/lib/tlsmon  # the site's history is never removed by the package
  echo "build-package: installed, ran tlsmon --version and check-config, purged"
fi
