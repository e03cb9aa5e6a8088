#!/usr/bin/env bash
# Runs every test of rotorpilot on a fresh machine: formatting, lints (Rust and Python), Python types, architecture rules,
# Rust unit/integration/doc tests (release build, reused by the Python tests), a bounded run of
# every fuzz target from the committed corpus, the README's set-up lines on a fresh clone, and the pytest
# suite in a venv with the pinned gcs-scripts/requirements.txt. Exits non-zero on any failure,
# including a pytest run that collects no test.
set -euo pipefail
cd "$(dirname "$0")/.."

# The Python venv is installed in the background while cargo builds and tests (pip waits on the
# network more than on the cores); its log is shown if it fails, before the Python tests need it.
venv=".venv"
pip_log=$(mktemp)
pip_pid=
trap 'if [ -n "$pip_pid" ]; then kill "$pip_pid" 2>/dev/null || true; fi; rm -f "$pip_log"' EXIT
(
    if [ ! -x "$venv/bin/python" ]; then
        python3 -m venv "$venv"
    fi
    "$venv/bin/pip" install --quiet --disable-pip-version-check -r gcs-scripts/requirements.txt
    "$venv/bin/pip" install --quiet --disable-pip-version-check --no-deps -r gcs-scripts/requirements-nodeps.txt
    # The package itself (rotorpilot_gcs, editable: its pins are requirements.txt's), whose pytest
    # plugin provides the suite's fixtures.
    "$venv/bin/pip" install --quiet --disable-pip-version-check --no-deps -e ./gcs-scripts
) >"$pip_log" 2>&1 &
pip_pid=$!

echo "== format and lints"
cargo fmt --all -- --check
cargo clippy --workspace --all-targets --release -- -D warnings

echo "== architecture rules (docs/architecture.md §1)"
bash tests/architecture-rules.sh

echo "== Rust tests"
cargo build --release --bin rotorpilot
cargo test --workspace --release

echo "== fuzz smoke run (docs/fuzzing.md)"
bash tests/fuzz-smoke.sh

echo "== Python tests"
if ! wait "$pip_pid"; then
    cat "$pip_log" >&2
    echo "installing the Python venv ($venv) failed" >&2
    exit 1
fi
pip_pid=
cat "$pip_log"
export ROTORPILOT_BIN="$PWD/target/release/rotorpilot"

echo "== Python lints and types (ruff; mypy --strict on rotorpilot_gcs)"
"$venv/bin/ruff" check gcs-scripts
(cd gcs-scripts && "../$venv/bin/mypy")

echo "== the README's set-up lines on a fresh clone"
bash tests/readme-setup.sh

echo "== pytest"
# Three workers (pytest-xdist): most tests wait on flights paced in wall time and leave the
# cores idle; those that keep a core busy are dealt to two groups of their own (`--dist
# loadgroup`, gcs-scripts/tests/conftest.py), so no more than two of them run at once. MAVSDK's and
# DroneKit's examples run afterwards on their own: they fly several vehicles at once and need the
# CPU to keep time. (--ignore takes a path: node ids are relative to pytest's rootdir, gcs-scripts/ with its
# pyproject.toml.)
examples="gcs-scripts/tests/test_mavsdk_examples.py gcs-scripts/tests/test_dronekit_examples.py"
status=0
for run in "-n 3 --dist loadgroup gcs-scripts/tests ${examples//gcs-scripts/--ignore=gcs-scripts}" "$examples"; do
    code=0
    # shellcheck disable=SC2086
    "$venv/bin/python" -m pytest -q --durations=15 $run || code=$?
    if [ "$code" -eq 5 ]; then
        echo "pytest collected no tests ($run): failing" >&2
        exit 1
    fi
    if [ "$code" -ne 0 ]; then
        status=$code
    fi
done
exit "$status"
