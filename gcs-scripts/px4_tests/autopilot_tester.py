"""The tester every ported case drives: PX4's AutopilotTester (test/mavsdk_tests/autopilot_tester.cpp
and .h in PX4-Autopilot) as an async class over MAVSDK-Python.

MAVSDK's C++ plugins keep the latest value of every telemetry topic; MAVSDK-Python streams them,
so the class keeps one background task per topic in use and reads the newest value from there.
Time-outs follow PX4's clocks: `poll` and `sleep_for` count the vehicle's time (the timestamps of
ATTITUDE_QUATERNION) once it is connected, the host's before; the helpers PX4 writes against the
host clock (std::future waits, steady_clock deadlines) use wall time here too.
"""
from __future__ import annotations

import asyncio
import dataclasses
import inspect
import math
import sys
import time
import warnings

from .checks import approx, check, require
from .geometry import CoordinateTransformation, point_to_line_distance

with warnings.catch_warnings():
    warnings.simplefilter("ignore", FutureWarning)  # mavsdk 3.x announces its rename on import
    from mavsdk import System
    from mavsdk.mission import MissionItem, MissionPlan
    from mavsdk.offboard import PositionNedYaw, VelocityNedYaw
    from mavsdk.telemetry import LandedState

NAN = float("nan")
#: The defaults of the MAVSDK structs PX4's tester reads before anything arrived.
_DEFAULTS = {"ground_truth": None, "home": None, "position": None, "position_velocity_ned": None,
             "raw_gps": None, "health": None, "health_all_ok": False, "armed": False, "in_air": False,
             "landed_state": None, "flight_mode": None, "attitude_euler": None, "attitude_quaternion": None,
             "actuator_output_status": None, "velocity_ned": None}


async def outcome(awaitable) -> str:
    """The result name of a MAVSDK call: "SUCCESS", or the error's result (e.g. "DENIED")."""
    try:
        await awaitable
        return "SUCCESS"
    except asyncio.CancelledError:
        raise
    except Exception as error:  # the plugins' *Error carry the result in `_result`
        result = getattr(error, "_result", None)
        return result.result.name if result is not None else f"{type(error).__name__}: {error}"


async def value_of(awaitable):
    """(result name, value) of a MAVSDK getter; value None when it failed."""
    try:
        return "SUCCESS", await awaitable
    except asyncio.CancelledError:
        raise
    except Exception as error:
        result = getattr(error, "_result", None)
        return (result.result.name if result is not None else f"{type(error).__name__}: {error}"), None


@dataclasses.dataclass
class MissionOptions:
    """PX4's MissionOptions and their defaults."""
    leg_length_m: float = 20.0
    relative_altitude_m: float = 10.0
    rtl_at_end: bool = False
    fly_through: bool = False


def log(*parts) -> None:
    print(time.strftime("[%H:%M:%S]"), *parts, file=sys.stderr, flush=True)


def finite(*values) -> bool:
    return all(v is not None and math.isfinite(v) for v in values)


#: The testers made by the running case (the runner reads their step and closes them).
ACTIVE: list["AutopilotTester"] = []


class AutopilotTester:
    """PX4's tester: connect, wait, arm, take off, missions, offboard, sticks, checks."""

    def __init__(self) -> None:
        ACTIVE.append(self)
        self.drone: System | None = None
        self._latest: dict[str, object] = {}
        self._tasks: dict[str, asyncio.Task] = {}
        self._background: list[asyncio.Task] = []
        self.home = None  # the ground truth stored by store_home (PX4's _home), None until then
        self.step = "connecting"  # what the case is doing (shown when it times out)

    # --- plumbing -------------------------------------------------------------------------
    def _watch(self, name: str, stream=None) -> None:
        """Keeps the latest value of telemetry topic `name` (or of the async generator `stream`)."""
        if name in self._tasks:
            return

        async def follow():
            source = stream if stream is not None else getattr(self.drone.telemetry, name)()
            async for value in source:
                self._latest[name] = value
        self._tasks[name] = asyncio.ensure_future(follow())

    def latest(self, name: str):
        """The newest value of a watched topic (PX4's getter), its default before any arrived."""
        self._watch(name)
        return self._latest.get(name, _DEFAULTS.get(name))

    def background(self, coro) -> asyncio.Task:
        """Runs `coro` (a subscription callback loop) until the case ends."""
        task = asyncio.ensure_future(coro)
        self._background.append(task)
        return task

    async def close(self) -> None:
        """Ends the subscriptions and stops this tester's mavsdk_server."""
        for task in [*self._tasks.values(), *self._background]:
            task.cancel()
        await asyncio.gather(*self._tasks.values(), *self._background, return_exceptions=True)
        if self.drone is not None:
            self.drone._stop_mavsdk_server()

    def sim_us(self) -> int:
        """The vehicle's clock [us]: the newest ATTITUDE_QUATERNION timestamp, 0 before one came."""
        q = self._latest.get("attitude_quaternion")
        return q.timestamp_us if q is not None else 0

    async def poll(self, fun, seconds: float) -> bool:
        """PX4's poll_condition_with_timeout: `fun` (sync or async) checked every `seconds`/100
        of wall time until true, false after `seconds` of vehicle time (host time before the
        vehicle's clock is known)."""
        pause = seconds / 100.0
        start_us, start_wall = self.sim_us(), time.monotonic()
        while True:
            result = fun()
            if inspect.isawaitable(result):
                result = await result
            if result:
                return True
            await asyncio.sleep(pause)
            if start_us and self.sim_us() - start_us > seconds * 1e6:
                return False
            if not start_us and time.monotonic() - start_wall > seconds:
                return False

    async def sleep_for(self, seconds: float) -> None:
        """PX4's sleep_for: `seconds` of vehicle time (host time before the clock is known)."""
        start = self.sim_us()
        if not start:
            await asyncio.sleep(seconds)
            return
        while self.sim_us() - start <= seconds * 1e6:
            await asyncio.sleep(0.001)

    # --- connection and readiness -----------------------------------------------------------
    async def connect(self, url: str) -> None:
        self.drone = System()
        await self.drone.connect(system_address=url)
        log("Waiting for system connect")
        connected = {"yes": False}

        async def state():
            async for s in self.drone.core.connection_state():
                connected["yes"] = s.is_connected
        self.background(state())
        require(await self.poll(lambda: connected["yes"], 25), "connect: a system appeared within 25 s", False)
        # MAVSDK's C++ Telemetry follows every topic from the start; these are the ones the cases read.
        for name in ("attitude_quaternion", "attitude_euler", "armed", "in_air", "landed_state", "flight_mode",
                     "health", "health_all_ok", "home", "position", "position_velocity_ned", "ground_truth"):
            self._watch(name)

        async def statustexts():
            async for text in self.drone.telemetry.status_text():
                log(f"[{text.type.name}] {text.text}")
        self.background(statustexts())

    async def wait_until_ready(self) -> None:
        self.step = "wait_until_ready"
        log("Waiting for system to be ready (system health ok & able to arm)")
        check(await self.poll(lambda: self.latest("health_all_ok"), 30),
              "wait_until_ready: health_all_ok within 30 s", self._health_text())
        check(await self.poll(lambda: self._armable(), 45),
              "wait_until_ready: health.is_armable within 45 s", self._health_text())

    def _armable(self) -> bool:
        h = self.latest("health")
        return h is not None and h.is_armable

    def _health_text(self) -> str:
        h = self.latest("health")
        return "no HEALTH yet" if h is None else str(h)

    async def request_ground_truth(self) -> None:
        result = await outcome(self.drone.telemetry.set_rate_ground_truth(15))
        check(result == "SUCCESS", "request_ground_truth: set_rate_ground_truth(15 Hz) == Success", result)

    def ground_truth(self):
        gt = self.latest("ground_truth")
        return (gt.latitude_deg, gt.longitude_deg, gt.absolute_altitude_m) if gt is not None else (NAN, NAN, NAN)

    async def store_home(self) -> None:
        self.step = "store_home"
        await self.request_ground_truth()
        log("Waiting to get home position")

        def got():
            self.home = self.ground_truth()
            return finite(self.home[0], self.home[1])
        check(await self.poll(got, 10), "store_home: ground truth position within 10 s", self.home)

    def get_home(self):
        """PX4's getHome: the stored ground truth, checked to be there."""
        home = self.home or (NAN, NAN, NAN)
        check(finite(home[0], home[1]), "home stored (ground truth) before use", home)
        return home

    def _truth_distance(self, target) -> float:
        check(finite(target[0], target[1]), "target position finite", target)
        current = self.ground_truth()
        check(finite(current[0], current[1]), "ground truth position finite", current)
        if not finite(target[0], target[1], current[0], current[1]):
            return NAN
        north, east = CoordinateTransformation(target[0], target[1]).local_from_global(current[0], current[1])
        return math.hypot(north, east)

    def ground_truth_close_to(self, target, radius_m: float) -> bool:
        """PX4's ground_truth_horizontal_position_close_to (its finiteness CHECKs, no verdict)."""
        return self._truth_distance(target) < radius_m

    async def check_home_within(self, radius_m: float) -> None:
        d = self._truth_distance(self.home or (NAN, NAN, NAN))
        check(d < radius_m, f"ground truth within {radius_m} m of the stored home", d)

    async def check_home_not_within(self, min_m: float) -> None:
        d = self._truth_distance(self.home or (NAN, NAN, NAN))
        check(d > min_m, f"ground truth farther than {min_m} m from the stored home", d)

    # --- parameters and settings -------------------------------------------------------------
    async def set_param_int(self, name: str, value: int) -> bool:
        result = await outcome(self.drone.param.set_param_int(name, value))
        return check(result == "SUCCESS", f"set_param_int({name}, {value}) == Success", result)

    async def set_param_float(self, name: str, value: float) -> bool:
        result = await outcome(self.drone.param.set_param_float(name, value))
        return check(result == "SUCCESS", f"set_param_float({name}, {value}) == Success", result)

    async def set_takeoff_altitude(self, altitude_m: float) -> None:
        action = self.drone.action
        result = await outcome(action.set_takeoff_altitude(altitude_m))
        check(result == "SUCCESS", f"set_takeoff_altitude({altitude_m}) == Success", result)
        result, value = await value_of(action.get_takeoff_altitude())
        check(result == "SUCCESS", "get_takeoff_altitude() == Success", result)
        check(approx(value, altitude_m),
              f"takeoff altitude reads back {altitude_m}", value)

    async def set_rtl_altitude(self, altitude_m: float) -> None:
        action = self.drone.action
        result = await outcome(action.set_return_to_launch_altitude(altitude_m))
        check(result == "SUCCESS", f"set_return_to_launch_altitude({altitude_m}) == Success", result)
        result, value = await value_of(action.get_return_to_launch_altitude())
        check(result == "SUCCESS", "get_return_to_launch_altitude() == Success", result)
        check(approx(value, altitude_m),
              f"RTL altitude reads back {altitude_m}", value)

    async def set_height_source(self, source: str) -> None:
        await self.set_param_int("EKF2_HGT_REF", {"baro": 0, "gps": 1}[source])

    async def set_rc_loss_exception(self, mask: str) -> None:
        await self.set_param_int("COM_RCL_EXCEPT", 1 << {"mission": 0, "hold": 1, "offboard": 2}[mask])

    # --- arming, take-off, landing ----------------------------------------------------------
    async def arm(self) -> None:
        self.step = "arm"
        seen = {}

        async def armed():
            seen["result"] = await outcome(self.drone.action.arm())
            return seen["result"] == "SUCCESS"
        require(await self.poll(armed, 30), "arm() == Success within 30 s (retried)", seen.get("result"))

    async def takeoff(self) -> None:
        self.step = "takeoff"
        result = await outcome(self.drone.action.takeoff())
        require(result == "SUCCESS", "takeoff() == Success", result)

    async def land(self) -> None:
        self.step = "land"
        result = await outcome(self.drone.action.land())
        require(result == "SUCCESS", "land() == Success", result)

    async def execute_rtl(self) -> None:
        self.step = "return_to_launch"
        result = await outcome(self.drone.action.return_to_launch())
        require(result == "SUCCESS", "return_to_launch() == Success", result)

    async def wait_until_disarmed(self, timeout_s: float = 60) -> None:
        self.step = f"wait_until_disarmed({timeout_s} s)"
        ok = await self.poll(lambda: not self.latest("armed"), timeout_s)
        require(ok, f"disarmed within {timeout_s} s", self._where())

    def _where(self) -> str:
        p, mode = self.latest("position"), self.latest("flight_mode")
        height = p.relative_altitude_m if p is not None else NAN
        return f"armed={self.latest('armed')} mode={getattr(mode, 'name', mode)} rel_alt={height:.2f} m"

    async def wait_for_landed_state(self, state, timeout_s: float) -> None:
        self.step = f"waiting for landed state {state.name}"
        ok = await self.poll(lambda: self.latest("landed_state") == state, timeout_s)
        require(ok, f"landed state {state.name} within {timeout_s} s",
                getattr(self.latest("landed_state"), "name", None))

    async def wait_until_hovering(self) -> None:
        await self.wait_for_landed_state(LandedState.IN_AIR, 45)

    async def wait_for_flight_mode(self, mode, timeout_s: float) -> None:
        ok = await self.poll(lambda: self.latest("flight_mode") == mode, timeout_s)
        require(ok, f"flight mode {mode.name} within {timeout_s} s", getattr(self.latest("flight_mode"), "name", None))

    def position_ned(self):
        pv = self.latest("position_velocity_ned")
        return [pv.position.north_m, pv.position.east_m, pv.position.down_m] if pv is not None else [NAN] * 3

    def velocity_ned(self):
        pv = self.latest("position_velocity_ned")
        return [pv.velocity.north_m_s, pv.velocity.east_m_s, pv.velocity.down_m_s] if pv is not None else [NAN] * 3

    async def wait_until_altitude(self, rel_alt_m: float, timeout_s: float, delta: float = 0.1) -> None:
        self.step = f"wait_until_altitude({rel_alt_m} m)"
        ok = await self.poll(lambda: abs(rel_alt_m + self.position_ned()[2]) <= delta, timeout_s)
        require(ok, f"altitude {rel_alt_m} m +- {delta} m within {timeout_s} s", -self.position_ned()[2])

    async def wait_until_speed_lower_than(self, speed: float, timeout_s: float) -> None:
        ok = await self.poll(lambda: math.sqrt(sum(v * v for v in self.velocity_ned())) < speed, timeout_s)
        require(ok, f"speed below {speed} m/s within {timeout_s} s", math.sqrt(sum(v * v for v in self.velocity_ned())))

    def check_current_altitude(self, target_m: float, max_distance_m: float = 1.5) -> None:
        p = self.latest("position")
        alt = p.relative_altitude_m if p is not None else NAN
        check(abs(alt - target_m) <= max_distance_m, f"relative altitude within {max_distance_m} m of {target_m} m",
              alt)

    def start_checking_altitude(self, max_deviation_m: float) -> None:
        target = self.position_ned()[2]

        async def watch():
            async for pv in self.drone.telemetry.position_velocity_ned():
                deviation = abs(target - pv.position.down_m)
                check(deviation <= max_deviation_m, f"altitude deviation <= {max_deviation_m} m while checking",
                      deviation, "max")
        self._altitude_checker = self.background(watch())

    def stop_checking_altitude(self) -> None:
        self._altitude_checker.cancel()

    # --- missions ---------------------------------------------------------------------------
    def get_coordinate_transformation(self) -> CoordinateTransformation:
        home = self.latest("home")
        lat, lon = (home.latitude_deg, home.longitude_deg) if home is not None else (NAN, NAN)
        check(finite(lat, lon), "home position (HOME_POSITION) finite", (lat, lon))
        return CoordinateTransformation(lat, lon)

    @staticmethod
    def mission_item(ct, north_m, east_m, options) -> MissionItem:
        lat, lon = ct.global_from_local(north_m, east_m)
        return MissionItem(lat, lon, options.relative_altitude_m, NAN, options.fly_through, NAN, NAN,
                           MissionItem.CameraAction.NONE, NAN, 1.0, NAN, NAN, NAN, MissionItem.VehicleAction.NONE)

    async def _upload(self, points, options) -> None:
        ct = self.get_coordinate_transformation()
        items = [self.mission_item(ct, n, e, options) for n, e in points]
        await outcome(self.drone.mission.set_return_to_launch_after_mission(options.rtl_at_end))
        result = await outcome(self.drone.mission.upload_mission(MissionPlan(items)))
        require(result == "SUCCESS", "upload_mission() == Success", result)
        await self.sleep_for(1)  # PX4 gives the vehicle a second to take the new mission in

    async def prepare_square_mission(self, options) -> None:
        leg = options.leg_length_m
        await self._upload([(leg, 0.0), (leg, leg), (0.0, leg)], options)

    async def prepare_straight_mission(self, options) -> None:
        await self._upload([(k * options.leg_length_m, 0.0) for k in range(5)], options)

    def mission_progress(self):
        progress = self.latest("mission_progress")
        return (progress.current, progress.total) if progress is not None else (-1, -1)

    def watch_mission_progress(self) -> None:
        self._watch("mission_progress", self.drone.mission.mission_progress())

    async def mission_finished(self, raw: bool = False) -> bool:
        plugin = self.drone.mission_raw if raw else self.drone.mission
        result, finished = await value_of(plugin.is_mission_finished())
        return result == "SUCCESS" and bool(finished)

    async def execute_mission(self) -> None:
        self.step = "execute_mission"
        self.watch_mission_progress()
        seen = {}

        async def started():
            seen["result"] = await outcome(self.drone.mission.start_mission())
            return seen["result"] == "SUCCESS"
        require(await self.poll(started, 3), "start_mission() == Success within 3 s", seen.get("result"))
        await self.wait_for_mission_finished(500)

    async def wait_for_mission_finished(self, timeout_s: float, raw: bool = False) -> None:
        self.step = f"waiting {timeout_s} s for the mission to finish"
        ok = await self.poll(lambda: self.mission_finished(raw), timeout_s)
        require(ok, f"mission finished within {timeout_s} s", f"progress {self.mission_progress()} {self._where()}")

    async def start_and_wait_for_mission_sequence(self, sequence: int) -> None:
        self.watch_mission_progress()
        result = await outcome(self.drone.mission.start_mission())
        require(result == "SUCCESS", "start_mission() == Success", result)
        ok = await self.poll(lambda: self.mission_progress()[0] >= sequence, 60)
        require(ok, f"mission progress reached item {sequence} within 60 s", self.mission_progress())

    async def execute_mission_and_lose(self, unit, kind, timeout_s: float | None) -> None:
        """PX4's execute_mission_and_{lose,get_*_stuck}: failure injection enabled, the mission
        under way to item 1, then the sensor failed; unless GPS was lost (then the caller only
        waits for the disarm), the mission must still finish within `timeout_s`."""
        await self.set_param_int("SYS_FAILURE_EN", 1)
        self.step = "starting the mission"
        await self.start_and_wait_for_mission_sequence(1)
        result = await outcome(self.drone.failure.inject(unit, kind, 0))
        check(result == "SUCCESS", f"inject({unit.name}, {kind.name}, 0) == Success", result)
        if timeout_s is not None:
            self.step = f"mission after {unit.name} {kind.name}"
            ok = await self.poll(lambda: self.mission_finished(), timeout_s)
            require(ok, f"mission finished within {timeout_s} s after {unit.name} {kind.name}",
                    f"progress {self.mission_progress()} {self._where()}")

    def check_tracks_mission(self, corridor_m: float = 1.5) -> asyncio.Task:
        """Every position sample between items 1 and the last must lie within `corridor_m` of
        the line through the previous and the current item (PX4's check_tracks_mission)."""
        async def watch():
            result, plan = await value_of(self.drone.mission.download_mission())
            check(result == "SUCCESS", "download_mission() == Success", result)
            items = plan.mission_items if plan is not None else []
            ct = self.get_coordinate_transformation()
            self.watch_mission_progress()
            local = [[*ct.local_from_global(i.latitude_deg, i.longitude_deg), -i.relative_altitude_m] for i in items]
            await outcome(self.drone.telemetry.set_rate_position_velocity_ned(5))
            async for pv in self.drone.telemetry.position_velocity_ned():
                current, total = self.mission_progress()
                if 0 < current < total and current < len(local):
                    here = [pv.position.north_m, pv.position.east_m, pv.position.down_m]
                    d = point_to_line_distance(here, local[current - 1], local[current])
                    check(d < corridor_m, f"check_tracks_mission: within {corridor_m} m of the line to item {current}",
                          d, "max")
        return self.background(watch())

    def check_mission_item_speed_above(self, item: int, min_speed: float) -> asyncio.Task:
        async def watch():
            self.watch_mission_progress()
            await outcome(self.drone.telemetry.set_rate_velocity_ned(10))
            async for v in self.drone.telemetry.velocity_ned():
                if self.mission_progress()[0] == item:
                    speed = math.hypot(v.north_m_s, v.east_m_s)
                    check(speed > min_speed, f"horizontal speed > {min_speed} m/s while item {item} is current",
                          speed, "min")
        return self.background(watch())

    # --- offboard ---------------------------------------------------------------------------
    async def start_offboard_with_retry(self, resend) -> None:
        result = None
        for _ in range(10):
            result = await outcome(self.drone.offboard.start())
            if result == "SUCCESS":
                return
            await resend()
            await asyncio.sleep(0.02)
        require(False, "offboard start() == Success (10 tries)", result)

    async def offboard_goto(self, target: PositionNedYaw, radius_m: float = 0.3, timeout_s: float = 60) -> None:
        self.step = f"offboard_goto({target.north_m}, {target.east_m}, {target.down_m})"
        offboard = self.drone.offboard
        await outcome(offboard.set_position_ned(target))
        await self.start_offboard_with_retry(lambda: outcome(offboard.set_position_ned(target)))
        goal = (target.north_m, target.east_m, target.down_m)

        def distance():
            return math.dist(self.position_ned(), goal) if finite(*self.position_ned()) else NAN
        ok = await self.poll(lambda: distance() < radius_m, timeout_s)
        check(ok, f"offboard_goto: within {radius_m} m of {goal} within {timeout_s} s", distance())
        log("Target position reached" if ok else f"Target position not reached, distance {distance():.2f} m")

    async def offboard_land(self) -> None:
        self.step = "offboard_land"
        await outcome(self.drone.offboard.set_velocity_ned(VelocityNedYaw(0.0, 0.0, 1.0, 0.0)))
