#!/bin/bash
# Times the whole `meshmorph transfer` command line on both shared pairs:
# horse -> camel (107 markers, the 10 poses) and face -> head (the cry pose),
# each under /usr/bin/time (wall, user time, peak memory).
#
# usage: tools/bench/time-transfer.sh [BIN]   (default: target/release/meshmorph)
# Needs ../shared/data beside the workspace.
set -euo pipefail
BIN=${1:-target/release/meshmorph}
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
D=$ROOT/../shared/data/dt/horse-camel
F=$ROOT/../shared/data/dt/face-head
if [ ! -d "$D" ] || [ ! -d "$F" ]; then
  echo "skipped: $ROOT/../shared/data/dt not found"
  exit 0
fi
POSES=()
for i in 01 02 03 04 05 06 07 08 09 10; do POSES+=("$D/horse-poses/horse-$i.obj"); done
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
# timed NAME ARGS...: one transfer under /usr/bin/time; its last line.
timed() {
  local name=$1
  shift
  /usr/bin/time -f "$name: wall %e s, user %U s, peak %M KiB" "$BIN" transfer "$@" \
    > /dev/null 2> "$OUT/err" || { cat "$OUT/err"; exit 1; }
  tail -n 1 "$OUT/err"
}
timed "horse -> camel" \
  --source-ref "$D/horse-poses/horse-reference.obj" \
  --target-ref "$D/camel-poses/camel-reference.obj" \
  --markers "$D/markers/horse-camel-107.cons" -o "$OUT/horse" "${POSES[@]}"
timed "face -> head  " \
  --source-ref "$F/face-poses/face-reference.obj" \
  --target-ref "$F/head-poses/head-reference.obj" \
  --markers "$F/markers/face-head.txt" -o "$OUT/face" "$F/face-poses/face-02-cry.obj"
