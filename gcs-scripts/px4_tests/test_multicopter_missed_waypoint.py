"""PX4's test_multicopter_missed_waypoint.cpp (PX4-Autopilot test/mavsdk_tests): a raw mission due
north (take-off to 20 m, waypoints at 60, 100 and 140 m with a 2 m acceptance radius, land at 140 m)
with NAV_ACC_RAD 2, NAV_MC_ALT_RAD 0.8, MPC_XY_VEL_MAX 12, MPC_XY_CRUISE 10, MPC_Z_V_AUTO_DN 1.
While item 2 is current and the vehicle is 6 to 12 m short of it at > 5 m/s and on altitude, home
is moved 5 m down (DO_SET_HOME): the mission altitude jumps 5 m and the vehicle flies past the
waypoint above the altitude band. It must then come back to the waypoint (within 2 m and 0.8 m)
and go on to item 3, never flying away from it (> 0.3 m/s outwards for 10 s and 10 m) in between,
all within 180 s of wall time; then finish the mission (60 s) and disarm (60 s).

The samples are GLOBAL_POSITION_INT (asked for at 50 Hz), each paired with the newest
HOME_POSITION and MISSION_CURRENT, read through MAVSDK's MavlinkDirect plugin.
"""
import asyncio
import math
import time
import warnings

from . import CONNECTION_URL, case
from .autopilot_tester import outcome, value_of
from .autopilot_tester_raw import (
    MAV_CMD_DO_SET_HOME,
    MAV_CMD_NAV_LAND,
    MAV_CMD_NAV_TAKEOFF,
    MAV_CMD_NAV_WAYPOINT,
    MAV_CMD_REQUEST_MESSAGE,
    MAV_FRAME_GLOBAL_INT,
    MAV_FRAME_GLOBAL_RELATIVE_ALT,
    MAVLINK_MSG_ID_HOME_POSITION,
    AutopilotTesterRaw,
    raw_item,
)
from .checks import require
from .geometry import CoordinateTransformation

with warnings.catch_warnings():
    warnings.simplefilter("ignore", FutureWarning)
    from mavsdk.telemetry import FlightMode

PARAMS = (("NAV_ACC_RAD", 2.0), ("NAV_MC_ALT_RAD", 0.8), ("MPC_XY_VEL_MAX", 12.0), ("MPC_XY_CRUISE", 10.0),
          ("MPC_Z_V_AUTO_DN", 1.0))


class MissedWaypointRecoveryTester(AutopilotTesterRaw):
    async def set_checked_float(self, name: str, value: float) -> None:
        result = await outcome(self.drone.param.set_param_float(name, value))
        require(result == "SUCCESS", f"set_param_float({name}, {value}) == Success", result)
        result, got = await value_of(self.drone.param.get_param_float(name))
        require(result == "SUCCESS", f"get_param_float({name}) == Success", result)
        require(abs(got - value) < 0.01, f"{name} reads back {value}", got)

    def start_sampling(self) -> list:
        state = {"home": None, "seq": -1}
        samples: list = []

        async def homes():
            async for m in self.messages("HOME_POSITION"):
                if m["sysid"] == 1:
                    state["home"] = m

        async def current():
            async for m in self.messages("MISSION_CURRENT"):
                if m["sysid"] == 1:
                    state["seq"] = m["seq"]

        async def positions():
            async for m in self.messages("GLOBAL_POSITION_INT"):
                if m["sysid"] == 1:
                    samples.append((m, state["home"], state["seq"]))
        for coro in (homes(), current(), positions()):
            self.background(coro)
        return samples

    async def run(self, url: str) -> None:
        await self.connect(url)
        await self.wait_until_ready()
        for name, value in PARAMS:
            await self.set_checked_float(name, value)
        result = await outcome(self.drone.telemetry.set_rate_position(50.0))
        require(result == "SUCCESS", "set_rate_position(50 Hz) == Success", result)
        samples = self.start_sampling()
        self.latest("flight_mode")
        home = await self.get_home_position()
        ct = self.get_coordinate_transformation()

        def item(seq, command, north, altitude):
            lat, lon = ct.global_from_local(north, 0.0)
            return raw_item(seq, command, MAV_FRAME_GLOBAL_RELATIVE_ALT, 0.0, 2.0 if command == MAV_CMD_NAV_WAYPOINT
                            else 0.0, round(lat * 1e7), round(lon * 1e7), altitude, 1 if seq == 0 else 0)
        mission = [item(0, MAV_CMD_NAV_TAKEOFF, 0.0, 20.0), item(1, MAV_CMD_NAV_WAYPOINT, 60.0, 20.0),
                   item(2, MAV_CMD_NAV_WAYPOINT, 100.0, 20.0), item(3, MAV_CMD_NAV_WAYPOINT, 140.0, 20.0),
                   item(4, MAV_CMD_NAV_LAND, 140.0, 5.0)]
        frame = CoordinateTransformation(mission[2].x / 1e7, mission[2].y / 1e7)
        result = await outcome(self.drone.mission_raw.upload_mission(mission))
        require(result == "SUCCESS", "mission_raw upload_mission() == Success", result)
        await self.sleep_for(1)
        await self.arm()
        result = await outcome(self.drone.mission_raw.start_mission())
        require(result == "SUCCESS", "mission_raw start_mission() == Success", result)

        f = dict(home_change_sent=False, home_change_accepted=None, missed=False, returned=False,
                 accepted_after_return=False, diverged=False)
        target_home_alt = home.get("altitude", math.nan) / 1000.0 - 5.0
        farthest, outward_since, outward_from = 0.0, -1.0, 0.0
        deadline = time.monotonic() + 180
        self.step = "flying the mission towards item 2 (home moves 5 m down on the way)"
        while time.monotonic() < deadline and not f["accepted_after_return"] and not f["diverged"]:
            batch, samples[:] = list(samples), []
            for position, sample_home, seq in batch:
                along, cross = frame.local_from_global(position["lat"] / 1e7, position["lon"] / 1e7)
                if (not f["home_change_sent"] and sample_home is not None and seq == 2 and -12.0 <= along <= -6.0
                        and abs(cross) < 1.0 and position["vx"] > 500
                        and abs(position["alt"] / 1000.0 - (sample_home["altitude"] / 1000.0 + 20.0)) < 0.8):
                    target_home_alt = sample_home["altitude"] / 1000.0 - 5.0
                    f["home_change_sent"] = True
                    answer = await self.command_int(MAV_CMD_DO_SET_HOME, MAV_FRAME_GLOBAL_INT, (0.0,) * 4,
                                                    sample_home["latitude"], sample_home["longitude"], target_home_alt)
                    f["home_change_accepted"] = answer
                    request = (float(MAVLINK_MSG_ID_HOME_POSITION),) + (0.0,) * 6
                    await self.command_long(MAV_CMD_REQUEST_MESSAGE, request)
                    self.step = "home moved 5 m down: waiting for the miss, the return to item 2 and item 3"
                if (f["home_change_accepted"] != "ACCEPTED" or sample_home is None
                        or abs(sample_home["altitude"] / 1000.0 - target_home_alt) >= 0.15):
                    continue
                altitude_error = position["alt"] / 1000.0 - (target_home_alt + 20.0)
                pending = seq == 2 and self.latest("flight_mode") == FlightMode.MISSION
                distance = math.hypot(along, cross)
                if pending and along > 2.1 and abs(altitude_error) > 0.8:
                    f["missed"] = True
                if not f["missed"]:
                    continue
                farthest = max(farthest, distance)
                if farthest > 2.1 and distance <= 2.0 and abs(altitude_error) <= 0.8:
                    f["returned"] = True
                if f["returned"] and seq > 2:
                    f["accepted_after_return"] = True
                radial = ((along * position["vx"] / 100.0 + cross * position["vy"] / 100.0) / distance
                          if distance > 0.01 else 0.0)
                if pending and distance > 2.1 and radial > 0.3 and abs(altitude_error) <= 0.8:
                    t = position["time_boot_ms"] / 1000.0
                    if outward_since < 0.0:
                        outward_since, outward_from = t, distance
                    if t - outward_since >= 10.0 and distance - outward_from >= 10.0:
                        f["diverged"] = True
                else:
                    outward_since = -1.0
            await asyncio.sleep(0.01)

        require(f["home_change_sent"], "home change sent (item 2 current, 6-12 m short, > 5 m/s, on altitude)", f)
        require(f["home_change_accepted"] == "ACCEPTED", "DO_SET_HOME accepted", f)
        require(f["missed"], "waypoint 2 missed after the home change", f)
        require(not f["diverged"], "never flew away from waypoint 2 after missing it", f)
        require(f["returned"], "came back to waypoint 2 (2 m, 0.8 m)", f)
        require(f["accepted_after_return"], "went on to item 3 after coming back", f)
        deadline = time.monotonic() + 60
        finished = False
        while time.monotonic() < deadline and not finished:
            finished = await self.mission_finished(raw=True)
            if not finished:
                await asyncio.sleep(0.05)
        require(finished, "mission finished within 60 s (wall)", self.mission_progress())
        await self.wait_until_disarmed(60)


@case("Multicopter recovers after missing a waypoint during a home-altitude change", "[multicopter][mission]")
async def multicopter_recovers_after_missing_a_waypoint_during_a_home_altitude_change(
        url: str = CONNECTION_URL) -> None:
    await MissedWaypointRecoveryTester().run(url)
