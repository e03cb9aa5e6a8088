"""One install for Python users: the wheel `pip` builds from gcs-scripts/ ships the `rotorpilot`
binary (setup.py's build hook runs ``cargo build --release --locked --bin rotorpilot`` in the
repository), and the package installed from it finds that binary (`find_binary`, the pytest
plugin's ``rotorpilot_bin``) with no ``$ROTORPILOT_BIN`` and no rotorpilot on PATH.

The build points CARGO_TARGET_DIR at the repository's target/, so cargo has nothing to rebuild
when the release binary is up to date (the test's time is then pip's and venv's, ≈ 30 s)."""
import os
import pathlib
import shutil
import subprocess
import sys
import sysconfig
import zipfile

import pytest

SCRIPTS = pathlib.Path(__file__).resolve().parents[1]
ROOT = SCRIPTS.parent
PLUGIN_TEST = '''
def test_the_plugin_finds_the_packaged_binary(rotorpilot_bin, rotorpilot):
    print("rotorpilot_bin:", rotorpilot_bin)
    assert rotorpilot("--version").stdout.startswith("rotorpilot ")
'''

pytestmark = pytest.mark.skipif(shutil.which("cargo") is None,
                                reason="cargo is not on PATH: the wheel's build hook builds rotorpilot with it")


def clean_env(**extra):
    """This process's environment without ROTORPILOT_BIN, PYTHONPATH or pytest's variables, PATH
    without any rotorpilot (cargo kept for the build), and `extra`."""
    env = {k: v for k, v in os.environ.items()
           if k != "ROTORPILOT_BIN" and not k.startswith(("PYTEST_", "PYTHONPATH"))}
    env["PATH"] = os.pathsep.join([str(pathlib.Path(shutil.which("cargo")).parent), "/usr/bin", "/bin"])
    return {**env, **extra}


def test_the_wheel_ships_the_binary_and_the_installed_package_runs_it(tmp_path):
    wheels = tmp_path / "wheels"
    build = subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--disable-pip-version-check",
                            "--quiet", "--wheel-dir", str(wheels), str(SCRIPTS)],
                           capture_output=True, text=True, timeout=600, check=False,
                           env=clean_env(CARGO_TARGET_DIR=str(ROOT / "target")))
    assert build.returncode == 0, build.stdout + build.stderr
    (wheel,) = wheels.glob("rotorpilot_gcs-*.whl")
    assert wheel.name.endswith(f"-py3-none-{sysconfig.get_platform().replace('-', '_').replace('.', '_')}.whl"), \
        wheel.name
    with zipfile.ZipFile(wheel) as z:
        info = z.getinfo("rotorpilot_gcs/bin/rotorpilot")
        assert info.file_size > 1_000_000 and (info.external_attr >> 16) & 0o111, "an executable binary"
        assert "rotorpilot_gcs/vehicle.py" in z.namelist()

    # A fresh venv; pymavlink and pytest come from this one's site-packages (a .pth line, after
    # the venv's own: the installed wheel is the rotorpilot_gcs it imports).
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(venv)], check=True, timeout=120)
    python = venv / "bin" / "python"
    site = subprocess.run([str(python), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
                          capture_output=True, text=True, check=True, timeout=60).stdout.strip()
    (pathlib.Path(site) / "pinned.pth").write_text(sysconfig.get_paths()["purelib"] + "\n")
    install = subprocess.run([sys.executable, "-m", "pip", "--python", str(python), "install", "--no-deps",
                              "--disable-pip-version-check", "--quiet", str(wheel)],
                             capture_output=True, text=True, timeout=300, check=False, env=clean_env())
    assert install.returncode == 0, install.stdout + install.stderr

    users = tmp_path / "user"
    users.mkdir()
    found = subprocess.run([str(python), "-I", "-c", "from rotorpilot_gcs.process import find_binary; "
                            "print(find_binary())"], capture_output=True, text=True, timeout=60, check=False,
                           cwd=users, env=clean_env())
    assert found.returncode == 0, found.stdout + found.stderr
    binary = pathlib.Path(found.stdout.strip())
    assert binary.is_relative_to(venv) and binary.parts[-3:] == ("rotorpilot_gcs", "bin", "rotorpilot"), binary
    version = subprocess.run([str(binary), "--version"], capture_output=True, text=True, timeout=30, check=False)
    assert version.returncode == 0 and version.stdout.startswith("rotorpilot "), version.stdout + version.stderr

    (users / "test_packaged.py").write_text(PLUGIN_TEST)
    run = subprocess.run([str(python), "-m", "pytest", "-p", "no:cacheprovider", "-q", "-s", "test_packaged.py"],
                         capture_output=True, text=True, timeout=120, check=False, cwd=users, env=clean_env())
    assert run.returncode == 0, run.stdout + run.stderr
    assert f"rotorpilot_bin: {binary}" in run.stdout, run.stdout
