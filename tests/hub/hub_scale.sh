#!/bin/sh
# The hub at the issue's scale, by hand (not in ctest: ~2 minutes): a throwaway PostgreSQL, a
# garmcap-hub, 100,000 items of 3 stations with 300,000 images (small distinct blobs) loaded in
# SQL, then 200 list pages (keyset, per station, deep cursors), 200 searches and 3 x 200 pages
# of the status filter through the HTTP API, timed by curl. Prints p50 and p99 in ms, then the
# status filter's plans (EXPLAIN ANALYZE) with the status indexes of schema 3 and without them.
#   tests/hub/hub_scale.sh build/bin/garmcap-hub [ITEMS [OTHER-GARMCAP-HUB]]
# With a second binary (an older build, say) both serve the same database and each request goes
# to one and then the other, so that both see the same load of a shared machine.
set -eu
hub=$(readlink -f "$1"); items=${2:-100000}; other=${3:+$(readlink -f "$3")}
bin=$(ls -d /usr/lib/postgresql/*/bin | sort | tail -1)
tmp=$(mktemp -d); chmod 755 "$tmp"
run() { if [ "$(id -u)" = 0 ]; then runuser -u nobody -- sh -c "$1"; else sh -c "$1"; fi; }
[ "$(id -u)" = 0 ] && chown nobody "$tmp"
port=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])')
hport=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])')
oport=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])')
cleanup() { kill $hubpid $otherpid 2>/dev/null || true; run "$bin/pg_ctl -D $tmp/data -m immediate stop" >/dev/null 2>&1 || true; rm -rf "$tmp"; }
hubpid=; otherpid=
trap cleanup EXIT
run "$bin/initdb -D $tmp/data -U garmcap --auth=trust -E UTF8 --no-locale --no-sync" >/dev/null
run "$bin/pg_ctl -D $tmp/data -l $tmp/log -o '-p $port -k $tmp -c listen_addresses=127.0.0.1' -w start" >/dev/null
psql="$bin/psql -X -q -h 127.0.0.1 -p $port -U garmcap"
$psql -d postgres -c 'CREATE DATABASE scale'
admin=$("$hub" hash-token admin-token)
"$hub" --db "host=127.0.0.1 port=$port user=garmcap dbname=scale" --listen "127.0.0.1:$hport" \
  --admin-token-sha256 "$admin" --station "shop1=$("$hub" hash-token t1)" \
  --station "shop2=$("$hub" hash-token t2)" --station "shop3=$("$hub" hash-token t3)" \
  >"$tmp/hub.out" 2>"$tmp/hub.err" &
hubpid=$!
for i in $(seq 100); do grep -qs listening "$tmp/hub.out" && break; sleep 0.1; done
if [ -n "$other" ]; then
  "$other" --db "host=127.0.0.1 port=$port user=garmcap dbname=scale" --listen "127.0.0.1:$oport" \
    --admin-token-sha256 "$admin" --station "shop1=$("$hub" hash-token t1)" \
    --station "shop2=$("$hub" hash-token t2)" --station "shop3=$("$hub" hash-token t3)" \
    >"$tmp/other.out" 2>"$tmp/other.err" &
  otherpid=$!
  for i in $(seq 100); do grep -qs listening "$tmp/other.out" && break; sleep 0.1; done
fi
start=$(date +%s.%N)
$psql -d scale <<SQL
INSERT INTO items(station_id, local_id, sku, title, status, type, doc)
  SELECT 'shop' || (1 + g % 3), g, 'SKU-' || g, 'Skirt ' || md5(g::text),
         CASE WHEN g % 1000 = 0 THEN 'rejected' WHEN g % 4 = 0 THEN 'approved' ELSE 'needs_review' END,
         'skirt', '{}'
  FROM generate_series(1, $items) g;
INSERT INTO measurements(item_id, name, value_cm) SELECT id, 'waist_circ', 60 + id % 30 FROM items;
INSERT INTO images(sha256, bytes, size)
  SELECT encode(sha256(('blob' || g)::bytea), 'hex'), ('blob' || g)::bytea, 8 FROM generate_series(1, 3 * $items) g;
INSERT INTO item_images(item_id, kind, sha256, media_type)
  SELECT i.id, k.kind, encode(sha256(('blob' || (3 * (i.id - 1) + k.n))::bytea), 'hex'), 'image/png'
  FROM items i CROSS JOIN (VALUES (1, 'dressed'), (2, 'cutout'), (3, 'product')) AS k(n, kind);
ANALYZE;
SQL
echo "loaded $items items, $((3 * items)) images in $(echo "$(date +%s.%N) - $start" | bc) s"
$psql -d scale -A -t -c "SELECT 'items ' || count(*) FROM items" -c "SELECT 'images ' || count(*) FROM images"
ask() {  # $1 = label, $2 = port, $3 = target: prints "label seconds"
  curl -s -o /dev/null -w "$1 %{time_total}\n" -H 'Authorization: Bearer admin-token' "http://127.0.0.1:$2$3"
}
time_requests() {  # $1 = label, stdin = targets; with a second hub, alternately B, A and A, B
  n=0
  while read -r t; do
    n=$((n + 1))
    if [ -z "$other" ]; then ask A "$hport" "$t"
    elif [ $((n % 2)) = 1 ]; then ask B "$oport" "$t"; ask A "$hport" "$t"
    else ask A "$hport" "$t"; ask B "$oport" "$t"; fi
  done | sort -k2 -n | awk -v label="$1" -v a="$hub" -v b="$other" '{ k = $1; c[k]++; t[k, c[k]] = $2 * 1000 } END {
    for (k in c) { n = c[k]; who = b == "" ? "" : " (" (k == "A" ? a : b) ")"
      printf "%s%s: %d requests, p50 %.1f ms, p99 %.1f ms, max %.1f ms\n", label, who, n, t[k, int(n * 0.5)], t[k, int(n * 0.99)], t[k, n] } }'
}
maxid=$($psql -d scale -A -t -c 'SELECT max(id) FROM items')
for i in $(seq 200); do
  after=$(( (i * 7919) % maxid + 1 ))
  echo "/api/items?limit=50&station=shop$((1 + i % 3))&after=$after"
done | time_requests "list 50 per page (station, keyset)"
for i in $(seq 200); do
  echo "/api/items?limit=50&q=$(echo "$i" | md5sum | cut -c1-4)"
done | time_requests "search 50 (trigram, 4 hex chars)"
# The review UI's status filter: a page of 24 of one station and status, from anywhere in the
# list; rejected is 1 item in 1,000 (the worst case without the status indexes of schema 3: the
# station's rows were walked newest first), approved 1 in 4.
for i in $(seq 200); do
  after=$(( (i * 7919) % maxid + 1 ))
  echo "/api/items?limit=24&station=shop$((1 + i % 3))&status=rejected&after=$after"
done | time_requests "status=rejected 24 (1 in 1,000; station, keyset)"
for i in $(seq 200); do
  after=$(( (i * 7919) % maxid + 1 ))
  echo "/api/items?limit=24&status=approved&after=$after"
done | time_requests "status=approved 24 (1 in 4; keyset)"
for i in $(seq 200); do
  after=$(( (i * 7919) % maxid + 1 ))
  echo "/api/items?limit=24&status=rejected&after=$after"
done | time_requests "status=rejected 24 (1 in 1,000; every station, keyset)"
# The plans of the status filter's list statement (HubStore::list), as the hub sends it (one
# statement with its values; PostgreSQL plans it with them), with the indexes of schema 3 and,
# when they are there, without them (dropped in a transaction that is rolled back).
after=$((maxid / 2))
explain() {  # $1 = station or '', $2 = status
  echo "EXPLAIN (ANALYZE, BUFFERS, COSTS OFF) SELECT id FROM items WHERE deleted_at IS NULL
    AND id < $after AND ('$1' = '' OR station_id = '$1') AND ('$2' = '' OR status = '$2')
    ORDER BY id DESC LIMIT 25;"
}
plans() {
  echo "--- station shop2, status rejected, after=$after"; $psql -d scale -A -t -c "$(explain shop2 rejected)"
  echo "--- every station, status rejected, after=$after"; $psql -d scale -A -t -c "$(explain '' rejected)"
}
echo "=== plans with the hub's indexes"
plans
if [ "$($psql -d scale -A -t -c "SELECT count(*) FROM pg_indexes WHERE indexname = 'items_status_id'")" = 1 ]; then
  echo "=== the same plans without the status indexes (dropped, rolled back)"
  $psql -d scale -A -t <<SQL
BEGIN;
DROP INDEX items_status_id, items_station_status_id;
$(explain shop2 rejected)
$(explain '' rejected)
ROLLBACK;
SQL
fi
