#!/usr/bin/env bash
# Enforces the dependency rules of architecture.md §1 with grep: the plant never names the flight
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

pure="src/math.rs src/rpy.rs src/flight src/lockstep src/sitl.rs src/commander src/mav/codec.rs src/mav/translate.rs src/mav/identity.rs src/mav/telemetry.rs src/mav/status.rs src/mav/services.rs src/mav/duplicates.rs src/mav/streams.rs src/mav/params.rs src/mav/offboard.rs src/mav/mission_items.rs src/mav/mission_xfer.rs src/params src/telemetry.rs src/scenario src/airframe src/allocation src/control src/estimation src/navigation src/report src/montecarlo/envelope.rs src/montecarlo/authority.rs src/montecarlo/trial.rs src/montecarlo/judging.rs src/montecarlo/stats.rs src/montecarlo/report.rs firmware-sim/src"
for path in $pure; do
    [ -e "$path" ] || complain "pure-module list names a missing path" "$path"
done
hits=$(code 'std::(net|thread)|std::time::(Instant|SystemTime)|\bInstant::now|std::sync::(Mutex|RwLock)|\btokio\b' $pure)
[ -z "$hits" ] || complain "pure modules must not use clocks, sockets, threads or locks" "$hits"

exit "$fail"
