"""The suite's fixtures come from the rotorpilot-gcs pytest plugin (`autopilot`,
`autopilot_factory`, `rotorpilot_bin`, `rotorpilot`): install the package into the venv first
(`pip install -e ./gcs-scripts --no-deps`, as tests/run-all.sh does). Without --rotorpilot-bin or
ROTORPILOT_BIN the binary is this repository's release build."""
import os
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
# The clients' own examples, vendored unchanged, are run by their runners, never collected
# (DroneKit's performance_test.py matches pytest's *_test.py).
collect_ignore_glob = ["third_party/*"]
os.environ.setdefault("ROTORPILOT_BIN", str(ROOT / "target" / "release" / "rotorpilot"))


def pytest_configure(config):
    if not config.pluginmanager.has_plugin("rotorpilot"):
        raise pytest.UsageError("the rotorpilot-gcs pytest plugin is not installed: "
                                "pip install -e ./gcs-scripts --no-deps (see tests/run-all.sh)")


# Tests that keep a core busy for their whole run (unpaced simulations, sweeps and campaigns,
# plotting, package builds, PX4's suite with its own two jobs, floods): with pytest-xdist's
# `--dist loadgroup` (tests/run-all.sh) they are dealt to two groups, each run by one worker in
# turn, so at most two of them share the machine's two cores, while the other workers run the
# tests that mostly wait on flights paced in wall time.
CPU_BOUND = {
    "test_bench_peer.py", "test_campaign.py", "test_estimate_cli.py", "test_gains_cli.py", "test_gcs_package.py",
    "test_homework_study.py", "test_hostile_peers.py", "test_montecarlo_cli.py", "test_plot_run.py",
    "test_plot_sweep.py", "test_px4_suite.py", "test_sim_cli.py", "test_speed_scale.py", "test_wheel_binary.py",
}


def pytest_collection_modifyitems(config, items):
    heavy = [item for item in items if item.path.name in CPU_BOUND]
    for k, item in enumerate(heavy):
        item.add_marker(pytest.mark.xdist_group(f"cpu{k % 2}"))
