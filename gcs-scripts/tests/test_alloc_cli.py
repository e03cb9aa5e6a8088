"""`rotorpilot alloc` against an independent numpy rendering of docs/allocation.md §2, eq. (2.3)."""
import json
import math

import numpy as np
import pytest


def alloc_json(rotorpilot, airframe):
    proc = rotorpilot("alloc", "--airframe", airframe, "--json")
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout)


def test_octocopter_equals_homework_equations(rotorpilot):
    out = alloc_json(rotorpilot, "octo")
    assert out["airframe"] == "octo" and out["rotors"] == 8
    ct, cq, arm = out["c_T"], out["c_Q"], out["arm_length"]
    assert (ct, cq, arm) == (5.84e-6, 3.504e-7, 0.35)
    s1 = math.sqrt(2) * ct * arm / 2
    expected = np.array([
        [ct] * 8,
        [0, s1, ct * arm, s1, 0, -s1, -ct * arm, -s1],
        [ct * arm, s1, 0, -s1, -ct * arm, -s1, 0, s1],
        [-cq, cq, -cq, cq, -cq, cq, -cq, cq],
    ])
    g = np.array(out["G"])
    assert g.shape == (4, 8)
    np.testing.assert_allclose(g, expected, rtol=1e-12, atol=1e-12 * ct * arm)


def test_quad_x_golden(rotorpilot):
    out = alloc_json(rotorpilot, "quad_x")
    ct, cq, arm = out["c_T"], out["c_Q"], out["arm_length"]
    k = ct * arm / math.sqrt(2)
    expected = np.array([
        [ct] * 4,
        [k, k, -k, -k],     # rotors at 45°, 135°, 225°, 315° counter-clockwise seen from above
        [k, -k, -k, k],
        [-cq, cq, -cq, cq],
    ])
    np.testing.assert_allclose(np.array(out["G"]), expected, rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize("airframe,n", [("quad_plus", 4), ("hexa_x", 6), ("fsr_quad", 4)])
def test_every_preset_has_rank_four(rotorpilot, airframe, n):
    g = np.array(alloc_json(rotorpilot, airframe)["G"])
    assert g.shape == (4, n)
    assert np.linalg.matrix_rank(g / np.linalg.norm(g, axis=1, keepdims=True)) == 4


def test_table_output_names_rows(rotorpilot):
    proc = rotorpilot("alloc", "--airframe", "hexa_x")
    assert proc.returncode == 0
    assert "τz [N·m]" in proc.stdout and "rotor 6" in proc.stdout


BAD_FILES = {
    "negative_mass": ("mass = 1.5 ", "mass = -1.5 ", "vehicle.mass", "must be positive"),
    "three_rotors": ("count = 4 ", "count = 3 ", "rotors.ring.count", "fewer than 4"),
    "overlapping": ("arm = 0.25 ", "arm = 0.1 ", "rotors", "overlap"),
    "missing_ct": ("c_t = 5.84e-6 ", "", "rotors.c_t", "missing field"),
}


@pytest.mark.parametrize("case", sorted(BAD_FILES))
def test_bad_airframe_is_refused_with_file_field_and_reason(rotorpilot, tmp_path, case):
    import pathlib

    old, new, field, reason = BAD_FILES[case]
    text = (pathlib.Path(__file__).resolve().parents[2] / "airframes" / "quad_x.toml").read_text()
    assert old in text
    path = tmp_path / f"{case}.toml"
    kept = "\n".join(line for line in text.splitlines() if not line.startswith(old))
    path.write_text(text.replace(old, new, 1) if new else kept)
    proc = rotorpilot("alloc", "--airframe", str(path), "--json")
    assert proc.returncode == 2
    assert str(path) in proc.stderr and field in proc.stderr and reason in proc.stderr, proc.stderr
    assert "panicked" not in proc.stderr


def test_unknown_airframe_name_lists_presets(rotorpilot):
    proc = rotorpilot("alloc", "--airframe", "dodecacopter")
    assert proc.returncode == 2
    assert "quad_x" in proc.stderr and "octo" in proc.stderr
