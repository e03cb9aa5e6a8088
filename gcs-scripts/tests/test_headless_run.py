"""`rotorpilot fly` (docs/cli.md §2): a headless take-off and hover."""
import csv
import json


def test_take_off_and_hover_at_two_metres(rotorpilot, tmp_path):
    log = tmp_path / "run.csv"
    proc = rotorpilot("fly", "--airframe", "octo", "--duration", "8", "--altitude", "2", "--out", str(log))
    assert proc.returncode == 0, proc.stderr
    summary = json.loads(proc.stdout)
    assert summary["airframe"] == "octo" and summary["rotors"] == 8
    assert summary["ticks"] == 8000 and not summary["on_ground"]
    # Rests at −gear_height (0.12 m) and climbs 2 m.
    assert abs(summary["final_position_m"][2] + 2.12) < 0.01
    assert abs(summary["final_rotor_speed_rad_s"] - summary["hover_speed_rad_s"]) < 1.0
    assert summary["saturated_time_s"] == 0.0
    with log.open() as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 8000
    assert {"t", "z", "z_ref", "thrust", "omega_8"} <= set(rows[0])
    assert float(rows[-1]["z_ref"]) == -2.12


def test_bad_option_is_refused(rotorpilot):
    proc = rotorpilot("fly", "--duration", "-1")
    assert proc.returncode == 2
    assert "--duration" in proc.stderr
