#!/bin/sh
# ctest: systemd-analyze verify on systemd/garmcap-hub.service (ExecStart pointed at the built
# binary) and its security exposure score. Exit 77 (skipped) when systemd-analyze is absent.
set -eu
src=$1; bin=$2
if ! command -v systemd-analyze >/dev/null 2>&1; then
  echo "SKIP: systemd-analyze not found; install the systemd package to verify the unit"
  exit 77
fi
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
sed "s#^ExecStart=/usr/bin/garmcap-hub#ExecStart=$bin#" "$src/systemd/garmcap-hub.service" > "$tmp/garmcap-hub.service"
# postgresql.service is not installed as a unit file everywhere the tests run: verify without it.
sed -i 's/^Requires=postgresql.service$//' "$tmp/garmcap-hub.service"
systemd-analyze verify --man=no "$tmp/garmcap-hub.service"
score=$(systemd-analyze security --offline=yes "$tmp/garmcap-hub.service" 2>/dev/null | sed -n 's/.*Overall exposure level for garmcap-hub.service: \([0-9.]*\).*/\1/p')
echo "systemd-analyze security exposure: ${score:-unknown} (goal <= 2.5)"
if [ -n "$score" ]; then awk -v s="$score" 'BEGIN { exit !(s <= 2.5) }'; fi
