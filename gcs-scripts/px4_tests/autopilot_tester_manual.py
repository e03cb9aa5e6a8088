"""The hand-flown and attitude-setpoint flights of PX4's AutopilotTester (fly_forward_in_posctl,
fly_forward_in_altctl, fly_forward_in_offboard_attitude in PX4-Autopilot's
test/mavsdk_tests/autopilot_tester.cpp), kept apart from autopilot_tester.py for its length.

Sticks go out at 50 Hz of vehicle time as MANUAL_CONTROL (x forward, y right, z throttle 0..1,
r yaw); attitude setpoints at 50 Hz through MAVSDK's offboard plugin.
"""
from __future__ import annotations

import warnings

from .autopilot_tester import AutopilotTester, outcome
from .checks import check

with warnings.catch_warnings():
    warnings.simplefilter("ignore", FutureWarning)
    from mavsdk.offboard import Attitude

STICK_RATE_HZ = 50


class AutopilotTesterManual(AutopilotTester):
    """AutopilotTester with the stick and attitude flights."""

    async def sticks(self, seconds: float, x: float, y: float, z: float, r: float, stop_on_ground=False):
        """Sends the stick position for `seconds` of vehicle time at 50 Hz; with
        `stop_on_ground`, stops as soon as the vehicle reports it is not in the air."""
        for _ in range(round(seconds * STICK_RATE_HZ)):
            result = await outcome(self.drone.manual_control.set_manual_control_input(x, y, z, r))
            check(result == "SUCCESS", f"set_manual_control_input({x}, {y}, {z}, {r}) == Success", result)
            await self.sleep_for(1.0 / STICK_RATE_HZ)
            if stop_on_ground and not self.latest("in_air"):
                break

    async def fly_forward(self, start_mode, centre_after_arm: bool) -> None:
        """The shared sequence: centred sticks around the mode switch, home stored, ready, armed,
        5 s full throttle, 10 s half forward stick, then zero throttle until on the ground (60 s
        at most). Altitude control also centres the sticks for a second after arming."""
        self.step = "sticks centred before the mode switch"
        await self.sticks(1, 0.0, 0.0, 0.5, 0.0)
        result = await outcome(start_mode())
        check(result == "SUCCESS", f"{start_mode.__name__}() == Success", result)
        await self.sticks(1, 0.0, 0.0, 0.5, 0.0)
        await self.store_home()
        await self.sticks(1, 0.0, 0.0, 0.5, 0.0)
        await self.wait_until_ready()
        await self.sticks(1, 0.0, 0.0, 0.5, 0.0)
        await self.arm()
        if centre_after_arm:
            await self.sticks(1, 0.0, 0.0, 0.5, 0.0)
        self.step = "climbing on full throttle for 5 s"
        await self.sticks(5, 0.0, 0.0, 1.0, 0.0)
        self.step = "flying forward for 10 s"
        await self.sticks(10, 0.5, 0.0, 0.5, 0.0)
        self.step = "descending on zero throttle"
        self.latest("in_air")
        await self.sticks(60, 0.0, 0.0, 0.0, 0.0, stop_on_ground=True)

    async def fly_forward_in_posctl(self) -> None:
        await self.fly_forward(self.drone.manual_control.start_position_control, centre_after_arm=False)

    async def fly_forward_in_altctl(self) -> None:
        await self.fly_forward(self.drone.manual_control.start_altitude_control, centre_after_arm=True)

    async def fly_forward_in_offboard_attitude(self) -> None:
        offboard = self.drone.offboard
        self._watch("raw_gps")

        def ellipsoid():
            gps = self.latest("raw_gps")
            return gps.altitude_ellipsoid_m if gps is not None else 0.0

        def level_with_gps():
            att = self.latest("attitude_euler")
            return ellipsoid() > 0 and att is not None and abs(att.roll_deg) < 5 and abs(att.pitch_deg) < 5
        check(await self.poll(level_with_gps, 20), "raw GPS altitude_ellipsoid_m > 0 and level within 20 s",
              f"altitude_ellipsoid_m={ellipsoid()}")
        start = ellipsoid()
        attitude = Attitude(0.0, 0.0, 0.0, 0.0)
        await outcome(offboard.set_attitude(attitude))
        await self.start_offboard_with_retry(lambda: outcome(offboard.set_attitude(attitude)))
        check(await self.poll(self._armable, 20), "health.is_armable within 20 s", self._health_text())
        await self.arm()

        async def send(att, label):
            result = await outcome(offboard.set_attitude(att))
            check(result == "SUCCESS", f"set_attitude() == Success while {label}", result)
            await self.sleep_for(0.02)
        attitude = Attitude(0.0, 0.0, 0.0, 0.8)
        while ellipsoid() - start < 10.0:  # PX4 climbs until GPS shows 10 m, without a time limit
            self.step = f"climbing on 0.8 thrust until GPS ellipsoid altitude is 10 m up ({ellipsoid() - start:.2f})"
            await send(attitude, "climbing")
        self.step = "pitching forward"
        attitude = Attitude(0.0, -20.0, 0.0, 0.8)
        for _ in range(3 * 50):
            await send(attitude, "flying forward")
        est = self.latest("attitude_euler")
        check(abs(attitude.roll_deg - est.roll_deg) < 5, "roll within 5 deg of the 0 deg set", est.roll_deg)
        check(abs(attitude.pitch_deg - est.pitch_deg) < 5, "pitch within 5 deg of the -20 deg set", est.pitch_deg)
        self.step = "descending at 0.4 thrust"
        attitude = Attitude(0.0, 0.0, 0.0, 0.4)
        for _ in range(6 * 50):
            await send(attitude, "descending")
        result = await outcome(offboard.set_attitude(Attitude(0.0, 0.0, 0.0, 0.0)))
        check(result == "SUCCESS", "set_attitude(thrust 0) == Success", result)
