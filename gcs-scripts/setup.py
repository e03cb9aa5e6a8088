"""The build hook of rotorpilot-gcs (the rest of its metadata is in pyproject.toml): a wheel built
from a checkout ships the `rotorpilot` binary, ``rotorpilot_gcs/bin/rotorpilot``, built here by
``cargo build --release --locked --bin rotorpilot`` in the repository (the directory above this
one), so ``pip install ./gcs-scripts`` is the one install a Python user needs: the pytest plugin
and `Autopilot.start` find that binary without ``cargo install``.

``ROTORPILOT_SKIP_BINARY=1`` builds the package without the binary (it then looks for one on
PATH or in the checkout's ``target/``); an editable install (``pip install -e``) never builds it.
Cargo honours ``CARGO_TARGET_DIR`` and its other settings as usual; a tree without the Rust
sources (``../Cargo.toml``) builds the package without the binary, with a warning.
"""
from __future__ import annotations

import json
import os
import pathlib
import shutil
import subprocess
import sys

from setuptools import Distribution, setup
from setuptools.command.build_py import build_py

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent
#: Set to 1 to build the package without the binary.
SKIP_ENV = "ROTORPILOT_SKIP_BINARY"
#: Where the binary goes inside the package.
BIN_DIR = pathlib.Path("rotorpilot_gcs") / "bin"


def ships_binary() -> bool:
    """Whether the package built here ships the binary: not asked to skip it
    (``$ROTORPILOT_SKIP_BINARY``), and the Rust sources are there."""
    skipped = os.environ.get(SKIP_ENV, "").strip().lower() not in ("", "0", "false", "no")
    return not skipped and (ROOT / "Cargo.toml").is_file()


def cargo_build() -> pathlib.Path:
    """Builds the rotorpilot binary (release) in the repository; its path, as cargo reports it."""
    cargo = shutil.which(os.environ.get("CARGO", "cargo"))
    if cargo is None:
        raise SystemExit("rotorpilot-gcs: the wheel ships the rotorpilot binary, and cargo is not on PATH: install "
                         f"Rust (https://rustup.rs), or set {SKIP_ENV}=1 to build the package without it")
    command = [cargo, "build", "--release", "--locked", "--bin", "rotorpilot",
               "--message-format=json-render-diagnostics"]
    print(f"rotorpilot-gcs: {' '.join(command[1:])} in {ROOT}", file=sys.stderr, flush=True)
    done = subprocess.run(command, cwd=ROOT, stdout=subprocess.PIPE, text=True, check=False)
    if done.returncode != 0:
        raise SystemExit(f"rotorpilot-gcs: cargo build failed (status {done.returncode}); see its messages above")
    for line in done.stdout.splitlines():
        message = json.loads(line) if line.startswith("{") else {}
        if message.get("reason") == "compiler-artifact" and message.get("executable") \
                and message.get("target", {}).get("name") == "rotorpilot":
            return pathlib.Path(message["executable"])
    raise SystemExit("rotorpilot-gcs: cargo built no rotorpilot executable")


class BuildPyWithBinary(build_py):
    """build_py, then the rotorpilot binary into the built package (not for editable installs)."""

    def run(self) -> None:
        super().run()
        target = pathlib.Path(self.build_lib) / BIN_DIR / "rotorpilot"
        target.unlink(missing_ok=True)  # an earlier build's, left in build/
        if getattr(self, "editable_mode", False) or not ships_binary():
            if not (ROOT / "Cargo.toml").is_file():
                print(f"rotorpilot-gcs: warning: no {ROOT / 'Cargo.toml'} (not a rotorpilot checkout): "
                      "the package ships no rotorpilot binary", file=sys.stderr, flush=True)
            return
        binary = cargo_build()
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(binary, target)
        target.chmod(0o755)


commands: dict[str, type] = {"build_py": BuildPyWithBinary}
try:  # setuptools >= 70.1 has bdist_wheel; before, the wheel package did.
    from setuptools.command.bdist_wheel import bdist_wheel
except ImportError:  # pragma: no cover - older setuptools
    try:
        from wheel.bdist_wheel import bdist_wheel
    except ImportError:
        bdist_wheel = None


class BinaryDistribution(Distribution):
    """A distribution with a native part when it ships the binary: installed into platlib, and
    its wheel not pure."""

    def has_ext_modules(self) -> bool:
        return ships_binary()


if bdist_wheel is not None:
    class PlatformWheel(bdist_wheel):
        """The wheel's tag: for any Python 3 on this platform (py3-none-PLATFORM) when it ships
        the binary (a native program, no extension module), py3-none-any otherwise."""

        def get_tag(self) -> tuple[str, str, str]:
            python, abi, platform = super().get_tag()
            return ("py3", "none", platform) if ships_binary() else (python, abi, platform)

    commands["bdist_wheel"] = PlatformWheel

setup(cmdclass=commands, distclass=BinaryDistribution)
