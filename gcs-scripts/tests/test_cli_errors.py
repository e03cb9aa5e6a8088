"""What a newcomer sees when something is wrong: errors name the file or value at fault with no
placeholder, mistyped names get a "did you mean", and stderr has colours only on a terminal
(never with NO_COLOR)."""
import os
import pty
import subprocess

import pytest


@pytest.mark.parametrize("args,expected", [
    (["fly", "--airframe", "quadx"], "quadx: no preset of that name and no such file; did you mean quad_x?"),
    (["fly", "--controller", "geometirc"], 'unknown controller "geometirc"; did you mean geometric?'),
    (["sim", "/nonexistent/x.toml"], "/nonexistent/x.toml: cannot read the file"),
    (["run", "--home", "47.4,8.5,20000", "--duration", "0.1"],
     '--home "47.4,8.5,20000": expected LAT,LON,ALT with |LAT| ≤ 90, |LON| ≤ 180 and ALT in [-500, 11000] m'),
])
def test_errors_name_what_is_wrong_and_suggest(rotorpilot, args, expected):
    proc = rotorpilot(*args)
    assert proc.returncode != 0
    assert expected in proc.stderr, proc.stderr
    assert "(name)" not in proc.stderr and "(file)" not in proc.stderr


def test_a_mistyped_parameter_in_a_params_file_gets_a_suggestion(rotorpilot, tmp_path):
    params = tmp_path / "my.params"
    params.write_text("MPC_XY_VEL_MX 3\n")
    proc = rotorpilot("run", "--params", str(params), "--bind-gcs", "127.0.0.1:0", "--bind-api", "127.0.0.1:0",
                      "--duration", "1")
    assert proc.returncode != 0
    assert f"{params}:1: MPC_XY_VEL_MX: no such parameter; did you mean MPC_XY_VEL_MAX?" in proc.stderr


RUN = ["run", "--bind-gcs", "127.0.0.1:0", "--bind-api", "127.0.0.1:0", "--gcs", "127.0.0.1:9", "--api",
       "127.0.0.1:9", "--duration", "0.3"]


def on_a_terminal(binary, env):
    """stdout+stderr of `rotorpilot run` on a pseudo-terminal."""
    leader, follower = pty.openpty()
    proc = subprocess.Popen([str(binary), *RUN], stdout=follower, stderr=follower, env=env)
    os.close(follower)
    out = b""
    while True:
        try:
            chunk = os.read(leader, 4096)
        except OSError:
            break
        if not chunk:
            break
        out += chunk
    proc.wait(timeout=10)
    os.close(leader)
    return out.decode(errors="replace")


def test_colours_only_on_a_terminal_and_never_with_no_color(rotorpilot, rotorpilot_bin):
    redirected = rotorpilot(*RUN)
    assert redirected.returncode == 0 and "stopped after" in redirected.stderr
    assert "\x1b[" not in redirected.stderr, "no escape codes in a file or pipe"
    env = {k: v for k, v in os.environ.items() if k != "NO_COLOR"}
    assert "\x1b[" in on_a_terminal(rotorpilot_bin, env)
    assert "\x1b[" not in on_a_terminal(rotorpilot_bin, {**env, "NO_COLOR": "1"})


def test_live_wrench_plot_without_matplotlib_stops_before_flying():
    """`--plot` without matplotlib is refused at once, before any data is gathered (it used to
    listen for the whole flight and then crash, losing the data)."""
    import pathlib
    import sys

    script = pathlib.Path(__file__).resolve().parents[1] / "live_wrench.py"
    hide = ("import runpy, sys; sys.modules['matplotlib'] = None; "
            f"sys.argv = [{str(script)!r}, '--plot', 'x.png', '--connection', 'udpin:127.0.0.1:0']; "
            f"sys.path.insert(0, {str(script.parent)!r}); runpy.run_path({str(script)!r}, run_name='__main__')")
    proc = subprocess.run([sys.executable, "-c", hide], capture_output=True, text=True, timeout=30, check=False)
    assert proc.returncode == 2 and "--plot needs matplotlib" in proc.stderr, proc.stderr


def test_a_mistyped_scenario_key_names_its_line_and_the_key_meant(rotorpilot, tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('name = "x"\nduraton = 3.0\n[airframe]\npreset = "quad_x"\n[trajectory]\nkind = "hover"\n'
                   'position = [0.0, 0.0, 0.0]\n')
    proc = rotorpilot("sim", str(bad))
    assert proc.returncode != 0
    assert f"{bad}: line 2: unknown field `duraton`" in proc.stderr and "did you mean duration?" in proc.stderr
