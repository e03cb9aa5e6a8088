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
