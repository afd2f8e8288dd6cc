#!/bin/sh
# ctest: systemd-analyze verify on systemd/garmcapd.service (ExecStart pointed at the built
# binary, since /usr/bin/garmcapd is not installed in CI), and the security exposure score.
# Exit 77 (skipped) when systemd-analyze is absent.
set -eu
src=$1; bin=$2
if ! command -v systemd-analyze >/dev/null 2>&1; then
  echo "SKIP: systemd-analyze not found; install the systemd package to verify the unit"
  exit 77
fi
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
sed "s#^ExecStart=/usr/bin/garmcapd#ExecStart=$bin#" "$src/systemd/garmcapd.service" > "$tmp/garmcapd.service"
systemd-analyze verify --man=no "$tmp/garmcapd.service"
score=$(systemd-analyze security --offline=yes "$tmp/garmcapd.service" 2>/dev/null | sed -n 's/.*Overall exposure level for garmcapd.service: \([0-9.]*\).*/\1/p')
echo "systemd-analyze security exposure: ${score:-unknown} (goal <= 2.5)"
if [ -n "$score" ]; then awk -v s="$score" 'BEGIN { exit !(s <= 2.5) }'; fi
