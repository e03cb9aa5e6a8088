"""The DroneKit examples' expectations (run_dronekit_examples.py): each example's checks, from
what its source asks, and `SPECS`, its verdict and run settings."""

import math
import pathlib
import re
import statistics

from dronekit_seen import (
    ARRIVED_M,
    AUTO,
    GUIDED,
    GUIDED_NOGPS,
    HOME,
    LAND,
    MAV_CMD_DO_SET_HOME,
    MAV_CMD_DO_SET_MODE,
    MAV_CMD_DO_SET_ROI,
    MAV_RESULT_ACCEPTED,
    RTL,
    STABILIZE,
    leg_checks,
    mode_seen_after,
    returns_home,
    speed_asked_at,
    takeoff_check,
    upload_check,
)
from tlog_judge import Check, horizontal_m, last_before


def check_simple_goto(tel, seen, summary, out, work):
    """Take-off to 10 m in GUIDED, the two points of the source approached (20 m above home, at the
    3 m/s airspeed, then the 10 m/s groundspeed asked), then RTL home."""
    points = [(-35.361354, 149.165218), (-35.363244, 149.168801)]  # LocationGlobalRelative(…, 20)
    rtl = seen.mode_requests(RTL)
    if len(seen.gotos) < 2 or not rtl:
        return [Check("gotos sent", False, f"{len(seen.gotos)} gotos and {len(rtl)} RTL received")], {}
    (g1, g2), rtl_at = seen.gotos[:2], rtl[0]
    checks = [
        Check(
            "gotos sent",
            all(
                horizontal_m(g[1:3], p) < 1.5 and abs(g[3] - 20) < 0.01 and g[4] == 3 for g, p in zip((g1, g2), points)
            ),
            f"MISSION_ITEM current=2 at {[(round(g[1], 6), round(g[2], 6), g[3], g[4]) for g in (g1, g2)]}"
            " (the source's points, 20 m, frame 3)",
        )
    ]
    takeoff, top = takeoff_check(seen, tel, GUIDED, 10.0, g1[0])
    checks.append(takeoff)
    values = {"takeoff_alt_m": top}
    for n, (goto, end, point) in enumerate(((g1, g2[0], points[0]), (g2, rtl_at, points[1])), 1):
        speed = speed_asked_at(seen, goto[0])
        leg, leg_values = leg_checks(
            f"leg {n}", seen, point, goto[0], end, speed[2] if speed else 10.0, speed[0] if speed else None
        )
        checks += leg
        values[f"leg{n}"] = leg_values
    legs = [p[4] for p in seen.window(g1[0], rtl_at)]
    checks.append(
        Check(
            "legs at 20 m",
            bool(legs) and max(legs) <= 21.0 and max(legs) >= 15.0,
            f"relative_alt {min(legs, default=0):.1f} … {max(legs, default=0):.1f} m on the legs "
            "(climbing to the 20 m asked, never above 21 m)",
        )
    )
    home, home_values = returns_home(seen, tel, rtl_at)
    values.update(home_values)
    return checks + home, values


def check_guided_set_speed_yaw(tel, seen, summary, out, work):
    """Take-off to 5 m in GUIDED and the simple_goto triangle at the 5 m/s asked, each point reached
    (the example waits for 1 % of the leg) before the example's own error."""
    checks = [
        Check(
            "the example's own error",
            "struct.error: required argument is not an integer" in out and "goto_position_target_global_int" in out,
            "goto_position_target_global_int packs aLocation.lat*1e7, a float, into an int32 field: "
            + ("raised" if "struct.error" in out else "not raised"),
        )
    ]
    if len(seen.gotos) < 3:
        return checks + [Check("gotos sent", False, f"{len(seen.gotos)} simple_goto received, 3 expected")], {}
    takeoff, top = takeoff_check(seen, tel, GUIDED, 5.0, seen.gotos[0][0])
    checks.append(takeoff)
    values = {"takeoff_alt_m": top}
    ends = [g[0] for g in seen.gotos[1:3]] + [seen.gotos[2][0] + 1e9]
    reached = len(re.findall(r"^Reached target$", out, re.M))
    for n, (goto, end) in enumerate(zip(seen.gotos[:3], ends), 1):
        end = min(end, max((p[0] for p in seen.position), default=end))
        speed = speed_asked_at(seen, goto[0]) or (goto[0], 1.0, 5.0)
        leg, leg_values = leg_checks(f"leg {n}", seen, goto[1:3], goto[0], end, 5.0, speed[0])
        checks += leg
        values[f"leg{n}"] = leg_values
    checks.append(Check("triangle reached", reached >= 3, f"'Reached target' printed {reached} times (3 legs)"))
    return checks, values


def check_set_attitude_target(tel, seen, summary, out, work):
    """Armed in GUIDED_NOGPS, climbs on thrust 0.7/0.6 to 2.5 m and holds on thrust 0.5 (ArduCopter
    reads thrust as a climb rate: 0.5 holds), the pitch moves (type_mask 0b100) refused as ArduCopter
    refuses them, then LAND."""
    masks = {}
    for _, mask, _, _ in seen.attitude_targets:
        masks[mask] = masks.get(mask, 0) + 1
    land = seen.mode_requests(LAND)
    top = max((p[4] for p in seen.position if not land or p[0] <= land[0]), default=0.0)
    # The moves: the targets leaning the vehicle (pitch ±5°), all with type_mask 0b100.
    leaning = [(w, mask) for w, mask, _, pitch in seen.attitude_targets if abs(pitch) > 1.0]
    moved = seen.window(leaning[0][0], leaning[-1][0] + 1.0) if leaning else []
    fastest = max((p[5] for p in moved), default=0.0)
    checks = [
        Check(
            "armed in GUIDED_NOGPS",
            GUIDED_NOGPS in summary["airborne_modes"],
            f"airborne modes {summary['airborne_modes']}",
        ),
        Check(
            "climbs to 2.5 m and holds",
            2.3 <= top <= 5.0,
            f"relative_alt up to {top:.1f} m before LAND (2.5 m asked; thrust 0.5 holds the height: ≤ 5 m)",
        ),
        Check(
            "pitch moves refused",
            bool(moved) and {m for _, m in leaning} == {4} and fastest <= 0.5,
            f"{len(leaning)} targets leaning ±5° (type_mask {sorted({m for _, m in leaning})}): ground speed up "
            f"to {fastest:.2f} m/s meanwhile (≤ 0.5; 5° for 3 s would reach 2.6 m/s); ArduCopter drops a target "
            "that ignores some body rates but not all",
        ),
        Check("LAND", bool(land) and mode_seen_after(tel, LAND, land[0]), f"LAND asked {len(land)} time(s)"),
    ]
    return checks, {"max_alt_m": round(top, 2), "type_masks": masks, "moves_max_speed_m_s": round(fastest, 2)}


def check_channel_overrides(tel, seen, summary, out, work):
    """The overrides the example sent reach the vehicle and show in its RC_CHANNELS, as ArduCopter
    shows an override for RC_OVERRIDE_TIME (3 s): each RC_CHANNELS within 3 s of an override that
    sets channels is compared with the override then in force (nothing to compare when the last
    override received released them all)."""
    printed = "Channel overrides: {}" in out and "Number of channels:" in out
    checks = [Check("channels printed", printed, "the example printed the channels and its overrides")]
    if not seen.overrides:
        return checks + [Check("overrides sent", False, "no RC_CHANNELS_OVERRIDE received")], {}
    checks.append(
        Check(
            "overrides sent",
            True,
            f"{len(seen.overrides)} of the 7 RC_CHANNELS_OVERRIDE the example sends received (DroneKit's close() "
            "drops what is still queued)",
        )
    )
    compared, matching, last = 0, 0, None
    for wall, chancount, chans in seen.rc:
        override = last_before(seen.overrides, wall)
        if override is None or wall - override[0] > 3.0:
            continue
        asked = {i + 1: v for i, v in enumerate(override[1]) if 0 < v < 65535}
        if asked:
            compared += 1
            matching += all(chans[ch - 1] == v for ch, v in asked.items())
            last = (asked, chancount, [chans[ch - 1] for ch in asked])
    if compared:  # none when the last override received released every channel (all 7 got out)
        checks.append(
            Check(
                "override shown in RC_CHANNELS",
                matching == compared,
                f"{matching} of {compared} RC_CHANNELS within 3 s of an override show it; the last: override "
                f"{last[0]}, RC_CHANNELS {last[1]} channels, {last[2]}",
            )
        )
    return checks, {"overrides_received": len(seen.overrides), "rc_compared": compared, "rc_matching": matching}


def check_create_attribute(tel, seen, summary, out, work):
    """RAW_IMU printed for 5 s through the custom attribute: a vehicle at rest reads about -1 g on
    z, and the magnetometer the field at home (at -35° latitude it points up: z < 0)."""
    lines = re.findall(r"RAW_IMU: time_boot_us=(\d+),xacc=(-?\d+),yacc=(-?\d+),zacc=(-?\d+),.*zmag=(-?\d+)", out)
    zacc = statistics.median(int(z[3]) for z in lines) if lines else 0
    zmag = statistics.median(int(z[4]) for z in lines) if lines else 0
    checks = [
        Check("RAW_IMU printed", len(lines) >= 15, f"{len(lines)} RAW_IMU lines printed in 5 s (4 Hz asked)"),
        Check("at rest: z about -1 g", -1100 <= zacc <= -900, f"median zacc {zacc} mg"),
        Check(
            "magnetometer: the field at home",
            zmag < 0,
            f"median zmag {zmag} mgauss at latitude {HOME[0]}° "
            "(the World Magnetic Model's field points up there: about -531 mgauss)",
        ),
    ]
    return checks, {"raw_imu_lines": len(lines), "zacc_mg": zacc, "zmag_mgauss": zmag}


def check_performance_test(tel, seen, summary, out, work):
    """Every DO_SET_ROI the example sends on each COMMAND_ACK is answered; the intervals it prints."""
    sent = sum(1 for _, c, _ in seen.commands if c == MAV_CMD_DO_SET_ROI)
    acks = [r for _, c, r in seen.acks if c == MAV_CMD_DO_SET_ROI]
    results = {r: acks.count(r) for r in set(acks)}
    intervals = re.findall(r"MaxInterval: ([0-9.e-]+)\tMinInterval: ([0-9.e-]+)", out)
    worst = float(intervals[-1][0]) if intervals else math.inf
    checks = [
        Check(
            "every DO_SET_ROI answered",
            sent >= 100 and len(acks) >= sent - 1,
            f"{sent} DO_SET_ROI received, {len(acks)} COMMAND_ACK for it",
        ),
        Check("round trips printed", worst < 1.0, f"last MaxInterval printed {worst:.4f} s (< 1 s)"),
        Check(
            "DO_SET_ROI accepted",
            bool(acks) and set(acks) == {MAV_RESULT_ACCEPTED},
            f"results {results} (ArduCopter 4.5: ACCEPTED 0; a ROI at 0, 0, 0 clears the ROI)",
        ),
    ]
    return checks, {"roi_sent": sent, "roi_acks": len(acks), "roi_results": results, "max_interval_s": worst}


def check_vehicle_state(tel, seen, summary, out, work):
    """The attributes printed; home read from mission item 0 (a mission download), set to the same
    place 222 m AMSL (DO_SET_HOME) and read back; GUIDED and STABILIZE set while disarmed; then the
    parameters THR_MIN/THR_MID, which ArduCopter 4.x no longer has: DroneKit raises KeyError."""
    printed = all(s in out for s in ("Is Armable?: True", "EKF OK?: True", "GPS: GPSInfo:fix=3", "Mode: "))
    home = re.search(r"\n Home location: (LocationGlobal:[^\n]*)", out)
    back = re.search(r"from vehicle - altitude should be 222\): (LocationGlobal:[^\n]*)", out)
    version = re.search(r"Autopilot Firmware version: APM:Copter-([0-9.]+)", out)
    set_home = [r for _, c, r in seen.acks if c == MAV_CMD_DO_SET_HOME]
    modes = {}
    for wall, command, params in seen.commands:
        if command == MAV_CMD_DO_SET_MODE:
            answer = next((r for w, c, r in seen.acks if c == command and w >= wall), None)
            modes.setdefault(int(params[1]), answer)
    texts = [t for _, _, t in seen.texts if t.startswith("Mode change")]
    checks = [
        Check("attributes printed", printed, "is_armable, ekf_ok, a 3D fix and the mode printed"),
        Check(
            "home location downloaded",
            home is not None,
            f"printed {home.group(1)}"
            if home
            else f"the vehicle's MISSION_COUNT {seen.counts_out} (ArduCopter: 1, item 0 home), items sent "
            f"{seen.items_out}, MISSION_ACK {[a[1] for a in seen.mission_acks]}",
        ),
        Check(
            "new home read back",
            back is not None and back.group(1).endswith("alt=222.0"),
            f"DO_SET_HOME answered {set_home}; item 0 downloaded after it: {back.group(1) if back else None}",
        ),
        Check(
            "firmware version 4.x",
            version is not None and version.group(1).startswith("4."),
            f"printed APM:Copter-{version.group(1) if version else '?'} (ArduCopter 4.5: APM:Copter-4.5.x)",
        ),
        Check("GUIDED set", modes.get(GUIDED) == MAV_RESULT_ACCEPTED, f"DO_SET_MODE answers by mode {modes}"),
        Check(
            "STABILIZE set",
            modes.get(STABILIZE) == MAV_RESULT_ACCEPTED,
            f"DO_SET_MODE answers by mode {modes} {texts} (ArduCopter changes mode freely while disarmed)",
        ),
        Check(
            "stops at THR_MIN as against ArduCopter 4.5",
            "KeyError: 'THR_MIN'" in out,
            "KeyError: 'THR_MIN' raised" if "KeyError: 'THR_MIN'" in out else "no KeyError: 'THR_MIN'",
        ),
    ]
    return checks, {"mission_count": seen.counts_out[0] if seen.counts_out else None, "set_mode": modes}




def check_mission_basic(tel, seen, summary, out, work):
    """The square mission uploaded, flown in AUTO from the air (the example takes off in GUIDED):
    waypoints 1 and 2 reached, the skip to 5, then RTL home."""
    upload, n = upload_check(seen)
    checks = [
        upload,
        Check("AUTO flown", AUTO in summary["airborne_modes"], f"airborne modes {summary['airborne_modes']}"),
    ]
    corners = [seen.items_in.get(seq) for seq in (1, 2)]
    for seq, item in zip((1, 2), corners):
        close = min((horizontal_m(p[2:4], item[1:3]) for p in seen.position), default=math.inf) if item else math.inf
        checks.append(
            Check(
                f"waypoint {seq} reached",
                close <= ARRIVED_M,
                f"closest {close:.1f} m to item {seq}" if item else f"no item {seq} uploaded",
            )
        )
    rtl = seen.mode_requests(RTL)
    checks.append(Check("skipped to waypoint 5", "Exit 'standard' mission" in out, "the example saw waypoint 5 next"))
    home, values = returns_home(seen, tel, rtl[0]) if rtl else ([Check("RTL", False, "no RTL asked")], {})
    return checks + home, {"mission_count": n, **values}


def check_mission_import_export(tel, seen, summary, out, work):
    """mpmission.txt uploaded, downloaded and written back as exportedmission.txt: the same items."""
    upload, n = upload_check(seen)
    exported = pathlib.Path(work, "exportedmission.txt")
    same, seen_text = False, "no exportedmission.txt written"
    if exported.exists():
        rows = [line.split("\t") for line in pathlib.Path(work, "mpmission.txt").read_text().splitlines()[2:]]
        back = [line.split("\t") for line in exported.read_text().splitlines()[2:]]
        same = len(rows) == len(back) and all(
            a[3] == b[3]
            and all(abs(float(x) - float(y)) < 2e-6 * max(1.0, abs(float(x))) for x, y in zip(a[8:11], b[8:11]))
            for a, b in zip(rows, back)
        )
        seen_text = f"{len(back)} items exported for {len(rows)} imported (after the home line)"
    return [upload, Check("mission downloaded as uploaded", same, seen_text)], {"mission_count": n}


# What each example must do besides resting on the ground before arming and never disarming in the
# air. Keys: speedup (overrides the command line's), timeout_s (wall; then Ctrl-C), exit (the
# exit code expected, "0" unless said), expect ("works" | "expected refusal" | "pending"), why, lands
# and disarms (the example ends on the ground, disarmed), settle_s (simulated seconds the vehicle is
# watched after the example while it returns or lands), linger_s (wall seconds the vehicle keeps
# running after the example), check (→ checks, judged values), pending ({check: why} the checks
# waiting for a vehicle feature), gaps ({check: why}: a works example's secondary checks the
# vehicle does not meet yet).


SPECS = {
    "simple_goto": {"lands": True, "disarms": True, "settle_s": 200, "check": check_simple_goto},
    "guided_set_speed_yaw": {
        "expect": "expected refusal",
        "exit": "1",
        "why": (
            "the example itself fails under Python 3 at its first goto_position_target_global_int: it packs "
            "aLocation.lat*1e7, a float, into SET_POSITION_TARGET_GLOBAL_INT's int32 lat_int, and pymavlink's "
            "struct.pack raises struct.error before anything is sent, whatever the autopilot; judged: the take-off "
            "to 5 m and the simple_goto triangle at the 5 m/s asked, flown before it"
        ),
        "check": check_guided_set_speed_yaw,
    },
    "set_attitude_target": {
        "lands": True,
        "disarms": True,
        "settle_s": 120,
        "check": check_set_attitude_target,
    },
    "channel_overrides": {
        "linger_s": 1.5,
        "check": check_channel_overrides,
    },
    "create_attribute": {
        "check": check_create_attribute,
    },
    "performance_test": {
        "check": check_performance_test,
        "gaps": {
            "DO_SET_ROI accepted": (
                "the vehicle answers MAV_CMD_DO_SET_ROI (201) with UNSUPPORTED; ArduCopter 4.5 accepts it "
                "(a ROI at 0, 0, 0 clears the ROI, any other sets where the nose points)"
            ),
        },
    },
    "vehicle_state": {
        "expect": "expected refusal",
        "exit": "1",
        "why": (
            "after reading and setting the vehicle's state it reads the parameter THR_MIN, which ArduCopter 4.x "
            "no longer has (MOT_SPIN_MIN and MOT_THST_HOVER replaced THR_MIN and THR_MID): DroneKit raises "
            "KeyError: 'THR_MIN' against ArduCopter 4.5 as here"
        ),
        "check": check_vehicle_state,
    },
    "mission_basic": {"lands": True, "disarms": True, "settle_s": 200, "check": check_mission_basic},
    "mission_import_export": {"check": check_mission_import_export},
}


