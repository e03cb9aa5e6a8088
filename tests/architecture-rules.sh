#!/usr/bin/env bash
# Enforces the dependency rules of docs/architecture.md §1 with grep: the plant never names the flight
# controller, tokio or mavlink; only src/sitl.rs names firmware_sim; only src/mav/ names mavlink;
# the plant is stepped in one place (src/lockstep/mod.rs); pure modules never name clocks,
# sockets, threads or locks.
set -euo pipefail
cd "$(dirname "$0")/.."
fail=0
complain() { echo "architecture rule broken: $1" >&2; echo "$2" >&2; fail=1; }

hits=$(grep -rnE '\b(rotorpilot|tokio|mavlink)::|^\s*use (rotorpilot|tokio|mavlink)\b' firmware-sim/src firmware-sim/benches || true)
[ -z "$hits" ] || complain "firmware-sim must not depend on the flight controller, tokio or mavlink" "$hits"
grep -qE '^\s*rotorpilot' firmware-sim/Cargo.toml && complain "firmware-sim/Cargo.toml depends on rotorpilot" ""

code() { grep -rnE "$1" "${@:2}" | grep -vE '^[^:]+:[0-9]+:\s*//' || true; }
hits=$(code 'firmware_sim' src | grep -v '^src/sitl.rs:' || true)
[ -z "$hits" ] || complain "only src/sitl.rs may name firmware_sim" "$hits"

hits=$(code '\bmavlink::' src | grep -v '^src/mav/' || true)
[ -z "$hits" ] || complain "only src/mav/ may name the mavlink crate" "$hits"

# `plant.step(` / `SimPlant::step`: the plant is stepped by the lockstep only (and wrapped by sitl.rs).
step='\bplant\s*\.\s*step\s*\(|SimPlant\s*::\s*step\b'
hits=$(code "$step" --include='*.rs' src tests benches | grep -vE '^src/(sitl|lockstep/mod)\.rs:' || true)
[ -z "$hits" ] || complain "only src/lockstep/mod.rs may step the plant (Lockstep::step)" "$hits"
n=$(code "$step" src | grep -c '^src/lockstep/mod\.rs:' || true)
[ "$n" -eq 1 ] || complain "src/lockstep/mod.rs must step the plant exactly once (Lockstep::step), found $n" ""

pure="src/math.rs src/ulog src/rpy.rs src/flight src/lockstep src/sitl.rs src/commander src/mav src/params src/telemetry.rs src/scenario src/airframe src/allocation src/control src/wrench_estimator src/nav_filter src/guidance src/report src/runners/montecarlo/envelope.rs src/runners/montecarlo/authority.rs src/runners/montecarlo/trial.rs src/runners/montecarlo/judging.rs src/runners/montecarlo/stats.rs src/runners/montecarlo/report.rs firmware-sim/src"
for path in $pure; do
    [ -e "$path" ] || complain "pure-module list names a missing path" "$path"
done
hits=$(code 'std::(net|thread)|std::time::(Instant|SystemTime)|\b(Instant|SystemTime)::now|\b(Mutex|RwLock)\b|\btokio\b' $pure)
[ -z "$hits" ] || complain "pure modules must not use clocks, sockets, threads or locks" "$hits"

# Size limits: every Rust source file; the socket layer (a file naming a socket) stays thin; the
# MAVLink fuzz target drives the shipped link machine with a small stub vehicle.
too_long() { awk -v max="$1" 'FNR == 1 && NR > 1 && n > max { print prev ": " n " lines" } { n = FNR; prev = FILENAME }
    END { if (n > max) print prev ": " n " lines" }' "${@:2}"; }
hits=$(too_long 500 $(find src firmware-sim tests benches fuzz/fuzz_targets -name '*.rs' | sort))
[ -z "$hits" ] || complain "Rust source files must stay within 500 lines" "$hits"
sockets=$(grep -rlE '\b(UdpSocket|TcpStream|TcpListener)\b' src || true)
hits=$([ -z "$sockets" ] || too_long 250 $sockets)
[ -z "$hits" ] || complain "a file that names a socket must stay within 250 lines (protocol belongs in src/mav/link)" "$hits"
hits=$(too_long 150 fuzz/fuzz_targets/mavlink_ingest.rs)
[ -z "$hits" ] || complain "the MAVLink fuzz target must stay within 150 lines (drive mav::link::LinkMachine)" "$hits"
hits=$(grep -L 'LinkMachine' fuzz/fuzz_targets/mavlink_ingest.rs || true)
[ -z "$hits" ] || complain "the MAVLink fuzz target must drive the shipped LinkMachine" "$hits"

# One name per idea: no type is defined twice in src/ (test files aside).
hits=$(find src -name '*.rs' ! -name '*_tests.rs' ! -name 'tests.rs' ! -path '*/tests/*' -print0 \
    | xargs -0 grep -hoE '^(pub(\([a-z]+\))? )?(struct|enum|trait|type) [A-Z][A-Za-z0-9]*' | awk '{print $NF}' | sort | uniq -d)
[ -z "$hits" ] || complain "a type name is defined twice in src/" "$hits"

# Types own their state (docs/architecture.md §1): one type's inherent `impl` blocks sit in at most
# three files (its definition, and at most two more), test files aside; a concern that needs more
# is its own type.
hits=$(find src -name '*.rs' ! -name '*_tests.rs' ! -name 'tests.rs' ! -path '*/tests/*' -print0 \
    | xargs -0 grep -HoE '^impl(<[^>]*>)? [A-Z][A-Za-z0-9]*(<[^>]*>)? *\{' \
    | sed -E 's/^([^:]+):impl(<[^>]*>)? ([A-Za-z0-9]+).*/\3 \1/' | sort -u \
    | awk '{ n[$1]++; f[$1] = f[$1] " " $2 } END { for (t in n) if (n[t] > 3) print t ":" f[t] }')
[ -z "$hits" ] || complain "a type's impl is spread over more than three files" "$hits"

# Parameters are declared once, as rows (src/params/rows/): nothing names them by position.
hits=$(code 'PARAM_NAMES' --include='*.rs' src tests benches fuzz/fuzz_targets; code '\b(v|values)\[[0-9]+' src/params src/mav/param_encoding.rs)
[ -z "$hits" ] || complain "parameters are read and written through their rows, never by index" "$hits"

# Documentation (docs/README.md §4): nothing points outside the repository; every docs/ citation
# names an existing note, section heading and equation; no old-style or homework-numbered
# citation is left. tests/docs_citations.py prints file:line of every problem.
if ! python3 tests/docs_citations.py; then
    complain "documentation citations are broken (see the file:line list above)" ""
fi

exit "$fail"
