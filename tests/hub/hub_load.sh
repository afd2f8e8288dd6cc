#!/bin/sh
# The chain under load, by hand (not in ctest: minutes per hundred captures on 2 cores): a
# throwaway PostgreSQL, garmcap-hub and STATIONS simulated stations (garmcapd --simulated: the
# synthetic camera renders a new garment for every capture) on loopback, their stills made
# STILL pixels (default 480x640, a quarter of the simulator's 960x1280: [camera] still_width and
# still_height) so that the run fits a shared 2-core machine. Each station makes N captures one
# after the other (the stations in parallel) while its pusher sends them; a capture the pipeline
# refuses (its job fails, no item is filed) is counted and printed, not fatal. Then:
#  - waits until every filed item is at the hub (at most 10 minutes after the last capture), checks
#    that each is there exactly once: per station, the hub's local ids are the station's item
#    ids, none twice, and each item's images (kind -> sha256) are the station's; every blob at the
#    hub hashes (PostgreSQL's sha256()) to its name;
#  - approves every item at the hub (in SQL: the exports take approved items only) and times the
#    chain's shopify.csv, woocommerce.csv, merchant.tsv and catalog.zip, reading the Shopify CSV
#    back with Python's csv module (strict) and the ZIP with its zipfile (CRC-checked).
#   tests/hub/hub_load.sh build/bin [N=200 [STATIONS=3 [STILL=480x640]]]
set -eu
bindir=$(readlink -f "$1"); n=${2:-200}; stations=${3:-3}; still=${4:-480x640}
still_w=${still%x*}; still_h=${still#*x}
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
for s in $(seq "$stations"); do
  mkdir -p "$tmp/s$s"
  printf '[camera]\nstill_width = %s\nstill_height = %s\n[hub]\nurl = "http://127.0.0.1:%s"\ntoken = "token-of-shop%s"\npoll_ms = 200\n' \
    "$still_w" "$still_h" "$hport" "$s" >"$tmp/s$s.toml"
  "$bindir/garmcapd" --simulated --data "$tmp/s$s" --listen 127.0.0.1:0 \
    --config "$tmp/s$s.toml" >"$tmp/s$s.out" 2>"$tmp/s$s.err" &
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
echo "$stations stations calibrated; $n captures each, stills ${still_w}x${still_h}"
start=$(now)
capturers=
for s in $(seq "$stations"); do
  (
    sport=$(cat "$tmp/s$s.port")
    refused=0
    for i in $(seq "$n"); do
      # A capture the pipeline refuses (a failed job: no item) is counted, not fatal: what
      # this measures is the chain, and every item a station files must reach the hub.
      job "$sport" "$(curl -s -X POST -H 'Content-Type: application/json' \
        -d "{\"sku\": \"S$s-$i\"}" "http://127.0.0.1:$sport/api/capture")" >/dev/null 2>"$tmp/s$s.job" ||
        { refused=$((refused + 1)); sed 's/^/  /' "$tmp/s$s.job" >&2; }
    done
    echo "station shop$s: $n captures in $(since "$start") s, $refused refused by the pipeline"
  ) &
  capturers="$capturers $!"
done
# shellcheck disable=SC2086
wait $capturers
captured=$(since "$start")
total=0
for s in $(seq "$stations"); do
  filed=$(curl -s "http://127.0.0.1:$(cat "$tmp/s$s.port")/api/items?limit=1" | python3 -c 'import json,sys; print(json.load(sys.stdin)["total"])')
  total=$((total + filed))
done
deadline=$(( $(date +%s) + 600 ))
while [ "$($psql -d load -c 'SELECT count(*) FROM items WHERE deleted_at IS NULL')" -lt "$total" ]; do
  if [ "$(date +%s)" -gt "$deadline" ]; then
    echo "FAIL: $($psql -d load -c 'SELECT count(*) FROM items') of $total items at the hub 10 minutes after the last capture" >&2
    exit 1
  fi
  sleep 0.2
done
echo "all captures done after $captured s ($total filed); all $total items at the hub after $(since "$start") s"
for s in $(seq "$stations"); do
  echo "shop$s outbox left: $(curl -s "http://127.0.0.1:$(cat "$tmp/s$s.port")/api/status" | python3 -c 'import json,sys; print(json.load(sys.stdin)["hub"]["outbox"])')"
done
# Exactly once, with the station's images: each station's items (its API) against the hub's
# (the admin's API), and every blob's bytes against its name.
for s in $(seq "$stations"); do
  echo "shop$s $(cat "$tmp/s$s.port")"
done >"$tmp/stations"
python3 - "$tmp/stations" "$hport" <<'PY'
import json, sys, urllib.request
stations = [l.split() for l in open(sys.argv[1])]
hub = sys.argv[2]
def get(url, token=None):
    req = urllib.request.Request(url, headers={"Authorization": "Bearer " + token} if token else {})
    return json.load(urllib.request.urlopen(req))
def images(item):
    return {k: v["sha256"] for k, v in item["images"].items()}
bad = 0
for name, port in stations:
    local, offset = {}, 0
    while True:
        page = get(f"http://127.0.0.1:{port}/api/items?limit=500&offset={offset}")
        for it in page["items"]:
            local[it["id"]] = images(it)
        offset += len(page["items"])
        if not page["items"] or offset >= page["total"]:
            break
    at_hub, ids, after = {}, [], None
    while True:
        page = get(f"http://127.0.0.1:{hub}/api/items?limit=500&station={name}" + (f"&after={after}" if after else ""), "admin-token")
        for it in page["items"]:
            ids.append(it["local_id"])
            at_hub[it["local_id"]] = images(it)
        after = page["next"]
        if after is None:
            break
    twice = len(ids) - len(set(ids))
    differ = sum(1 for k in local if at_hub.get(k) != local[k])
    print(f"{name}: {len(local)} items at the station, {len(ids)} at the hub, {twice} twice, "
          f"{len(set(at_hub) - set(local))} unknown, {differ} with other images")
    bad += twice + differ + len(set(at_hub) ^ set(local))
sys.exit(1 if bad else 0)
PY
echo "blobs at the hub whose bytes do not hash to their name: $($psql -d load -c "SELECT count(*) FROM images WHERE encode(sha256(bytes), 'hex') <> sha256")"
$psql -d load -c "SELECT 'images at the hub: ' || count(*) || ', ' || pg_size_pretty(sum(size)) FROM images"
$psql -d load -c "SELECT 'item images: ' || count(*) || ' (' || count(DISTINCT sha256) || ' distinct)' FROM item_images"
$psql -d load -c "UPDATE items SET status = 'approved', hub_owned = true"
opts="base_url=https://files.shop.example&store_url=https://shop.example&brand=Chain"
for f in shopify.csv woocommerce.csv merchant.tsv catalog.zip; do
  curl -s -o "$tmp/chain-$f" -H 'Authorization: Bearer admin-token' \
    -w "chain $f: HTTP %{http_code} in %{time_total} s, %{size_download} bytes\n" \
    "http://127.0.0.1:$hport/api/export/$f?$opts"
done
python3 - "$tmp/chain-shopify.csv" "$tmp/chain-catalog.zip" "$total" <<'PY'
import csv, sys, zipfile
rows = list(csv.reader(open(sys.argv[1], newline="", encoding="utf-8"), strict=True))
head = rows[0]
sku, title = head.index("SKU"), head.index("Title")
products = [r[sku] for r in rows[1:] if r[title]]
print(f"shopify.csv: {len(rows) - 1} rows, {len(products)} products, {len(set(products))} distinct "
      f"SKUs of {sys.argv[3]} items")
z = zipfile.ZipFile(sys.argv[2])
bad = z.testzip()
print(f"catalog.zip: {len(z.namelist())} entries, CRC {'bad: ' + bad if bad else 'ok'}")
sys.exit(0 if len(set(products)) == int(sys.argv[3]) and not bad else 1)
PY
