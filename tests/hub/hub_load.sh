#!/bin/sh
# The chain under load, by hand (not in ctest: minutes per hundred captures on 2 cores): a
# throwaway PostgreSQL, garmcap-hub and STATIONS simulated stations (garmcapd --simulated on the
# replay rig of tests/data/rig/case_002, as hub_e2e_test runs them) on loopback, each making N
# captures one after the other (the stations in parallel) while its pusher sends them. Prints
# how long the captures took, when the last item was at the hub, and then, with every item
# approved at the hub (in SQL: the export takes approved items only), how long the chain's
# Shopify CSV took, read back by Python's csv module (strict) and its SKUs counted.
#   tests/hub/hub_load.sh build/bin [N=200 [STATIONS=3]]
set -eu
bindir=$(readlink -f "$1"); n=${2:-200}; stations=${3:-3}
src=$(cd "$(dirname "$0")/../.." && pwd)
bin=$(ls -d /usr/lib/postgresql/*/bin | sort | tail -1)
tmp=$(mktemp -d); chmod 755 "$tmp"
run() { if [ "$(id -u)" = 0 ]; then runuser -u nobody -- sh -c "$1"; else sh -c "$1"; fi; }
[ "$(id -u)" = 0 ] && chown nobody "$tmp"
freeport() { python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])'; }
port=$(freeport); hport=$(freeport)
pids=
cleanup() {
  for p in $pids; do kill "$p" 2>/dev/null || true; done
  run "$bin/pg_ctl -D $tmp/data -m immediate stop" >/dev/null 2>&1 || true
  rm -rf "$tmp"
}
trap cleanup EXIT
now() { date +%s.%N; }
since() { echo "$(now) - $1" | bc; }
waitline() {  # $1 = file, $2 = text: up to 60 s
  for i in $(seq 600); do grep -qs "$2" "$1" && return 0; sleep 0.1; done
  echo "timed out waiting for '$2' in $1" >&2; return 1
}
run "$bin/initdb -D $tmp/data -U garmcap --auth=trust -E UTF8 --no-locale --no-sync" >/dev/null
run "$bin/pg_ctl -D $tmp/data -l $tmp/pg.log -o '-p $port -k $tmp -c listen_addresses=127.0.0.1' -w start" >/dev/null
psql="$bin/psql -X -q -A -t -h 127.0.0.1 -p $port -U garmcap"
$psql -d postgres -c 'CREATE DATABASE load'
hubargs="--admin-token-sha256 $("$bindir/garmcap-hub" hash-token admin-token)"
for s in $(seq "$stations"); do
  hubargs="$hubargs --station shop$s=$("$bindir/garmcap-hub" hash-token "token-of-shop$s")"
done
# shellcheck disable=SC2086
"$bindir/garmcap-hub" --db "host=127.0.0.1 port=$port user=garmcap dbname=load" \
  --listen "127.0.0.1:$hport" $hubargs >"$tmp/hub.out" 2>"$tmp/hub.err" &
pids="$pids $!"
waitline "$tmp/hub.out" listening
mkdir -p "$tmp/rig/c1"
for f in empty.png empty.jpg dressed.png dressed.jpg truth.json; do
  [ -f "$src/tests/data/rig/case_002/$f" ] && cp "$src/tests/data/rig/case_002/$f" "$tmp/rig/c1/"
done
echo '{"format": "garmcap-rig", "version": 1, "cases": [{"id": "c1", "dir": "c1", "type": "skirt", "attributes": {}, "hard": false}]}' >"$tmp/rig/rig.json"
for s in $(seq "$stations"); do
  mkdir -p "$tmp/s$s"
  printf '[hub]\nurl = "http://127.0.0.1:%s"\ntoken = "token-of-shop%s"\npoll_ms = 200\n' "$hport" "$s" >"$tmp/s$s.toml"
  "$bindir/garmcapd" --simulated --data "$tmp/s$s" --listen 127.0.0.1:0 --camera replay \
    --device "$tmp/rig" --config "$tmp/s$s.toml" >"$tmp/s$s.out" 2>"$tmp/s$s.err" &
  pids="$pids $!"
done
job() {  # $1 = station port, $2 = job JSON of a POST: waits for the job, prints its item id
  id=$(echo "$2" | python3 -c 'import json,sys; print(json.load(sys.stdin)["job"])')
  while :; do
    state=$(curl -s "http://127.0.0.1:$1/api/jobs/$id")
    case "$state" in
      *'"state":"done"'* | *'"state": "done"'*) echo "$state" | python3 -c 'import json,sys; print(json.load(sys.stdin).get("item_id"))'; return 0 ;;
      *'"state":"failed"'* | *'"state": "failed"'*) echo "job $id failed: $state" >&2; return 1 ;;
    esac
    sleep 0.2
  done
}
for s in $(seq "$stations"); do
  waitline "$tmp/s$s.out" "garmcapd listening on"
  sport=$(sed -n 's/.*garmcapd listening on 127.0.0.1:\([0-9]*\).*/\1/p' "$tmp/s$s.out" | head -1)
  echo "$sport" >"$tmp/s$s.port"
  job "$sport" "$(curl -s -X POST "http://127.0.0.1:$sport/api/capture/empty")" >/dev/null
done
echo "$stations stations calibrated; $n captures each"
start=$(now)
capturers=
for s in $(seq "$stations"); do
  (
    sport=$(cat "$tmp/s$s.port")
    for i in $(seq "$n"); do
      job "$sport" "$(curl -s -X POST -H 'Content-Type: application/json' \
        -d "{\"sku\": \"S$s-$i\"}" "http://127.0.0.1:$sport/api/capture")" >/dev/null
    done
    echo "station shop$s: $n captures in $(since "$start") s"
  ) &
  capturers="$capturers $!"
done
# shellcheck disable=SC2086
wait $capturers
captured=$(since "$start")
total=$((n * stations))
while [ "$($psql -d load -c 'SELECT count(*) FROM items WHERE deleted_at IS NULL')" -lt "$total" ]; do
  sleep 0.2
done
echo "all $total captures done after $captured s; all $total items at the hub after $(since "$start") s"
for s in $(seq "$stations"); do
  echo "shop$s outbox left: $(curl -s "http://127.0.0.1:$(cat "$tmp/s$s.port")/api/status" | python3 -c 'import json,sys; print(json.load(sys.stdin)["hub"]["outbox"])')"
done
$psql -d load -c "UPDATE items SET status = 'approved', hub_owned = true"
$psql -d load -c "SELECT 'images at the hub: ' || count(*) || ', ' || pg_size_pretty(sum(size)) FROM images"
t=$(now)
curl -s -o "$tmp/chain.csv" -w '%{http_code}\n' -H 'Authorization: Bearer admin-token' \
  "http://127.0.0.1:$hport/api/export/shopify.csv?base_url=https://files.shop.example&store_url=https://shop.example&brand=Chain" >"$tmp/code"
echo "chain shopify.csv: HTTP $(cat "$tmp/code") in $(since "$t") s, $(wc -c <"$tmp/chain.csv") bytes"
python3 - "$tmp/chain.csv" "$total" <<'PY'
import csv, sys
rows = list(csv.reader(open(sys.argv[1], newline="", encoding="utf-8"), strict=True))
sku = rows[0].index("SKU")
skus = [r[sku] for r in rows[1:] if r[sku]]
print(f"{len(rows) - 1} rows, {len(set(skus))} distinct SKUs of {sys.argv[2]} items, "
      f"{len(skus) - len(set(skus))} repeated")
PY
