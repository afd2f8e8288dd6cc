#!/bin/sh
# Retakes docs/screenshots/*.png from the real garmcapd on the simulated rig: the browser test's
# run against the daemon (rig case_002, a skirt), on portrait tablets of 768x1024 and 1024x1366
# (each file name ends in its viewport), and the hub's review UI (hub-*.png, browser_hub_test.mjs).
# Writes into the source tree, so CI never runs it; run it by hand after a UI change:
#   tests/browser/update_screenshots.sh [BUILD_DIR]        (default: ./build, already built)
# The PNGs are shrunk with pngquant (Debian package pngquant) when it is installed.
set -eu
src=$(cd "$(dirname "$0")/../.." && pwd)
build=$(cd "${1:-$src/build}" && pwd)
node_dir=$build/tests/browser/node
for f in "$build/bin/garmcapd" "$build/bin/garmcap-hub" "$node_dir/browser_test.mjs"; do
  [ -e "$f" ] || { echo "update_screenshots: $f is missing: configure and build $build first" >&2; exit 1; }
done
if [ ! -d "$node_dir/node_modules/playwright-core" ]; then
  (cd "$node_dir" && npm ci --no-audit --no-fund --loglevel=error)
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
(cd "$node_dir" && node browser_test.mjs "$build/bin/garmcapd" "$build/share/garmcap/web" "$tmp" \
  --rig "$src/tests/data/rig/case_002")
# The hub's review UI (hub-*.png) from the real garmcap-hub on a throwaway PostgreSQL; without
# PostgreSQL's binaries (exit 77) the hub's screenshots stay as they are.
hub_rc=0
(cd "$node_dir" && node browser_hub_test.mjs "$build/bin/garmcap-hub" "$build/share/garmcap/hub-web" \
  "$tmp" "$src/tests/data") || hub_rc=$?
[ "$hub_rc" = 0 ] || [ "$hub_rc" = 77 ] || exit "$hub_rc"
out=$src/docs/screenshots
mkdir -p "$out"
for f in "$out"/*.png; do
  case $(basename "$f") in hub-*) [ "$hub_rc" = 77 ] && continue ;; esac
  rm -f "$f"
done
for f in "$tmp"/*.png; do
  name=$(basename "$f")
  if command -v pngquant >/dev/null 2>&1; then
    pngquant --quality 70-95 --speed 1 --strip --output "$out/$name" -- "$f"
  else
    cp "$f" "$out/$name"
  fi
done
echo "update_screenshots: wrote" && ls -l "$out"
