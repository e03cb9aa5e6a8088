"""`rotorpilot gains` against the golden values of docs/estimator.md §3.3 and an independent
numpy design."""
import json
import math

import numpy as np
import pytest

R7_DENOMINATOR = [1, 1.1368401966214219, 7.646202816327117, 6.651529192122977, 16.82951700040185,
                  9.600533199327506, 9.353792060928335, 2.0047545860152005]
R7_GAINS = [0.214325331689727, 0.9742992255454671, 0.5704580350760077, 2.5301726135896807,
            0.8699127334053722, 6.725837843393368, 1.1368401966214219]


def gains_json(rotorpilot, *args):
    proc = rotorpilot("gains", *args, "--json")
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout)


def test_order_seven_matches_reference_table(rotorpilot):
    out = gains_json(rotorpilot, "--order", "7", "--ripple-db", "3", "--wp", "2")
    assert out["order"] == 7 and out["stable"] is True
    np.testing.assert_allclose(out["a"], R7_DENOMINATOR, rtol=1e-9)
    np.testing.assert_allclose(out["K"], R7_GAINS, rtol=1e-9)
    # Slowest pole of docs/estimator.md §3.3: −0.0563 ± 1.965j.
    slowest = max(out["poles"], key=lambda p: p[0])
    assert abs(slowest[0] + 0.0563) < 1e-4 and abs(abs(slowest[1]) - 1.965) < 1e-3


def test_order_one_is_wp_over_epsilon(rotorpilot):
    out = gains_json(rotorpilot, "--order", "1", "--ripple-db", "3", "--wp", "2")
    assert out["K"] == pytest.approx([2.004754586015201], rel=1e-12)


@pytest.mark.parametrize("order,ripple,wp", [(2, 1.0, 5.0), (4, 0.5, 3.0), (5, 3.0, 10.0)])
def test_gains_agree_with_an_independent_pole_expansion(rotorpilot, order, ripple, wp):
    eps = math.sqrt(10 ** (ripple / 10) - 1)
    v = math.asinh(1 / eps) / order
    poles = [wp * complex(-math.sinh(v) * math.sin((2 * k - 1) * math.pi / (2 * order)),
                          math.cosh(v) * math.cos((2 * k - 1) * math.pi / (2 * order))) for k in range(1, order + 1)]
    a = np.real(np.poly(poles))
    out = gains_json(rotorpilot, "--order", str(order), "--ripple-db", str(ripple), "--wp", str(wp))
    np.testing.assert_allclose(out["a"], a, rtol=1e-9)
    ascending = a[::-1]
    np.testing.assert_allclose(out["K"], [ascending[i - 1] / ascending[i] for i in range(1, order + 1)], rtol=1e-9)
    assert len(out["poles"]) == order


def test_unstable_design_is_reported_with_the_largest_stable_edge(rotorpilot):
    out = gains_json(rotorpilot, "--order", "13", "--ripple-db", "3", "--wp", "20")
    assert out["stable"] is False
    assert out["max_stable_wp"] == pytest.approx(16.5, abs=0.1)


def test_bad_design_is_an_error(rotorpilot):
    proc = rotorpilot("gains", "--order", "0", "--ripple-db", "3", "--wp", "2", "--json")
    assert proc.returncode != 0
    assert "order" in proc.stderr
