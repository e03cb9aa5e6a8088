"""PX4's follow-target tester (PX4-Autopilot test/mavsdk_tests/autopilot_tester_follow_me.cpp/.h):
a simulated target walking north at 2 m/s, streamed to the vehicle through MAVSDK's FollowMe
plugin, and the three flights the cases use (straight line, velocity only, stick adjustment).

The target's noise is Gaussian and re-seeded from the update count, as PX4's is (the generator is
Python's, so the samples differ from PX4's): 1 m on the global position sent, 0.1 m/s on the
velocity.
"""
from __future__ import annotations

import math
import random
import warnings

from .autopilot_tester import NAN, finite, outcome
from .autopilot_tester_raw import AutopilotTesterRaw
from .checks import check
from .geometry import CoordinateTransformation, diff, norm

with warnings.catch_warnings():
    warnings.simplefilter("ignore", FutureWarning)
    from mavsdk.follow_me import Config, TargetLocation

TARGET_SPEED_M_S = 2.0
POSITION_NOISE_M, VELOCITY_NOISE_M_S = 1.0, 0.1
# How fast the follow distance [m/s], height [m/s] and angle [rad/s] move under full stick
# (FlightTaskAutoFollowTarget's constants, as PX4's test copies them).
DISTANCE_ADJUST_SPEED, HEIGHT_ADJUST_SPEED, ANGLE_ADJUST_SPEED = 2.0, 1.5, 1.5


def default_config() -> Config:
    """MAVSDK's FollowMe::Config defaults."""
    return Config(8.0, 8.0, 0.1, Config.FollowAltitudeMode.CONSTANT, 8.0, 180.0)


class FollowTargetSimulator:
    """A target moving north on a straight line from `start_ned`, about the stored `home`."""

    def __init__(self, start_ned, home) -> None:
        self.position = list(start_ned)
        self.velocity = [0.0, 0.0, 0.0]
        self.home = home
        self.updates = 0

    def update(self, dt_s: float) -> None:
        self.velocity = [TARGET_SPEED_M_S, 0.0, self.velocity[2]]
        self.position = [p + v * dt_s for p, v in zip(self.position, self.velocity)]
        self.updates += 1

    def _noisy(self, values, sigma):
        rng = random.Random(self.updates)
        return [v + rng.gauss(0.0, sigma) for v in values]

    def position_global(self, noisy: bool):
        north, east, down = self._noisy(self.position, POSITION_NOISE_M) if noisy else self.position
        check(finite(self.home[0], self.home[1]), "follow target: home stored", self.home)
        lat, lon = CoordinateTransformation(self.home[0], self.home[1]).global_from_local(north, east)
        return lat, lon, down + self.home[2]

    def velocity_noisy(self):
        return self._noisy(self.velocity, VELOCITY_NOISE_M_S)

    @staticmethod
    def check_follow_angle(config, drone_ned, target_ned, tolerance: float) -> None:
        """The vehicle must sit at the configured angle (from the target's course, north) and distance."""
        offset = (drone_ned[0] - target_ned[0], drone_ned[1] - target_ned[1])
        angle = math.radians(config.follow_angle_deg)
        expected = (config.follow_distance_m * math.cos(angle), config.follow_distance_m * math.sin(angle))
        check(abs(offset[0] - expected[0]) < tolerance,
              f"follow angle {config.follow_angle_deg} deg: north offset within {tolerance} m of {expected[0]:.1f}",
              offset[0])
        check(abs(offset[1] - expected[1]) < tolerance,
              f"follow angle {config.follow_angle_deg} deg: east offset within {tolerance} m of {expected[1]:.1f}",
              offset[1])


class AutopilotTesterFollowMe(AutopilotTesterRaw):
    async def _follow(self, call, label) -> None:
        result = await outcome(call)
        check(result == "SUCCESS", f"follow_me {label} == Success", result)

    async def straight_line_test(self, stream_velocity: bool) -> None:
        rate_hz, tolerance, height = 1, 11.0, 10.0
        target = FollowTargetSimulator(self.position_ned(), self.get_home())
        config = Config(height, 8.0, 0.1, Config.FollowAltitudeMode.CONSTANT, 15.0, 0.0)
        follow = self.drone.follow_me
        await self.sleep_for(1)
        await self._follow(follow.start(), "start()")
        await self.sleep_for(1)
        moving = checking = False
        # (update index, follow angle) where the configuration changes; checks run after the
        # target has moved ten updates with the new angle.
        angle_changes = {5: 180.0, 20: 0.0, 35: 45.0, 55: -45.0}
        checked_from = {15: True, 30: True, 45: True, 65: True}
        for k in range(75 * rate_hz):
            self.step = f"following the target, update {k}/75"
            truth = list(target.position)
            here = self.position_ned()
            distance = norm(diff(truth, here))
            if k in angle_changes:
                checking = False
                config.follow_angle_deg = angle_changes[k]
                await self._follow(follow.set_config(config), f"set_config(angle {config.follow_angle_deg})")
            elif k in checked_from:
                checking = True
            if 5 < k < 15:
                moving = True  # from the update after the first change on, for good
            if moving:
                target.update(1.0 / rate_hz)
            if checking:
                self.check_current_altitude(height)
                check(distance <= config.follow_distance_m + tolerance,
                      f"distance to target <= {config.follow_distance_m + tolerance} m", distance)
                check(distance >= config.follow_distance_m - tolerance,
                      f"distance to target >= {config.follow_distance_m - tolerance} m", distance)
                target.check_follow_angle(config, here, truth, tolerance)
            lat, lon, alt = target.position_global(noisy=True)
            vel = target.velocity_noisy() if stream_velocity else [NAN] * 3
            await self._follow(follow.set_target_location(TargetLocation(lat, lon, alt, *vel)),
                               "set_target_location()")
            await self.sleep_for(1.0 / rate_hz)
        await self._follow(follow.stop(), "stop()")

    async def stream_velocity_only(self) -> None:
        config = default_config()
        config.follow_angle_deg = 180.0
        follow = self.drone.follow_me
        await self._follow(follow.set_config(config), "set_config()")
        await self.sleep_for(1)
        await self._follow(follow.start(), "start()")
        await self.sleep_for(1)
        start = self.position_ned()
        for k in range(15):
            self.step = f"streaming target velocity only, {k}/15"
            await self._follow(follow.set_target_location(TargetLocation(NAN, NAN, NAN, 2.0, 1.0, 0.5)),
                               "set_target_location(velocity only)")
            await self.sleep_for(1)
        moved = norm(diff(start, self.position_ned()))
        check(moved < 4.0, "moved less than 4 m while the target sent velocity only", moved)

    async def rc_adjustment_test(self) -> None:
        rate, height, angle_deg, distance_m = 50, 10.0, 0.0, 10.0
        target = FollowTargetSimulator(self.position_ned(), self.get_home())
        follow, sticks = self.drone.follow_me, self.drone.manual_control
        config = default_config()
        config.follow_height_m, config.follow_distance_m, config.follow_angle_deg = height, distance_m, angle_deg
        await self._follow(follow.set_config(config), "set_config()")
        lat, lon, alt = target.position_global(noisy=False)
        location = TargetLocation(lat, lon, alt, NAN, NAN, NAN)
        target_pos = self.position_ned()
        await self._follow(follow.start(), "start()")
        initial = self.position_ned()

        async def stick(x, y, z):
            result = await outcome(sticks.set_manual_control_input(x, y, z, 0.0))
            check(result == "SUCCESS", f"set_manual_control_input({x}, {y}, {z}, 0) == Success", result)
        for i in range(60 * rate + 1):
            self.step = f"stick adjustment of the follow, {i / rate:.1f} s of 60"
            await outcome(follow.set_target_location(location))
            here = self.position_ned()
            if i < 5 * rate:
                await stick(0.0, 0.0, 0.5)
            elif i == 5 * rate:
                initial = self.position_ned()
            elif i < 8 * rate:
                await stick(0.0, 0.0, 1.0)
            elif i < 10 * rate:
                await stick(0.0, 0.0, 0.5)
            elif i == 10 * rate:
                climbed = -(here[2] - initial[2])
                check(climbed > HEIGHT_ADJUST_SPEED * 3 * 0.5, "throttle up 3 s raised the follow height by > 2.25 m",
                      climbed)
            elif i < 13 * rate:
                await stick(1.0, 0.0, 0.5)
            elif i < 15 * rate:
                await stick(0.0, 0.0, 0.5)
            elif i == 15 * rate:
                d = math.hypot(here[0] - target_pos[0], here[1] - target_pos[1])
                check(d > distance_m + DISTANCE_ADJUST_SPEED * 3 * 0.5, "pitch forward 3 s: follow distance > 13 m", d)
            elif i < 18 * rate:
                await stick(0.0, 1.0, 0.5)
            elif i < 20 * rate:
                await stick(0.0, 0.0, 0.5)
            elif i == 20 * rate:
                a = math.atan2(here[1] - target_pos[1], here[0] - target_pos[0])
                check(a > math.radians(angle_deg) + ANGLE_ADJUST_SPEED * 3 * 0.5,
                      "roll right 3 s: follow angle > 2.25 rad", a)
            await self.sleep_for(1.0 / rate)
