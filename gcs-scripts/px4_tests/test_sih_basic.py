"""PX4's test_sih_basic.cpp (PX4-Autopilot test/mavsdk_tests), its smoke test on the SIH
quadrotor ([sih], configs/sitl_sih.json): take off to 5 m (reached within 1 m in 30 s), land and
disarm within 60 s, after a 10 s host-clock pause before arming. Nothing in its steps needs SIH,
so it runs on rotorpilot's quad_x."""
import asyncio

from . import CONNECTION_URL, case
from .autopilot_tester import AutopilotTester


@case("SIH takeoff and land", "[sih]")
async def sih_takeoff_and_land(url: str = CONNECTION_URL) -> None:
    takeoff_altitude = 5.0
    tester = AutopilotTester()
    await tester.connect(url)
    await tester.wait_until_ready()
    await tester.set_takeoff_altitude(takeoff_altitude)
    await tester.store_home()
    await asyncio.sleep(10)  # PX4 lets its estimator settle before arming
    await tester.arm()
    await tester.takeoff()
    await tester.wait_until_hovering()
    await tester.wait_until_altitude(takeoff_altitude, 30, 1.0)
    await tester.land()
    await tester.wait_until_disarmed(60)
