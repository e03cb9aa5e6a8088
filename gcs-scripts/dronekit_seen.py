"""What the DroneKit examples' judge reads in a run (run_dronekit_examples.py): ArduCopter's
mode numbers and the judged constants, the frames the example sent and the telemetry seen
(`Seen`), and the checks the examples share (take-off, legs, speeds, the return home, uploads)."""

import math
import pathlib
import re
import statistics

import tlog_judge as judge
from tlog_judge import Check, horizontal_m, last_before

HERE = pathlib.Path(__file__).resolve().parent
EXAMPLES = HERE / "tests" / "third_party" / "dronekit_examples"
# ArduPilot SITL's default home (CMAC): the examples' absolute coordinates are near it.
HOME = (-35.363261, 149.165230, 584.0)
CONNECT = "udpin:127.0.0.1:14550"
# ArduCopter's HEARTBEAT custom_mode numbers.
STABILIZE, AUTO, GUIDED, RTL, LAND, GUIDED_NOGPS, SMART_RTL = 0, 3, 4, 6, 9, 20, 21
RETURNING = (RTL, LAND, SMART_RTL)
# MAV_STATE in HEARTBEAT.system_status → the landed state it stands for (ArduCopter: STANDBY once
# landed, armed or not; ACTIVE in the air). CRITICAL (a failsafe active, in the air or not) stands
# for none: there a disarmed vehicle is on the ground (Copter disarms only there, but for a kill).
LANDED_BY_STATUS = {3: "ON_GROUND", 4: "IN_AIR"}
MAV_MODE_FLAG_SAFETY_ARMED = 128
MAV_CMD_DO_SET_MODE, MAV_CMD_DO_CHANGE_SPEED, MAV_CMD_DO_SET_HOME, MAV_CMD_DO_SET_ROI = 176, 178, 179, 201
MAV_RESULT_ACCEPTED = 0
SPEED_SETTLE_S = 4.0  # simulated seconds after a speed change before the leg's speed is judged
ARRIVED_M = 3.0  # a target approached this close is reached




class Seen:
    """What the judge reads besides tlog_judge.Telemetry: the frames the example sent (gotos,
    commands, overrides, attitude targets, mission items) and the vehicle's answers (system
    status, ground speed, RC_CHANNELS, RAW_IMU, mission requests and acks), each with its wall time."""

    def __init__(self, path):
        from rotorpilot_gcs import connection_with_dialect

        self.status = []  # (wall, system_status, armed), changes only
        self.position = []  # (wall, sim, lat, lon, relative_alt [m], ground speed [m/s])
        self.rc = []  # (wall, chancount, [chan1_raw … chan18_raw])
        self.raw_imu = []  # (wall, zacc [mg], zmag [mgauss])
        self.gotos = []  # (wall, lat, lon, alt, frame): MISSION_ITEM(_INT) with current = 2
        self.commands = []  # (wall, command, (param1 … param7))
        self.overrides = []  # (wall, [chan1_raw … chan8_raw])
        self.attitude_targets = []  # (wall, type_mask, thrust, pitch [deg])
        self.items_in = {}  # seq → (command, lat, lon, alt) mission items the vehicle received
        self.counts_in = []  # MISSION_COUNT the vehicle received
        self.requests = {}  # kind (MISSION_REQUEST / _INT) → number the vehicle sent
        self.counts_out = []  # MISSION_COUNT the vehicle sent
        self.items_out = []  # (seq, kind) items the vehicle sent
        self.mission_acks = []  # (wall, type) MISSION_ACK the vehicle sent
        self.acks = []  # (wall, command, result)
        self.texts = []  # (wall, severity, text)
        last = {}
        log = connection_with_dialect(str(path), "ardupilotmega")
        while (m := log.recv_match()) is not None:
            kind, wall = m.get_type(), m._timestamp
            if (m.get_srcSystem(), m.get_srcComponent()) != judge.VEHICLE:
                self._received(kind, m, wall)
                continue
            stamp = getattr(m, "time_boot_ms", getattr(m, "time_usec", None))
            if stamp is not None and kind != "SYSTEM_TIME":
                if stamp <= last.get(kind, -1):
                    continue  # the same sample on the other link
                last[kind] = stamp
            if kind == "HEARTBEAT":
                now = (m.system_status, bool(m.base_mode & MAV_MODE_FLAG_SAFETY_ARMED))
                if not self.status or self.status[-1][1:] != now:
                    self.status.append((wall, *now))
            elif kind == "GLOBAL_POSITION_INT":
                self.position.append(
                    (
                        wall,
                        m.time_boot_ms / 1000.0,
                        m.lat / 1e7,
                        m.lon / 1e7,
                        m.relative_alt / 1000.0,
                        math.hypot(m.vx, m.vy) / 100.0,
                    )
                )
            elif kind == "RC_CHANNELS":
                self.rc.append((wall, m.chancount, [getattr(m, f"chan{i}_raw") for i in range(1, 19)]))
            elif kind == "RAW_IMU":
                self.raw_imu.append((wall, m.zacc, m.zmag))
            elif kind in ("MISSION_REQUEST", "MISSION_REQUEST_INT"):
                self.requests[kind] = self.requests.get(kind, 0) + 1
            elif kind == "MISSION_COUNT":
                self.counts_out.append(m.count)
            elif kind in ("MISSION_ITEM", "MISSION_ITEM_INT"):
                self.items_out.append((m.seq, kind))
            elif kind == "MISSION_ACK":
                self.mission_acks.append((wall, m.type))
            elif kind == "COMMAND_ACK":
                self.acks.append((wall, m.command, m.result))
            elif kind == "STATUSTEXT":
                self.texts.append((wall, m.severity, m.text))

    def _received(self, kind, m, wall):
        if kind in ("MISSION_ITEM", "MISSION_ITEM_INT"):
            scale = 1e7 if kind == "MISSION_ITEM_INT" else 1.0
            if m.current == 2:
                self.gotos.append((wall, m.x / scale, m.y / scale, m.z, m.frame))
            else:
                self.items_in[m.seq] = (m.command, m.x / scale, m.y / scale, m.z)
        elif kind == "MISSION_COUNT":
            self.counts_in.append(m.count)
        elif kind in ("COMMAND_LONG", "COMMAND_INT"):
            params = [m.param1, m.param2, m.param3, m.param4]
            params += [m.x / 1e7, m.y / 1e7, m.z] if kind == "COMMAND_INT" else [m.param5, m.param6, m.param7]
            self.commands.append((wall, m.command, tuple(params)))
        elif kind == "RC_CHANNELS_OVERRIDE":
            self.overrides.append((wall, [getattr(m, f"chan{i}_raw") for i in range(1, 9)]))
        elif kind == "SET_ATTITUDE_TARGET":
            w, x, y, z = m.q
            pitch = math.degrees(math.asin(max(-1.0, min(1.0, 2.0 * (w * y - z * x)))))
            self.attitude_targets.append((wall, m.type_mask, m.thrust, pitch))

    def landed_states(self, tel):
        """tlog_judge's landed-state series (wall, sim, state) from HEARTBEAT.system_status."""
        states = []
        for wall, status, armed in self.status:
            state = LANDED_BY_STATUS.get(status, None if armed else "ON_GROUND")
            if state is not None and (not states or states[-1][2] != state):
                sim = (last_before(tel.local, wall) or (0, 0.0))[1]
                states.append((wall, sim, state))
        return states

    def mode_requests(self, mode):
        """Wall times of the example's DO_SET_MODE to Copter mode `mode`."""
        return [w for w, c, p in self.commands if c == MAV_CMD_DO_SET_MODE and int(p[1]) == mode]

    def window(self, start, end):
        """GLOBAL_POSITION_INT samples from wall `start` to `end`."""
        return [p for p in self.position if start <= p[0] <= end]


def mode_seen_after(tel, mode, wall):
    """Whether a HEARTBEAT at or after `wall` showed the vehicle armed in Copter mode `mode`."""
    return any(h[3] == mode and h[2] for h in tel.heartbeats if h[0] >= wall)


def leg_checks(name, seen, target, start, end, speed_asked, speed_from):
    """A go-to leg from wall `start` to `end`: the horizontal distance to `target` (lat, lon) at
    both ends, the ground flown, and the fastest ground speed once the vehicle, asked at wall
    `speed_from` (None: the speed is not judged), has gone at half `speed_asked` for SPEED_SETTLE_S
    (simulated). The approach holds when the vehicle came ARRIVED_M close, or closer by at least
    half of what `speed_asked` covers in the leg's time, flying straight at it; the speed when at
    most 10 % (+0.3 m/s) over the one asked."""
    leg = seen.window(start, end)
    before = last_before(seen.position, start)
    if before is not None:
        leg.insert(0, before)
    if len(leg) < 2:
        return [Check(f"{name} approached", False, "no GLOBAL_POSITION_INT during the leg")], {}
    dist = [horizontal_m(p[2:4], target) for p in leg]
    flown = sum(horizontal_m(a[2:4], b[2:4]) for a, b in zip(leg, leg[1:]))
    duration = leg[-1][1] - leg[0][1]
    closer = dist[0] - dist[-1]
    expected = min(dist[0] - ARRIVED_M, speed_asked * duration)
    straight = closer >= 0.9 * flown - 2.0
    ok = min(dist) <= ARRIVED_M or (closer >= 0.5 * expected and straight)
    values = {
        "start_m": round(dist[0], 1),
        "end_m": round(dist[-1], 1),
        "closest_m": round(min(dist), 1),
        "flown_m": round(flown, 1),
        "leg_s": round(duration, 1),
    }
    checks = [
        Check(
            f"{name} approached",
            ok,
            f"{dist[0]:.0f} m → {dist[-1]:.1f} m from the target (closest {min(dist):.1f} m) in {duration:.0f} s "
            f"simulated, {flown:.0f} m flown; at {speed_asked:g} m/s asked: ≥ {0.5 * expected:.0f} m closer, "
            f"straight at it, or within {ARRIVED_M:g} m",
        )
    ]
    if speed_from is not None:
        # From SPEED_SETTLE_S (simulated) after the vehicle, asked, first went at half that speed.
        going = next((p for p in leg if p[0] >= speed_from and p[5] >= 0.5 * speed_asked), None)
        speeds = [p[5] for p in leg if going is not None and p[0] >= going[0] and p[1] >= going[1] + SPEED_SETTLE_S]
        fastest = max(speeds, default=0.0)
        values["max_speed_m_s"] = round(fastest, 2)
        values["cruise_m_s"] = round(statistics.median(speeds), 2) if speeds else None
        checks.append(
            Check(
                f"{name} speed",
                bool(speeds) and fastest <= speed_asked * 1.1 + 0.3,
                f"fastest {fastest:.2f} m/s over ground (GLOBAL_POSITION_INT vx, vy), median "
                f"{values['cruise_m_s']} m/s, from {SPEED_SETTLE_S:g} s after it first went at half the "
                f"{speed_asked:g} m/s asked (≤ {speed_asked * 1.1 + 0.3:.1f})"
                if going is not None
                else f"never at half the {speed_asked:g} m/s asked",
            )
        )
    return checks, values


def speed_asked_at(seen, wall, before_s=1.0):
    """The DO_CHANGE_SPEED the example sent within `before_s` wall seconds of `wall` (either side):
    (wall, speed type, speed), None without one."""
    near = [(w, p[0], p[1]) for w, c, p in seen.commands if c == MAV_CMD_DO_CHANGE_SPEED and abs(w - wall) <= before_s]
    return near[-1] if near else None


def takeoff_check(seen, tel, mode, height, before):
    """Armed and airborne in Copter `mode`, relative_alt ≥ 95 % of `height` and ≤ `height` + 1 m
    before wall `before` (the example's next step)."""
    climb = [p[4] for p in seen.position if p[0] <= before]
    top = max(climb, default=0.0)
    summary_modes = {h[3] for h in tel.heartbeats if h[2] and h[0] <= before}
    ok = mode in summary_modes and 0.95 * height <= top <= height + 1.0
    return Check(
        f"take-off to {height:g} m",
        ok,
        f"armed in modes {sorted(summary_modes)} (asked {mode}); relative_alt up to {top:.2f} m before the "
        f"next step ({0.95 * height:.2f} … {height + 1.0:.2f})",
    ), round(top, 2)


def returns_home(seen, tel, rtl_at):
    """After the example's RTL at wall `rtl_at`: RTL (6) shown and the vehicle brought home (its last
    position, once landed, within ARRIVED_M of HOME)."""
    after = seen.window(rtl_at, math.inf)
    home = [horizontal_m(p[2:4], HOME[:2]) for p in after]
    checks = [
        Check(
            "RTL",
            mode_seen_after(tel, RTL, rtl_at),
            f"modes after the RTL asked: {sorted({h[3] for h in tel.heartbeats if h[0] >= rtl_at})}",
        )
    ]
    checks.append(
        Check(
            "returns home",
            bool(home) and home[-1] <= ARRIVED_M,
            f"{home[0]:.0f} m from home when RTL was asked, closest {min(home):.1f} m, last {home[-1]:.1f} m"
            if home
            else "no GLOBAL_POSITION_INT after the RTL",
        )
    )
    return checks, {
        "home_at_rtl_m": round(home[0], 1) if home else None,
        "home_final_m": round(home[-1], 1) if home else None,
    }




def upload_check(seen):
    """The mission upload: MISSION_COUNT n received, the n items asked and received, MISSION_ACK
    ACCEPTED sent after them."""
    n = seen.counts_in[-1] if seen.counts_in else None
    accepted = [a for a in seen.mission_acks if a[1] == 0]
    ok = n is not None and len(seen.items_in) >= n and len(accepted) >= 2  # one for MISSION_CLEAR_ALL
    texts = sorted({t for _, _, t in seen.texts if re.search("timeout|plan|mission", t, re.I)})
    return Check(
        "mission uploaded",
        ok,
        f"MISSION_COUNT {n} received; the vehicle asked with {seen.requests or 'nothing'} (DroneKit answers "
        f"MISSION_REQUEST only); {len(seen.items_in)} items received; MISSION_ACK "
        f"{[a[1] for a in seen.mission_acks]}; {texts}",
    ), n


