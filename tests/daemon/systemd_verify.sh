#!/bin/sh
# ctest: systemd-analyze verify on systemd/UNIT.service (UNIT: garmcapd, or garmcap-hub; ExecStart
# pointed at the built binary, since /usr/bin/UNIT is not installed in CI), and the security
# exposure score. Exit 77 (skipped) when systemd-analyze is absent.
#   systemd_verify.sh SOURCE_DIR BINARY [UNIT]
set -eu
src=$1; bin=$2; unit=${3:-garmcapd}
if ! command -v systemd-analyze >/dev/null 2>&1; then
  echo "SKIP: systemd-analyze not found; install the systemd package to verify the unit"
  exit 77
fi
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
sed "s#^ExecStart=/usr/bin/$unit#ExecStart=$bin#" "$src/systemd/$unit.service" > "$tmp/$unit.service"
# postgresql.service (the hub's) is not installed as a unit file everywhere the tests run.
sed -i '/^Requires=postgresql.service$/d' "$tmp/$unit.service"
systemd-analyze verify --man=no "$tmp/$unit.service"
score=$(systemd-analyze security --offline=yes "$tmp/$unit.service" 2>/dev/null | sed -n "s/.*Overall exposure level for $unit.service: \([0-9.]*\).*/\1/p")
echo "systemd-analyze security exposure: ${score:-unknown} (goal <= 2.5)"
if [ -n "$score" ]; then awk -v s="$score" 'BEGIN { exit !(s <= 2.5) }'; fi
