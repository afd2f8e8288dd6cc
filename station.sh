#!/usr/bin/env bash
# GarmCap Station: install dependencies, build, run the station on the simulated rig, run tests.
#
#   ./station.sh run     install + build + start the station on the simulated rig
#   ./station.sh test    install + build + run every test (ctest --output-on-failure)
#   ./station.sh deps    install the Debian packages only (apt-get; idempotent)
#   ./station.sh build   configure and build into build/ (Release, -Wall -Wextra -Werror)
#   ./station.sh asan    build into build-asan/ with ASan+UBSan and run every test
#   ./station.sh fuzz    build the libFuzzer targets (tests/fuzz, clang) and run each FUZZ_SECONDS (60)
#   ./station.sh physrig OUT [ARGS]  install Blender (not in PACKAGES: CI never needs it), build,
#                        render a physical rig into OUT and calibrate it (docs/physical_rig.md)
#
# Environment: JOBS (parallel build jobs, default: nproc), GARMCAP_PORT (default 8080),
# GARMCAP_DATA (station data folder for `run`, default ./station-data).
set -euo pipefail
cd "$(dirname "$0")"
ROOT=$PWD
JOBS=${JOBS:-$(nproc)}

# Debian bookworm packages, grouped by what needs them.
PACKAGES=(
  # toolchain
  build-essential cmake ninja-build pkg-config git clang-format
  # drafts, core: geometry, JSON, CLI, logging
  libeigen3-dev nlohmann-json3-dev libcli11-dev libspdlog-dev
  # drafts: markers nested by libnest2d (header-only; its clipper backend and NLopt optimizers)
  libnest2d-dev libpolyclipping-dev libnlopt-cxx-dev
  # calib, core/garmcap: images (libwebp: the WebP copies at a chosen encoder method)
  libopencv-dev libwebp-dev
  # capture: cameras and GPIO
  libcamera-dev libgpiod-dev gpiod
  # daemon: service, catalog, config, systemd
  libboost-dev libsqlite3-dev sqlite3 libtoml11-dev libsystemd-dev systemd nettle-dev libzbar-dev
  # daemon: the ZIP writer's CRC-32 (catalog.zip, streamed at the hub)
  zlib1g-dev
  # hub (daemon/hub): the chain's catalog on PostgreSQL; its tests run a throwaway server
  postgresql-15 libpqxx-dev
  # hub and station pusher: TLS (Boost.Asio's SSL stream on OpenSSL 3); tests make throwaway
  # certificates with the openssl command
  libssl-dev openssl
  # tests: unit tests, benchmarks, CGAL peer check, SVG and PDF rendering checks, XML 1.0
  # well-formedness check of escaped text
  libgtest-dev libgmock-dev libbenchmark-dev libcgal-dev librsvg2-bin poppler-utils libxml2-utils
  # pattern DXF audited and measured by an independent reader (tests/drafts/dxf_ezdxf_check.py)
  python3-ezdxf
  # libFuzzer targets (tests/fuzz, ./station.sh fuzz): clang and its sanitizer/fuzzer runtime
  clang libclang-rt-14-dev
  # web UI browser test (headless chromium), Valentina .vit interop test, ZIP check (unzip -t
  # reads the station's and the hub's catalog.zip and the Zip64 archives of zip_writer_test)
  chromium valentina unzip
  # the WebP product photo decoded by libwebp's own dwebp (tests/e2e/export_http_test.cpp)
  webp
)

# Only for `physrig`: Blender 3.4 (cloth solver and Cycles) with numpy for its Python.
PHYSRIG_PACKAGES=(blender python3-numpy)

physrig() {  # $1 = output rig folder, rest = make_rig.py arguments (default: the committed rig)
  local out=${1:?usage: ./station.sh physrig OUT [--count N --seed S ...]}; shift
  local station_packages=("${PACKAGES[@]}")
  PACKAGES=("${PHYSRIG_PACKAGES[@]}")
  deps
  PACKAGES=("${station_packages[@]}")
  build
  local args=("$@")
  [ ${#args[@]} -gt 0 ] || args=(--count 24 --seed 2026)
  nice -n 10 blender -b -t 2 --python capture/sim/physical/make_rig.py -- --out "$out" "${args[@]}"
  /usr/bin/python3 capture/sim/physical/calibrate_rig.py "$out" --garmcap build/bin/garmcap
}

as_root() {
  if [ "$(id -u)" = 0 ]; then "$@"; elif command -v sudo >/dev/null; then sudo "$@"; else
    echo "station.sh: need root (or sudo) to install packages: $*" >&2; exit 1; fi
}

deps() {
  local missing=()
  for p in "${PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if [ ${#missing[@]} -eq 0 ]; then
    echo "station.sh: all ${#PACKAGES[@]} packages already installed"
    return
  fi
  echo "station.sh: installing ${missing[*]}"
  as_root apt-get update -q
  as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${missing[@]}"
}

configure_and_build() {  # $1 = build dir, rest = extra cmake args
  local dir=$1; shift
  cmake -S "$ROOT" -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DGARMCAP_WERROR=ON "$@"
  cmake --build "$dir" -j "$JOBS"
}

build() { configure_and_build "$ROOT/build"; }

run_tests() {  # $1 = build dir; GARMCAP_CTEST_ARGS adds ctest arguments (e.g. "-L unit")
  # shellcheck disable=SC2086
  (cd "$1" && ctest --output-on-failure -j "$JOBS" --timeout 600 ${GARMCAP_CTEST_ARGS:-})
}

run_station() {
  local port=${GARMCAP_PORT:-8080}
  local data=${GARMCAP_DATA:-$ROOT/station-data}
  if [ -x build/bin/garmcapd ]; then
    echo "GarmCap Station: http://127.0.0.1:$port/  (catalog in $data; Ctrl-C to stop)"
    exec build/bin/garmcapd --simulated --data "$data" --listen "127.0.0.1:$port"
  fi
  # Until the daemon exists: draft every garment type at size 55 and write SVGs.
  mkdir -p "$data/demo"
  local types
  types=$(build/bin/garmcap draft --list | python3 -c 'import json,sys; print(" ".join(t["name"] for t in json.load(sys.stdin)["types"]))')
  for t in $types; do
    build/bin/garmcap draft --type "$t" --size 55 --chart korean_women \
      --out "$data/demo/$t.json" --svg "$data/demo/$t.svg"
    echo "drafted $t -> $data/demo/$t.svg"
  done
}

# libFuzzer targets (tests/fuzz/, built with clang into build-fuzz/), each run for FUZZ_SECONDS
# (60 by default) from its seed corpus; a crash or sanitizer finding fails the run and leaves the
# input in build-fuzz/ (crash-*). FUZZ_RUNS=N runs N executions instead. An input that runs
# longer than 10 s (a hang) or takes 2 GB is a finding too.
fuzz() {
  cmake -S "$ROOT/tests/fuzz" -B "$ROOT/build-fuzz" -G Ninja -DCMAKE_CXX_COMPILER=clang++ \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo
  cmake --build "$ROOT/build-fuzz" -j"$(nproc)"
  local entry name seeds corpus limit failed=0
  local -a names=()
  # target:seed folder under tests/fuzz/corpus
  for entry in http_request:http pattern_json:pattern config_toml:toml measurements:measurements \
    calibration_json:calibration mesh:mesh; do
    name=${entry%%:*} seeds="$ROOT/tests/fuzz/corpus/${entry#*:}"
    corpus="$ROOT/build-fuzz/corpus/$name"
    mkdir -p "$corpus"
    [ -d "$seeds" ] || { echo "fuzz: no seed folder $seeds" >&2; return 1; }
    cp "$seeds/"* "$corpus/"
    names+=("$name")
  done
  if [ -n "${FUZZ_RUNS:-}" ]; then limit="-runs=$FUZZ_RUNS"; else limit="-max_total_time=${FUZZ_SECONDS:-60}"; fi
  # The targets run side by side, JOBS at a time (each is one process on one core); each one's
  # output is kept in build-fuzz/fuzz_<name>.log and its summary printed in the list's order.
  run_one() {
    (cd "$ROOT/build-fuzz" && "./fuzz_$1" "$limit" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
      -print_final_stats=1 "corpus/$1" > "fuzz_$1.log" 2>&1)
  }
  local -A pid=()
  local running=0
  for name in "${names[@]}"; do
    if [ "$running" -ge "$JOBS" ]; then wait -n || true; running=$((running - 1)); fi
    run_one "$name" & pid[$name]=$!
    running=$((running + 1))
  done
  for name in "${names[@]}"; do
    local rc=0
    wait "${pid[$name]}" || rc=$?
    echo "fuzz: $name ($limit)"
    grep -E "^(Done|stat::number_of_executed_units|stat::peak_rss_mb|==[0-9]+==ERROR|SUMMARY)" \
      "$ROOT/build-fuzz/fuzz_$name.log" || true
    if [ "$rc" -ne 0 ]; then
      echo "fuzz: $name FAILED (exit $rc); its output: build-fuzz/fuzz_$name.log" >&2
      tail -n 40 "$ROOT/build-fuzz/fuzz_$name.log" >&2
      failed=1
    fi
  done
  return "$failed"
}

case "${1:-}" in
  deps) deps ;;
  build) deps; build ;;
  test) deps; build; run_tests "$ROOT/build" ;;
  asan) deps; configure_and_build "$ROOT/build-asan" -DGARMCAP_SANITIZE=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo
        ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 run_tests "$ROOT/build-asan" ;;
  fuzz) deps; fuzz ;;
  run) deps; build; run_station ;;
  physrig) shift; deps; physrig "$@" ;;
  *) sed -n '2,14p' "$0"; exit 2 ;;
esac
