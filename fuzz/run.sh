#!/usr/bin/env bash
# Runs every fuzz target (or the ones named) for SECONDS each, one after the
# other, with the seeds in corpus/TARGET, and prints each target's run count.
# Needs a nightly toolchain and cargo-fuzz (`cargo install cargo-fuzz --locked`).
#
#   fuzz/run.sh 600                 # every target, 10 minutes each
#   fuzz/run.sh 60 obj ply          # two targets, a minute each
#
# New inputs found are kept in corpus/TARGET (delete what you do not want to
# commit), crashes in artifacts/TARGET.
set -euo pipefail
cd "$(dirname "$0")"
seconds="${1:?usage: fuzz/run.sh SECONDS [TARGET...]}"
shift
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
    targets=(obj off ply markers correspondence interpolate transfer surface)
fi
# The library is safe Rust: no sanitizer needed, and the runs are faster.
cargo +nightly fuzz build -s none
for t in "${targets[@]}"; do
    mkdir -p "corpus/$t" "artifacts/$t"
    log="artifacts/$t/last-run.log"
    status=0
    cargo +nightly fuzz run -s none "$t" "corpus/$t" -- \
        -max_total_time="$seconds" -max_len=4096 -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
        >"$log" 2>&1 || status=$?
    runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || true)
    echo "$t: ${runs:-?} runs in ${seconds} s, exit ${status} (log: fuzz/$log)"
done
