#!/usr/bin/env bash
# The README's set-up lines, as a newcomer runs them, on a fresh clone of this checkout: the
# commands are read from the README's set-up blocks (each ```sh block right after a
# `<!-- setup -->` line), so the README cannot drift from what works. Each is bounded in time; the clone
# shares this checkout's build directory so nothing but the workspace crates is compiled again.
#
#   cargo run --release -- run ...   must print its ready line (run with --duration 3, in its own
#                                    network namespace when unshare is allowed: its ports are fixed)
#   cargo install --path . --locked  must install a working `rotorpilot` (into a scratch root)
#   the Python one-liner             must give a venv whose Python imports the ground-station
#                                    library and runs plot_run.py --help
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
scratch=$(mktemp -d)
# The clone's build replaces target/release/rotorpilot with the committed sources' binary (cargo
# uplifts it to the same path); this checkout's own binary, which the tests after this use, is put
# back on exit.
binary="$root/target/release/rotorpilot"
restore() {
    if [ -f "$scratch/rotorpilot.checkout" ]; then rm -f "$binary" && cp -p "$scratch/rotorpilot.checkout" "$binary"; fi
    rm -rf "$scratch"
}
trap restore EXIT
if [ -f "$binary" ]; then cp -p "$binary" "$scratch/rotorpilot.checkout"; fi
block=$(awk '/<!-- setup -->/{want=1; next} want && /^```sh/{inside=1; want=0; next} inside && /^```/{inside=0; next} inside' README.md)
[ -n "$block" ] || { echo "README: no set-up block after <!-- setup -->" >&2; exit 1; }
line() { printf '%s\n' "$block" | grep -m1 -- "$1" | sed 's/[[:space:]]*#.*$//'; }
run_line=$(line 'cargo run --release -- run')
install_line=$(line 'cargo install')
python_line=$(line 'python3 -m venv')
for l in "$run_line" "$install_line" "$python_line"; do
    [ -n "$l" ] || { echo "README set-up block lacks a line: $block" >&2; exit 1; }
done

git clone -q "$root" "$scratch/clone"
cd "$scratch/clone"
export CARGO_TARGET_DIR="$root/target"

echo "== $run_line"
netns=()
if unshare -n true 2>/dev/null; then netns=(unshare -n); fi
ready=$(timeout 900 "${netns[@]}" bash -c "$run_line --duration 3" | head -n 1)
case "$ready" in
    *'"event":"ready"'*) echo "ready: $ready" ;;
    *) echo "the autopilot did not print its ready line: $ready" >&2; exit 1 ;;
esac

echo "== $install_line"
timeout 900 bash -c "$install_line --root '$scratch/root'"
"$scratch/root/bin/rotorpilot" --version

echo "== $python_line"
timeout 900 bash -c "$python_line"
.venv/bin/python -c "import rotorpilot_gcs; print('rotorpilot_gcs', rotorpilot_gcs.__version__)"
.venv/bin/python gcs-scripts/plot_run.py --help > /dev/null
echo "README set-up: ok"
