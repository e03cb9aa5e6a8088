"""Shared fixtures: the rotorpilot binary under test."""
import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def rotorpilot_bin():
    """The release binary under test (`ROTORPILOT_BIN` or target/release); fails when missing."""
    binary = pathlib.Path(os.environ.get("ROTORPILOT_BIN", ROOT / "target" / "release" / "rotorpilot"))
    if not binary.exists():
        pytest.fail(f"rotorpilot binary not found at {binary}: run cargo build --release first")
    return binary


@pytest.fixture(scope="session")
def rotorpilot(rotorpilot_bin):
    """Returns a function that runs the release binary and returns the CompletedProcess."""
    binary = rotorpilot_bin

    def run(*args, timeout=120):
        return subprocess.run([str(binary), *args], capture_output=True, text=True, timeout=timeout, check=False)

    return run
