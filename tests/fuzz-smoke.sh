#!/usr/bin/env bash
# Builds the cargo-fuzz targets of fuzz/ with the stable toolchain (the instrumentation flags
# cargo-fuzz passes with `--sanitizer none`, plus debug assertions and overflow checks) and runs
# each for FUZZ_SECONDS (default 20, two targets at a time) from the committed corpus in fuzz/corpus. New inputs go to
# a scratch directory, so the committed corpus only changes by hand. Any crash, panic, timeout
# or out-of-memory fails the run and leaves the input in fuzz/artifacts/TARGET/.
set -euo pipefail
cd "$(dirname "$0")/../fuzz"
seconds="${FUZZ_SECONDS:-20}"
target_triple="$(rustc -vV | sed -n 's/^host: //p')"
export RUSTFLAGS="-Cpasses=sancov-module -Cllvm-args=-sanitizer-coverage-level=4 \
-Cllvm-args=-sanitizer-coverage-inline-8bit-counters -Cllvm-args=-sanitizer-coverage-pc-table \
-Cllvm-args=-sanitizer-coverage-trace-compares --cfg fuzzing -Cdebug-assertions -Coverflow-checks -Dwarnings"
cargo fmt --check
cargo build --release --locked --target "$target_triple"
scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT
# Each target runs on one core: two at a time.
fuzz() {
    local target=$1 log="$scratch/$1.log" status=0
    mkdir -p "$scratch/$target" "artifacts/$target"
    "target/$target_triple/release/$target" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
        -max_len=4096 -print_final_stats=1 -artifact_prefix="artifacts/$target/" \
        "$scratch/$target" "corpus/$target" >"$log" 2>&1 || status=$?
    echo "fuzzed $target for ${seconds}s"
    grep -E '^(Done|stat::number_of_executed_units)' "$log" || true
    if [ "$status" -ne 0 ]; then
        tail -n 40 "$log" >&2
        echo "fuzz target $target failed (exit $status); input in fuzz/artifacts/$target/" >&2
        return 1
    fi
}
failed=0
for pair in "mavlink_ingest airframe_parse" "scenario_parse param_file_parse"; do
    pids=()
    for target in $pair; do
        fuzz "$target" &
        pids+=($!)
    done
    for pid in "${pids[@]}"; do
        wait "$pid" || failed=1
    done
done
exit "$failed"
