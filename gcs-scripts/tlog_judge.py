"""What a ground station saw of one flight, read back from the vehicle's tlog, and the checks that
`run_mavsdk_examples.py` makes on it.

`rotorpilot run --log DIR` writes `DIR/flight.tlog`: every frame the vehicle sent on its GCS and
API links and every frame it received, each with its wall-clock time. The vehicle's own frames
(system 1, component 1) are the telemetry QGroundControl or MAVSDK shows: the judge reads nothing
else about the vehicle (no simulator truth, no flight log). The frames it received say what the
example asked: its offboard setpoints mark the phases of an offboard flight, its DO_ORBIT the
orbit's centre.

- Heights are LOCAL_POSITION_NED.z relative to the last reading before the first arming, as a
  ground station's height above take-off; GLOBAL_POSITION_INT.relative_alt is checked beside them.
  On the ground before arming |z| ≤ 0.1 m (a run that never arms reports its last reading, not
  judged); after every landing the resting height and relative_alt within 0.2 m of 0; no disarm
  more than 0.5 m up.
- Touch-down: the fastest LOCAL_POSITION_NED.vz in the second before the vehicle last descended
  faster than LNDMC_Z_VEL_MAX (0.25 m/s) ahead of the landed state turning ON_GROUND; then the
  disarm (COM_DISARM_LAND).
- Yaw per offboard phase: `tlog_yaw.py`.
- GPS state after a GPS failure: GPS_RAW_INT stops or reports fix_type < 2, and SYS_STATUS clears
  the GPS health bit.

Windows that follow the example (its phases, the GPS failure) are in the tlog's wall time, as the
example's own `asyncio.sleep`; durations of the vehicle's behaviour are in its simulated time
(time_boot_ms), so they mean the same at any --speedup.
"""
import bisect
import math
import statistics
from dataclasses import dataclass

VEHICLE = (1, 1)
# Messages pymavlink 2.4.49's generated dialects lack (they arrive as UNKNOWN_<id>).
UNKNOWN_NAMES = {300: "PROTOCOL_VERSION", 360: "ORBIT_EXECUTION_STATUS", 397: "COMPONENT_METADATA",
                 435: "AVAILABLE_MODES", 436: "CURRENT_MODE"}
# PX4's custom_mode values (main mode << 16 | sub mode << 24) in HEARTBEAT.
POSCTL, ORBIT, OFFBOARD = 196608, 16973824, 393216
AUTO_LOITER, AUTO_RTL, AUTO_LAND, FOLLOW_TARGET, GOTO = 50593792, 84148224, 100925440, 134479872, 352583680
ARMED_FLAG = 128  # MAV_MODE_FLAG_SAFETY_ARMED
GPS_SENSOR = 32  # MAV_SYS_STATUS_SENSOR_GPS
INJECT_FAILURE, ACCEPTED = 420, 0
AIRBORNE_STATES = ("TAKEOFF", "IN_AIR", "LANDING")

REST_Z_MAX_M = 0.1  # |LOCAL_POSITION_NED.z| on the ground before arming
LANDED_HEIGHT_MAX_M = 0.2  # |height| and |relative_alt| resting after a landing
DISARM_HEIGHT_MAX_M = 0.5  # a disarm higher up is a vehicle dropped from the sky
AIRBORNE_M = 1.0  # a mode flown this high counts as flown in the air
LANDING_WINDOW_S = 15.0  # simulated seconds before ON_GROUND searched for the touch-down
CONTACT_M_S = 0.25  # LNDMC_Z_VEL_MAX: descending faster than this, the vehicle has not touched down yet
TOUCHDOWN_MAX_M_S = 1.0  # MPC_LAND_SPEED (0.7 m/s) and a margin
GPS_GRACE_S = 1.5  # wall seconds after the failure's ACK before the telemetry must show it


@dataclass
class Check:
    """One judged property of the flight: its name, whether it holds, the values seen."""

    name: str
    ok: bool
    seen: str

    def as_dict(self):
        """The check for the JSON verdict."""
        return {"check": self.name, "ok": self.ok, "seen": self.seen}


class Telemetry:
    """The series a ground station received, from a tlog. Each sample starts (wall [s], sim [s]):
    wall is the tlog's time, sim the vehicle's time_boot_ms (its latest for messages without one).
    Streams sent on both links are kept once (strictly increasing time_boot_ms)."""

    def __init__(self, path):
        from rotorpilot_gcs import connection_with_dialect, mavutil

        self.heartbeats = []  # (wall, sim, armed, custom_mode)
        self.local = []  # (wall, sim, z [m], vz [m/s, down])
        self.position = []  # (wall, sim, relative_alt [m], lat [deg], lon [deg])
        self.attitude = []  # (wall, sim, yaw [deg], heading rate ψ̇ [deg/s])
        self.landed = []  # (wall, sim, MAV_LANDED_STATE name without its prefix), changes only
        self.gps_raw = []  # (wall, sim, fix_type, satellites_visible)
        self.gps_health = []  # (wall, sim, present, enabled, healthy)
        self.setpoints = []  # (wall, sim, {field: value}) SET_POSITION_TARGET_LOCAL_NED received
        self.counts, self.statustexts, self.command_acks, self.mission_acks = {}, [], [], []
        self.param_count, self.orbit_centre = 0, None
        last_boot = {}
        sim = 0.0
        log = connection_with_dialect(str(path), "common")
        landed_names = mavutil.mavlink.enums["MAV_LANDED_STATE"]
        while (m := log.recv_match()) is not None:
            kind = m.get_type()
            if kind.startswith("UNKNOWN_"):  # no header fields either: counted only
                kind = UNKNOWN_NAMES.get(int(kind[8:]), kind)
                self.counts[kind] = self.counts.get(kind, 0) + 1
                continue
            self.counts[kind] = self.counts.get(kind, 0) + 1
            wall = m._timestamp
            if (m.get_srcSystem(), m.get_srcComponent()) != VEHICLE:
                self._received(kind, m, wall, sim)
                continue
            boot = getattr(m, "time_boot_ms", None)
            if boot is not None:
                if boot <= last_boot.get(kind, -1):
                    continue  # the same sample on the other link
                last_boot[kind] = boot
                sim = max(sim, boot / 1000.0)
            if kind == "HEARTBEAT":
                self.heartbeats.append((wall, sim, bool(m.base_mode & ARMED_FLAG), m.custom_mode))
            elif kind == "LOCAL_POSITION_NED":
                self.local.append((wall, sim, m.z, m.vz))
            elif kind == "GLOBAL_POSITION_INT":
                self.position.append((wall, sim, m.relative_alt / 1000.0, m.lat / 1e7, m.lon / 1e7))
            elif kind == "ATTITUDE":
                self.attitude.append((wall, sim, math.degrees(m.yaw), math.degrees(heading_rate(m))))
            elif kind == "EXTENDED_SYS_STATE":
                name = landed_names[m.landed_state].name[len("MAV_LANDED_STATE_"):]
                if not self.landed or self.landed[-1][2] != name:
                    self.landed.append((wall, sim, name))
            elif kind == "GPS_RAW_INT":
                self.gps_raw.append((wall, sim, m.fix_type, m.satellites_visible))
            elif kind == "SYS_STATUS":
                self.gps_health.append((wall, sim, *(bool(bits & GPS_SENSOR) for bits in (
                    m.onboard_control_sensors_present, m.onboard_control_sensors_enabled,
                    m.onboard_control_sensors_health))))
            elif kind == "STATUSTEXT":
                self.statustexts.append(m.text)
            elif kind == "COMMAND_ACK":
                self.command_acks.append((wall, m.command, m.result))
            elif kind == "PARAM_VALUE":
                self.param_count = m.param_count
            elif kind == "MISSION_ACK":
                self.mission_acks.append((m.mission_type, m.type))

    def _received(self, kind, m, wall, sim):
        """A frame the vehicle received: what the example asked."""
        if kind == "COMMAND_LONG" and m.command == 34:  # DO_ORBIT
            self.orbit_centre = (m.param5, m.param6)
        elif kind == "COMMAND_INT" and m.command == 34:
            self.orbit_centre = (m.x / 1e7, m.y / 1e7)
        elif kind == "SET_POSITION_TARGET_LOCAL_NED":
            fields = {k: getattr(m, k) for k in ("x", "y", "z", "vx", "vy", "vz")}
            fields.update(yaw=math.degrees(m.yaw) % 360.0, yaw_rate=math.degrees(m.yaw_rate))
            self.setpoints.append((wall, sim, fields))

    def state_at(self, wall):
        """(armed, custom_mode) by the last HEARTBEAT at or before `wall`; (False, None) before any."""
        i = bisect.bisect_right(self.heartbeats, wall, key=lambda h: h[0])
        return self.heartbeats[i - 1][2:] if i else (False, None)

    def first_armed(self):
        """Wall time of the first HEARTBEAT showing the vehicle armed, None if never."""
        return next((h[0] for h in self.heartbeats if h[2]), None)


def last_before(series, wall):
    """The last sample of `series` at or before `wall`, None if none."""
    i = bisect.bisect_right(series, wall, key=lambda s: s[0])
    return series[i - 1] if i else None


def summarize(tel, target=None):
    """What the flight showed, as the runner reports it (heights [m] from the rest reading before
    the first arming, modes, landed states, landings, answers)."""
    armed_at = tel.first_armed()
    if armed_at is not None:
        rest, summary = last_before(tel.local, armed_at), {"rest_at": "before the first arming"}
    else:
        rest, summary = (tel.local[-1] if tel.local else None), {"rest_at": "at the end, never armed"}
    z0 = rest[2] if rest is not None else 0.0
    heights = [(w, s, z0 - z) for w, s, z, _ in tel.local]
    alt = last_before(tel.position, rest[0]) if rest is not None else None
    summary.update({"rest_z_m": None if rest is None else round(rest[2], 3),
                    "rest_relative_alt_m": None if alt is None else round(alt[2], 3)})
    summary.update({"max_height_m": 0.0, "modes": [],
               "airborne_modes": [], "counts": tel.counts, "statustexts": tel.statustexts,
               "command_acks": [a[1:] for a in tel.command_acks], "mission_acks": tel.mission_acks,
               "param_count": tel.param_count, "landed_states": [s[2] for s in tel.landed]})
    summary["max_height_m"] = round(max((h[2] for h in heights), default=0.0), 2)
    disarms, armed = [], False
    for wall, _, now_armed, mode in tel.heartbeats:
        height = (last_before(heights, wall) or (0, 0, 0.0))[2]
        if armed and not now_armed:
            alt = last_before(tel.position, wall)
            disarms.append({"height_m": round(height, 2), "relative_alt_m": None if alt is None else round(alt[2], 2),
                            "wall": wall})
        armed = now_armed
        if mode not in summary["modes"]:
            summary["modes"].append(mode)
        if armed and height > AIRBORNE_M and mode not in summary["airborne_modes"]:
            summary["airborne_modes"].append(mode)
    summary["disarms"] = [{k: v for k, v in d.items() if k != "wall"} for d in disarms]
    summary["disarms_in_air"] = [d["height_m"] for d in disarms if d["height_m"] > DISARM_HEIGHT_MAX_M]
    summary["landings"] = landings(tel, heights, disarms)
    summary["touchdown_m_s"] = max((x["touchdown_m_s"] for x in summary["landings"]), default=0.0)
    summary["final_armed"] = tel.state_at(math.inf)[0]
    summary["final_height_m"] = round(heights[-1][2], 2) if heights else 0.0
    summary["final_relative_alt_m"] = round(tel.position[-1][2], 2) if tel.position else 0.0
    follow = [h for w, _, h in heights if tel.state_at(w) == (True, FOLLOW_TARGET)]
    if follow:
        summary["min_follow_height_m"] = round(min(follow), 2)
    if target is not None and tel.position:
        summary["start_target_m"] = round(horizontal_m(tel.position[0][3:], target), 1)
        summary["final_target_m"] = round(horizontal_m(tel.position[-1][3:], target), 1)
    radii = [horizontal_m(p[3:], tel.orbit_centre) for p in tel.position
             if tel.orbit_centre is not None and tel.state_at(p[0])[1] == ORBIT]
    on_circle = radii[len(radii) // 2:] or [0.0]  # the second half: the first includes the approach
    summary["orbit_radius_m"] = [round(min(on_circle), 2), round(max(on_circle), 2)]
    return summary


def heading_rate(attitude) -> float:
    """ψ̇ [rad/s] from an ATTITUDE's body rates and angles (ZYX Euler kinematics)."""
    phi, theta = attitude.roll, attitude.pitch
    return (attitude.pitchspeed * math.sin(phi) + attitude.yawspeed * math.cos(phi)) / max(math.cos(theta), 1e-3)


def landings(tel, heights, disarms):
    """Each landing: the landed state turning ON_GROUND after an airborne one. Its touch-down
    speed and how long before ON_GROUND it came (simulated), the resting height and relative_alt
    after it (medians until the next take-off or the end), and how long after it the vehicle
    disarmed (wall time)."""
    found = []
    for i in range(1, len(tel.landed)):
        wall, sim, state = tel.landed[i]
        if state != "ON_GROUND" or tel.landed[i - 1][2] not in AIRBORNE_STATES:
            continue
        until = tel.landed[i + 1][0] if i + 1 < len(tel.landed) else math.inf
        descent = [(s, vz) for _, s, _, vz in tel.local if sim - LANDING_WINDOW_S <= s <= sim]
        # The touch-down: the last sample still descending faster than CONTACT_M_S; its speed is
        # the fastest descent in the second before it (a slow landing: the fastest of the window).
        contact = next((s for s, vz in reversed(descent) if vz > CONTACT_M_S), None)
        if contact is not None:
            descent = [(s, vz) for s, vz in descent if contact - 1.0 <= s <= contact]
        resting = [h for w, _, h in heights if wall <= w < until] or [(last_before(heights, wall) or (0, 0, 0.0))[2]]
        alts = [p[2] for p in tel.position if wall <= p[0] < until] or [(last_before(tel.position, wall)
                                                                          or (0, 0, 0.0))[2]]
        disarm = next((d for d in disarms if wall - 0.5 <= d["wall"] < until), None)
        after = None
        if disarm is not None:
            after = round(disarm["wall"] - wall, 1)
        found.append({"touchdown_m_s": round(max((vz for _, vz in descent), default=0.0), 2),
                      "touchdown_before_s": None if contact is None else round(sim - contact, 1),
                      "rest_height_m": round(statistics.median(resting), 2),
                      "rest_relative_alt_m": round(statistics.median(alts), 2),
                      "relative_alt_range_m": [round(min(alts), 2), round(max(alts), 2)],
                      "disarmed_after_s": after})
    return found


def horizontal_m(a, b):
    """Distance [m] between two (lat, lon) [deg] points (equirectangular, fine over km)."""
    k = math.pi / 180.0 * 6_371_000.0
    return math.hypot((a[0] - b[0]) * k, (a[1] - b[1]) * k * math.cos(math.radians(a[0])))


def ground_checks(summary, lands=False, disarms=False, touchdown_max=TOUCHDOWN_MAX_M_S):
    """The height at rest before the first arming, the disarms, every landing's touch-down and
    resting height; `lands`: the example ends on the ground; `disarms`: and disarmed."""
    checks = []
    if summary["rest_z_m"] is not None and summary["rest_at"] == "before the first arming":
        z, alt = summary["rest_z_m"], summary["rest_relative_alt_m"]
        checks.append(Check("at rest on the ground", abs(z) <= REST_Z_MAX_M,
                            f"LOCAL_POSITION_NED.z {z:+.2f} m {summary['rest_at']} (|z| ≤ {REST_Z_MAX_M} m)"
                            + ("" if alt is None else f", relative_alt {alt:+.2f} m")))
    if summary["disarms"]:
        checks.append(Check("disarmed on the ground", not summary["disarms_in_air"],
                            f"heights at disarm {[d['height_m'] for d in summary['disarms']]} m, relative_alt "
                            f"{[d['relative_alt_m'] for d in summary['disarms']]} m (≤ {DISARM_HEIGHT_MAX_M} m)"))
    for n, landing in enumerate(summary["landings"], 1):
        h, alt = landing["rest_height_m"], landing["rest_relative_alt_m"]
        checks.append(Check(f"landing {n}: resting height", abs(h) <= LANDED_HEIGHT_MAX_M
                            and abs(alt) <= LANDED_HEIGHT_MAX_M,
                            f"{h:+.2f} m above the rest reading before arming (LOCAL_POSITION_NED), "
                            f"relative_alt {alt:+.2f} m (seen {landing['relative_alt_range_m']}); "
                            f"within {LANDED_HEIGHT_MAX_M} m of 0"
                            + ("" if h >= -LANDED_HEIGHT_MAX_M and alt >= -LANDED_HEIGHT_MAX_M
                               else ": shown under the ground")))
        checks.append(Check(f"landing {n}: touch-down", landing["touchdown_m_s"] <= touchdown_max,
                            f"{landing['touchdown_m_s']:.2f} m/s down (LOCAL_POSITION_NED.vz) at the touch-down "
                            + (f"{landing['touchdown_before_s']} s before ON_GROUND" if landing["touchdown_before_s"]
                               is not None else f"(never faster than {CONTACT_M_S} m/s in the {LANDING_WINDOW_S:g} s "
                               "before ON_GROUND)") + f" (≤ {touchdown_max} m/s)"))
    if lands:
        last = summary["landed_states"][-1:]
        checks.append(Check("ends on the ground", last == ["ON_GROUND"] and bool(summary["landings"]),
                            f"landed states {summary['landed_states']}, final height {summary['final_height_m']} m, "
                            f"relative_alt {summary['final_relative_alt_m']} m"))
    if disarms:
        after = summary["landings"][-1]["disarmed_after_s"] if summary["landings"] else None
        checks.append(Check("disarms after landing", after is not None and not summary["final_armed"],
                            f"disarmed {after} s after ON_GROUND" if after is not None
                            else f"no disarm after a landing (armed at the end: {summary['final_armed']})"))
    return checks


def gps_loss_checks(tel):
    """After an accepted GPS failure (INJECT_FAILURE's COMMAND_ACK), from GPS_GRACE_S on:
    GPS_RAW_INT stopped or fix_type < 2, and SYS_STATUS's GPS health bit cleared."""
    injected = next((w for w, command, result in tel.command_acks
                     if command == INJECT_FAILURE and result == ACCEPTED), None)
    if injected is None:
        return [Check("GPS loss shown", False, "no failure injection accepted")]
    since, until = injected + GPS_GRACE_S, injected - 1e-3  # the GPS as shown before the failure: until then
    before = last_before(tel.gps_raw, until)
    was = f"before: fix_type {before[2]}, {before[3]} satellites; " if before else "before: no GPS_RAW_INT; "
    after = [g for g in tel.gps_raw if g[0] >= since]
    fixed = [g for g in after if g[2] >= 2]
    if not after:
        raw = "after: no GPS_RAW_INT (stopped)"
    else:
        raw = (f"after: {len(after)} GPS_RAW_INT, {len(fixed)} with fix_type ≥ 2 (last: fix_type {after[-1][2]}, "
               f"{after[-1][3]} satellites, {after[-1][0] - injected:.1f} s after the failure)")
    checks = [Check("GPS loss shown in GPS_RAW_INT", not fixed,
                    was + raw + (": the GPS still shows a fix" if fixed else ""))]
    status_before = last_before(tel.gps_health, until)
    status = [g for g in tel.gps_health if g[0] >= since]
    healthy = [g for g in status if g[4]]
    bits = "present/enabled/healthy " + ("/".join(str(int(b)) for b in status_before[2:]) if status_before else "?")
    checks.append(Check("GPS loss shown in SYS_STATUS", bool(status) and not healthy and bool(status_before),
                        f"before: GPS {bits}; after: health bit set in {len(healthy)} of {len(status)} SYS_STATUS"
                        + (": the GPS still shows healthy" if healthy else "")))
    return checks
