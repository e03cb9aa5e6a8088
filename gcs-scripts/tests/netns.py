"""Whether the tests may give a client its own loopback (`unshare -n`, root): MAVSDK's examples and
MAVProxy bind fixed ports, which clash when several run at once."""
import shutil
import subprocess


def can_unshare():
    """True when `unshare -n` works here."""
    return bool(shutil.which("unshare")) and subprocess.run(["unshare", "-n", "true"], check=False).returncode == 0
