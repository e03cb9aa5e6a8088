"""PX4's test_multicopter_basics.cpp (PX4-Autopilot test/mavsdk_tests): take off to 10 m and hold
the altitude within 0.25 m for 60 s (PX4 waits those 60 s on the host clock)."""
import asyncio

from . import CONNECTION_URL, case
from .autopilot_tester import AutopilotTester


@case("Takeoff and hold position", "[multicopter][vtol]")
async def takeoff_and_hold_position(url: str = CONNECTION_URL) -> None:
    takeoff_altitude, tolerance, hold_s = 10.0, 0.25, 60
    tester = AutopilotTester()
    await tester.connect(url)
    await tester.wait_until_ready()
    await tester.set_takeoff_altitude(takeoff_altitude)
    await tester.store_home()
    await asyncio.sleep(1)  # PX4: lets the take-off altitude settle in
    await tester.arm()
    await tester.takeoff()
    await tester.wait_until_hovering()
    await tester.wait_until_altitude(takeoff_altitude, 30, tolerance + 0.1)
    tester.start_checking_altitude(tolerance)
    tester.step = f"holding {takeoff_altitude} m for {hold_s} s"
    await asyncio.sleep(hold_s)
