"""The yaw checks of `tlog_judge.py`: what a ground station saw of the heading in each offboard
phase of an example, read back from the tlog.

Per offboard phase: the heading rate ATTITUDE shows (ψ̇ = (q sin φ + r cos φ) / cos θ from
  its body rates and angles: what a yaw-rate setpoint asks; the body rate `yawspeed` alone reads
  cos θ cos φ of it in a tilted turn) against the phase's commanded yaw rate, or for a commanded
  heading against the vehicle's heading reference (`HeadingTurn`): from the heading and heading
  rate when the heading was commanded, the short way as of then, at up to MPC_YAWRAUTO_MAX
  (45 °/s) reached and left at MPC_YAWRAUTO_ACC (60 °/s²), and a hold once there; judged while in
  OFFBOARD, from 1 s after the setpoint changed (and 1 s after such a turn ends) until it changes
  again or the example's duration of the phase ends; a departure of more
  than 5 °/s for more than 0.5 s (simulated), a stall, or a spike (under a commanded yaw rate
  30 °/s faster than asked or the wrong way; in a heading turn 30 °/s the wrong way for 0.2 s) is
  reported with its values.
"""
import math
import statistics
from dataclasses import dataclass

from tlog_judge import OFFBOARD, Check, last_before

YAW_SETTLE_S = 1.0  # skipped after each setpoint change (wall time, as the example's phases)
YAW_TOL_DEG_S = 5.0  # a yaw rate further from the expected one departs
YAW_DEPART_MAX_S = 0.5  # a departure longer than this (simulated) is reported
YAW_SPIKE_DEG_S = 30.0  # a sample this much faster than expected (or the wrong way) is a spike
HEADING_SPIKE_MIN_S = 0.2  # ...in a heading turn, a wrong-way run this long (a tilt swing reads shorter)
HEADING_RATE_DEG_S = 45.0  # MPC_YAWRAUTO_MAX: a commanded heading is turned at this rate
HEADING_ACC_DEG_S2 = 60.0  # MPC_YAWRAUTO_ACC: ...reached and left at this acceleration
HEADING_TOL_DEG = 5.0  # a commanded heading is reached within this (and half a turn within it goes either way)


@dataclass(frozen=True)
class Phase:
    """One offboard setpoint of an example as its source sends it, and how long it holds it:
    `setpoint` names fields of SET_POSITION_TARGET_LOCAL_NED (x, y, z, vx, vy, vz; yaw and
    yaw_rate in degrees) with the example's values; a phase with `yaw_rate` is judged on that rate,
    one with `yaw` on the turn to that heading."""

    label: str
    setpoint: dict
    duration_s: float

    def describe(self):
        """'label (yaw rate +60 °/s, 5 s)' or '(heading 90°, 4 s)'."""
        what = (f"yaw rate {self.setpoint['yaw_rate']:+g} °/s" if "yaw_rate" in self.setpoint
                else f"heading {self.setpoint['yaw']:g}°")
        return f"{self.label} ({what}, {self.duration_s:g} s)"


def wrap_deg(angle):
    """`angle` [deg] in (-180, 180]."""
    return -((-angle + 180.0) % 360.0 - 180.0)


def _matches(fields, setpoint):
    for name, value in setpoint.items():
        got = fields.get(name, math.nan)
        diff = wrap_deg(got - value) if name == "yaw" else got - value
        if not abs(diff) < 0.01:
            return False
    return True


def setpoint_runs(setpoints):
    """The received setpoint stream cut where it changes: (wall, sim of its first frame, wall of
    the next change or of its last frame, fields) per run of identical setpoints."""
    runs = []
    for wall, sim, fields in setpoints:
        key = tuple((k, round(v, 4)) if math.isfinite(v) else (k, str(v)) for k, v in sorted(fields.items()))
        if runs:
            runs[-1][2] = wall
        if not runs or runs[-1][4] != key:
            runs.append([wall, sim, wall, fields, key])
    return [tuple(r[:4]) for r in runs]


class HeadingTurn:
    """The heading reference the vehicle turns to a commanded heading through (its docs: rate up to
    HEADING_RATE_DEG_S, acceleration HEADING_ACC_DEG_S2, the short way as of the command, kept),
    stepped at 1 kHz from the heading [deg] and heading rate [deg/s] the vehicle had when the
    heading was commanded: `rate(t)` [deg/s] `t` [s] after the command, `duration` until it rests."""

    STEP_S = 1e-3

    def __init__(self, start_deg: float, start_rate_deg_s: float, target_deg: float):
        a, w, dt = HEADING_ACC_DEG_S2, HEADING_RATE_DEG_S, self.STEP_S
        left, rate, self.rates = wrap_deg(target_deg - start_deg), start_rate_deg_s, [start_rate_deg_s]
        while len(self.rates) < 60_000 and not (abs(left) < 1e-6 and rate == 0.0):
            dv = a * dt
            if abs(left) <= (abs(rate) + dv) * dt and abs(rate) <= dv:
                rate, left = 0.0, 0.0
            else:
                braking = math.sqrt((dv / 2) ** 2 + 2 * a * abs(left)) - dv / 2
                demand = math.copysign(min(braking, w, abs(left) / dt), left)
                rate += max(-dv, min(dv, demand - rate))
                left -= rate * dt
            self.rates.append(rate)
        self.duration = (len(self.rates) - 1) * dt
        self.turn_deg = wrap_deg(target_deg - start_deg)

    def rate(self, t: float) -> float:
        """The reference's heading rate [deg/s] `t` [s] after the command (0 once it rests)."""
        k = int(round(t / self.STEP_S))
        return self.rates[k] if 0 <= k < len(self.rates) else 0.0 if k >= len(self.rates) else self.rates[0]


def yaw_checks(tel, phases):
    """One check per phase: the heading rate ATTITUDE shows against what the phase's setpoint asks, while in
    OFFBOARD, from YAW_SETTLE_S after the setpoint arrived until it changed (at most the
    example's duration)."""
    runs, i, checks = setpoint_runs(tel.setpoints), 0, []
    for phase in phases:
        name = f"yaw: {phase.describe()}"
        found = next((j for j in range(i, len(runs)) if _matches(runs[j][3], phase.setpoint)), None)
        if found is None:
            checks.append(Check(name, False, f"setpoint {phase.setpoint} never received"))
            continue
        start, start_sim, end, _ = runs[found]
        i = found + 1
        end = min(end, start + phase.duration_s)
        samples = [a for a in tel.attitude if start + YAW_SETTLE_S <= a[0] <= end
                   and tel.state_at(a[0]) == (True, OFFBOARD)]
        if not samples:
            armed, mode = tel.state_at(end)
            checks.append(Check(name, False, f"not armed in OFFBOARD during the phase (at its end: armed {armed}, "
                                             f"custom_mode {mode})"))
            continue
        if "yaw_rate" in phase.setpoint:
            checks.append(_judge_rate(name, samples, phase.setpoint["yaw_rate"]))
        else:
            first = last_before(tel.attitude, start) or samples[0]
            turn = HeadingTurn(first[2], first[3], phase.setpoint["yaw"])
            checks.append(_judge_heading(name, samples, phase.setpoint["yaw"], turn, start_sim))
    return checks


def _departures(samples, expected):
    """Runs of samples whose yaw rate is more than YAW_TOL_DEG_S from `expected(sample)` (None:
    not judged, ends a run): (simulated duration [s], samples) for each."""
    runs, current = [], []
    for a in samples:
        want = expected(a)
        if want is not None and abs(a[3] - want) > YAW_TOL_DEG_S:
            current.append(a)
            continue
        if current:
            runs.append(current)
        current = []
    if current:
        runs.append(current)
    period = (samples[-1][1] - samples[0][1]) / max(len(samples) - 1, 1)
    return [(r[-1][1] - r[0][1] + period, r) for r in runs]


def _runs(samples, chosen):
    """`chosen` (a subset of `samples`, in order) split into runs of consecutive samples."""
    index = {id(a): i for i, a in enumerate(samples)}
    runs = []
    for a in chosen:
        if runs and index[id(a)] == index[id(runs[-1][-1])] + 1:
            runs[-1].append(a)
        else:
            runs.append([a])
    return runs


def _rate_report(samples, expected, t0, stall_when, faster_is_spike=True):
    """(ok, text): the longest departure beyond YAW_DEPART_MAX_S, a stall in it, the spikes (more
    than YAW_SPIKE_DEG_S the wrong way, or faster than asked when `faster_is_spike`)."""
    problems = []
    long = [(d, r) for d, r in _departures(samples, expected) if d > YAW_DEPART_MAX_S]
    if long:
        d, r = max(long, key=lambda x: x[0])
        rates = [a[3] for a in r]
        stalled = sum(stall_when(a) for a in r) > len(r) / 2
        problems.append(f"more than {YAW_TOL_DEG_S:g} °/s off for {d:.2f} s from +{r[0][0] - t0:.1f} s"
                        f" ({min(rates):+.1f} … {max(rates):+.1f} °/s)" + (": stalled" if stalled else "")
                        + (f", {len(long)} such departures" if len(long) > 1 else ""))
    def spike(a, want):
        wrong_way = a[3] * want < 0 or (want == 0 and faster_is_spike)
        return abs(a[3] - want) > YAW_SPIKE_DEG_S and (wrong_way or (faster_is_spike and abs(a[3]) > abs(want)))

    spikes = [a for a in samples if expected(a) is not None and spike(a, expected(a))]
    if not faster_is_spike:  # a heading: only a wrong-way turn that lasts
        spikes = [a for run in _runs(samples, spikes) if run[-1][1] - run[0][1] >= HEADING_SPIKE_MIN_S for a in run]
    if spikes:
        worst = max(spikes, key=lambda a: abs(a[3] - expected(a)))
        plural = "s" if len(spikes) > 1 else ""
        problems.append(f"spike to {worst[3]:+.1f} °/s at +{worst[0] - t0:.1f} s (expected {expected(worst):+.1f} °/s; "
                        f"{len(spikes)} sample{plural} more than {YAW_SPIKE_DEG_S:g} °/s faster or the wrong way)")
    return problems


def _judge_rate(name, samples, rate):
    """A commanded yaw rate: every judged sample within YAW_TOL_DEG_S of it."""
    rates = [a[3] for a in samples]
    t0 = samples[0][0] - YAW_SETTLE_S
    problems = _rate_report(samples, lambda a: rate, t0,
                            lambda a: abs(rate) >= 2 * YAW_TOL_DEG_S and abs(a[3]) < YAW_TOL_DEG_S)
    seen = (f"heading rate (ATTITUDE) mean {statistics.fmean(rates):+.1f} °/s, "
            f"{min(rates):+.1f} … {max(rates):+.1f} °/s over {samples[-1][1] - samples[0][1]:.1f} s in OFFBOARD")
    return Check(name, not problems, "; ".join(problems + [seen]))


def _judge_heading(name, samples, heading, turn, start_sim):
    """A commanded heading: turned as `turn` (a HeadingTurn from the heading and rate when it was
    commanded), then held (rate 0) from YAW_SETTLE_S after the turn's end; reached within
    HEADING_TOL_DEG by the end of the phase when the phase is long enough for that."""
    arrives = start_sim + turn.duration

    def expected(a):
        if a[1] <= arrives:
            return turn.rate(a[1] - start_sim)
        return 0.0 if a[1] >= arrives + YAW_SETTLE_S else None

    t0 = samples[0][0] - YAW_SETTLE_S
    # A heading is the nose's direction seen from above: while a position step swings the tilt
    # at a few hundred °/s it swings too, for a tenth of a second either way (PX4's too); only a
    # turn the wrong way for HEADING_SPIKE_MIN_S is a spike here, and a lasting departure is
    # reported as everywhere.
    problems = _rate_report(samples, expected, t0,
                            lambda a: abs(expected(a) or 0.0) >= 2 * YAW_TOL_DEG_S and abs(a[3]) < YAW_TOL_DEG_S,
                            faster_is_spike=False)
    final = wrap_deg(samples[-1][2])
    if arrives + YAW_SETTLE_S <= samples[-1][1] and abs(wrap_deg(heading - final)) > HEADING_TOL_DEG:
        problems.append(f"heading {final:.1f}° at the end of the phase, not {heading:g}° ± {HEADING_TOL_DEG:g}°")
    rates = [a[3] for a in samples]
    seen = (f"heading {wrap_deg(heading - turn.turn_deg):.1f}° → {final:.1f}° (a turn of {round(turn.turn_deg):+d}°, "
            f"{turn.duration:.1f} s at up to {HEADING_RATE_DEG_S:g} °/s), heading rate (ATTITUDE) "
            f"{min(rates):+.1f} … {max(rates):+.1f} °/s over {samples[-1][1] - samples[0][1]:.1f} s in OFFBOARD")
    return Check(name, not problems, "; ".join(problems + [seen]))
