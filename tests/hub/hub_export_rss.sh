#!/bin/sh
# The memory the chain's exports take at the hub, by hand (not in ctest): a throwaway PostgreSQL,
# a garmcap-hub, ITEMS approved items of 3 stations (a product JPEG each, measurements, a size-
# guide-free item JSON, the base pattern of tests/data/designs/dress_55.json) loaded in SQL, then
# FILES (default: shopify.csv woocommerce.csv merchant.tsv catalog.zip) fetched one after the
# other; prints the hub's resident memory (VmRSS) before, and its peak (VmHWM) after each file,
# with the file's size and time; catalog.zip is then read by Python's zipfile (every CRC) and
# `unzip -t`. Run it at two sizes to see whether the peak grows with the item count (FILES with
# one file alone to see that file's peak).
# PATTERNS=0 leaves the patterns out (catalog.zip then holds photos and shop files: about 200 KB
# less per item).
#   [PATTERNS=0] tests/hub/hub_export_rss.sh build/bin/garmcap-hub [ITEMS [FILES]]
set -eu
hub=$(readlink -f "$1"); items=${2:-10000}
files=${3:-shopify.csv woocommerce.csv merchant.tsv catalog.zip}
pattern=$(dirname "$(readlink -f "$0")")/../data/designs/dress_55.json
bin=$(ls -d /usr/lib/postgresql/*/bin | sort | tail -1)
tmp=$(mktemp -d); chmod 755 "$tmp"
run() { if [ "$(id -u)" = 0 ]; then runuser -u nobody -- sh -c "$1"; else sh -c "$1"; fi; }
[ "$(id -u)" = 0 ] && chown nobody "$tmp"
port=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])')
hport=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])')
cleanup() { kill $hubpid 2>/dev/null || true; run "$bin/pg_ctl -D $tmp/data -m immediate stop" >/dev/null 2>&1 || true; rm -rf "$tmp"; }
hubpid=
trap cleanup EXIT
run "$bin/initdb -D $tmp/data -U garmcap --auth=trust -E UTF8 --no-locale --no-sync" >/dev/null
run "$bin/pg_ctl -D $tmp/data -l $tmp/log -o '-p $port -k $tmp -c listen_addresses=127.0.0.1' -w start" >/dev/null
psql="$bin/psql -X -q -h 127.0.0.1 -p $port -U garmcap"
$psql -d postgres -c 'CREATE DATABASE rss'
"$hub" --db "host=127.0.0.1 port=$port user=garmcap dbname=rss" --listen "127.0.0.1:$hport" \
  --admin-token-sha256 "$("$hub" hash-token admin-token)" --station "shop1=$("$hub" hash-token t1)" \
  --station "shop2=$("$hub" hash-token t2)" --station "shop3=$("$hub" hash-token t3)" \
  >"$tmp/hub.out" 2>"$tmp/hub.err" &
hubpid=$!
for i in $(seq 100); do grep -qs listening "$tmp/hub.out" && break; sleep 0.1; done
$psql -d rss -v pattern="$(cat "$pattern")" <<SQL
INSERT INTO items(station_id, local_id, sku, title, price_cents, status, type, hub_owned, doc)
  SELECT 'shop' || (1 + g % 3), g, 'SKU-' || g, 'Skirt ' || md5(g::text), 1000 + g % 5000,
         'approved', 'skirt', true,
         jsonb_build_object('notes', 'Lined, ' || md5((g + 1)::text), 'base_size', '38',
                            'tags', jsonb_build_array('skirt', 'chain'),
                            'attributes', jsonb_build_object('color', 'navy'))
  FROM generate_series(1, $items) g;
INSERT INTO measurements(item_id, name, value_cm)
  SELECT id, n, 50 + id % 40 FROM items CROSS JOIN (VALUES ('waist_circ'), ('hip_circ'),
    ('garment_length')) AS m(n);
INSERT INTO images(sha256, bytes, size)
  SELECT encode(sha256(('jpeg' || g)::bytea), 'hex'), ('jpeg' || g)::bytea, 8 FROM generate_series(1, $items) g;
INSERT INTO item_images(item_id, kind, sha256, media_type)
  SELECT i.id, 'product', encode(sha256(('jpeg' || i.local_id)::bytea), 'hex'), 'image/jpeg' FROM items i;
INSERT INTO item_patterns(item_id, size, pattern) SELECT id, 'base', :'pattern'::jsonb FROM items
  WHERE ${PATTERNS:-1} = 1;
ANALYZE;
SQL
kb() { awk -v k="$1:" '$1 == k { print $2 }' "/proc/$hubpid/status"; }
echo "$items approved items; hub VmRSS before the exports: $(kb VmRSS) kB"
for f in $files; do
  curl -s -o "$tmp/$f" -w "$f: HTTP %{http_code}, %{size_download} bytes, %{time_total} s" \
    -H 'Authorization: Bearer admin-token' \
    "http://127.0.0.1:$hport/api/export/$f?base_url=https://files.example&store_url=https://shop.example&brand=Chain"
  echo "; hub VmHWM (peak) $(kb VmHWM) kB, VmRSS $(kb VmRSS) kB"
  if [ "$f" = catalog.zip ]; then
    python3 -c 'import sys, zipfile; z = zipfile.ZipFile(sys.argv[1]); assert z.testzip() is None
print("catalog.zip: %d entries, every CRC right (Python zipfile)" % len(z.namelist()))' "$tmp/$f"
    unzip -tq "$tmp/$f"
  fi
done
