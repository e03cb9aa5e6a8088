"""PX4's Goto-mode tester and the parts of its loiter tester it builds on (PX4-Autopilot
test/mavsdk_tests/autopilot_tester_goto.cpp/.h and autopilot_tester_loiter.cpp/.h): DO_REPOSITION
sent as COMMAND_INT to a point given in metres from home (altitude above the stored ground-truth
home), the navigation state read from HEARTBEAT.custom_mode, and trajectory checks on the
estimated local position sampled at 10 Hz.

As in PX4, waits on a reached point and on a navigation state count wall time; the trajectory
checks last for vehicle time.
"""
from __future__ import annotations

import asyncio
import math
import time

from .autopilot_tester import NAN, log, outcome
from .autopilot_tester_raw import MAV_CMD_DO_REPOSITION, MAV_FRAME_GLOBAL_INT, AutopilotTesterRaw
from .checks import check, require

INT32_MAX = 2**31 - 1
POSITION_RATE_HZ = 10.0
#: px4_custom_mode: main mode AUTO, its sub modes LOITER (Hold) and GOTO.
PX4_MAIN_MODE_AUTO, PX4_SUB_MODE_AUTO_LOITER, PX4_SUB_MODE_GOTO = 4, 3, 21


def horizontal_distance(a, b) -> float:
    return math.hypot(a[0] - b[0], a[1] - b[1])


class AutopilotTesterGoto(AutopilotTesterRaw):
    def __init__(self) -> None:
        super().__init__()
        self.custom_mode = 0
        self._heartbeats = None

    # --- the loiter tester's part ---------------------------------------------------------------
    async def command_reposition(self, target, rel_alt_m: float, change_mode: bool = True) -> None:
        lat, lon = self.get_coordinate_transformation().global_from_local(*target)
        z = self.get_home()[2] + rel_alt_m
        params = (-1.0, 1.0 if change_mode else 0.0, 0.0, NAN)
        result = await self.command_int(MAV_CMD_DO_REPOSITION, MAV_FRAME_GLOBAL_INT, params, int(lat * 1e7),
                                        int(lon * 1e7), z)
        log(f"DO_REPOSITION to {target} at {rel_alt_m} m: {result}")

    async def command_hold_here(self) -> None:
        result = await self.command_int(MAV_CMD_DO_REPOSITION, MAV_FRAME_GLOBAL_INT, (-1.0, 1.0, 0.0, NAN),
                                        INT32_MAX, INT32_MAX, NAN)
        log(f"DO_REPOSITION hold here: {result}")

    def current_local_position(self):
        here = self.position_ned()
        return here[0], here[1]

    async def _samples(self, on_sample, seconds: float) -> None:
        """Calls `on_sample(north, east, sample)` for every local position during `seconds` of vehicle time."""
        await outcome(self.drone.telemetry.set_rate_position_velocity_ned(POSITION_RATE_HZ))

        async def follow():
            async for pv in self.drone.telemetry.position_velocity_ned():
                on_sample(pv.position.north_m, pv.position.east_m, pv)
        task = asyncio.ensure_future(follow())
        await self.sleep_for(seconds)
        task.cancel()

    async def check_stays_within(self, centre, max_radius_m: float, seconds: float) -> None:
        self.step = f"staying within {max_radius_m} m of {centre} for {seconds} s"
        label = f"stays within {max_radius_m} m of {tuple(round(c, 1) for c in centre)}"
        await self._samples(lambda n, e, _: check(horizontal_distance((n, e), centre) <= max_radius_m, label,
                                                  horizontal_distance((n, e), centre), "max"), seconds)

    async def check_never_reaches(self, point, min_dist_m: float, seconds: float) -> None:
        self.step = f"keeping {min_dist_m:.1f} m from {point} for {seconds} s"
        label = f"keeps at least {min_dist_m:.1f} m from {tuple(round(c, 1) for c in point)}"
        await self._samples(lambda n, e, _: check(horizontal_distance((n, e), point) >= min_dist_m, label,
                                                  horizontal_distance((n, e), point), "min"), seconds)

    # --- the Goto tester's own --------------------------------------------------------------------
    async def wait_until_nav_state(self, main_mode: int, sub_mode: int, timeout_s: float) -> None:
        self.step = f"waiting {timeout_s} s for navigation state {main_mode}/{sub_mode}"
        if self._heartbeats is None:
            async def heartbeats():
                async for hb in self.messages("HEARTBEAT"):
                    if hb["sysid"] == 1:
                        self.custom_mode = int(hb.get("custom_mode", 0))
            self._heartbeats = self.background(heartbeats())

        def matches():
            return (self.custom_mode >> 16) & 0xFF == main_mode and (self.custom_mode >> 24) & 0xFF == sub_mode
        deadline = time.monotonic() + timeout_s
        while not matches() and time.monotonic() < deadline:
            await asyncio.sleep(0.02)
        require(matches(), f"navigation state main {main_mode} sub {sub_mode} within {timeout_s} s",
                f"main {(self.custom_mode >> 16) & 0xFF} sub {(self.custom_mode >> 24) & 0xFF}")

    async def wait_until_reaches(self, target, radius_m: float, timeout_s: float) -> None:
        self.step = f"flying to {target} (within {radius_m} m, {timeout_s} s)"
        await outcome(self.drone.telemetry.set_rate_position_velocity_ned(POSITION_RATE_HZ))
        closest = [math.inf]

        async def follow():
            async for pv in self.drone.telemetry.position_velocity_ned():
                d = horizontal_distance((pv.position.north_m, pv.position.east_m), target)
                closest[0] = min(closest[0], d)
                if d <= radius_m:
                    return
        try:
            await asyncio.wait_for(follow(), timeout_s)
        except asyncio.TimeoutError:
            require(False, f"reached {target} within {radius_m} m in {timeout_s} s (wall)", closest[0])
        log("Reached Goto target")

    async def change_speed(self, speed_m_s: float) -> None:
        result = await outcome(self.drone.action.set_current_speed(speed_m_s))
        require(result == "SUCCESS", f"set_current_speed({speed_m_s}) == Success", result)

    async def check_max_horizontal_speed(self, max_speed: float, seconds: float) -> None:
        self.step = f"horizontal speed at most {max_speed} m/s for {seconds} s"
        def speed(pv) -> float:
            return math.hypot(pv.velocity.north_m_s, pv.velocity.east_m_s)
        await self._samples(lambda n, e, pv: check(speed(pv) <= max_speed, f"horizontal speed <= {max_speed} m/s",
                                                   speed(pv), "max"), seconds)
