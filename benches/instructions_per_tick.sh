#!/usr/bin/env bash
# Instructions per full tick (plant + estimator r = 7 + controller + allocation), counted by
# valgrind's callgrind: a figure that does not depend on how busy a shared machine is, for
# comparing two builds. Each law flies its `scenarios/<law>_quintic.toml` with a 7th-order
# estimator for 2 s and for 12 s; the difference over 10,000 ticks leaves out the start-up.
#
#   bash benches/instructions_per_tick.sh [path/to/rotorpilot]   (default: target/release/rotorpilot)
set -euo pipefail
cd "$(dirname "$0")/.."
bin="${1:-target/release/rotorpilot}"
command -v valgrind >/dev/null || { echo "valgrind is needed (apt-get install valgrind)" >&2; exit 2; }
[ -x "$bin" ] || { echo "$bin: not built (cargo build --release)" >&2; exit 2; }
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

instructions() {
    valgrind --tool=callgrind --callgrind-out-file=/dev/null "$bin" sim "$1" >/dev/null 2>"$work/err"
    sed -n 's/.*Collected : \([0-9]*\).*/\1/p' "$work/err"
}

for law in geometric hierarchical passivity; do
    for seconds in 2 12; do
        sed -e "s/^duration = 20.0/duration = $seconds.0/" -e 's/^order = 1/order = 7/' \
            "scenarios/${law}_quintic.toml" >"$work/${law}_$seconds.toml"
    done
    short=$(instructions "$work/${law}_2.toml")
    long=$(instructions "$work/${law}_12.toml")
    echo "$law: $(((long - short) / 10000)) instructions per tick"
done
