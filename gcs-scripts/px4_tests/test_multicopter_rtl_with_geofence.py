"""PX4's test_multicopter_rtl_with_geofence.cpp (PX4-Autopilot test/mavsdk_tests): a QGC plan
(plans/multicopter_mission_geofence_avoid.plan: take-off at 20 m, three waypoints to the south-west,
an exclusion polygon and an exclusion circle between the last of them and home, all inside an
inclusion polygon) moved to where the vehicle stands; RTL_TYPE 0 (straight home), RTL_APPR_FORCE 0,
GF_ACTION 1 (warn only); RTL once item 3 is current. The vehicle must be home within 5 m and
disarmed within 400 s without its ground-truth track ever breaching a fence."""
import pathlib

from . import CONNECTION_URL, case
from .autopilot_tester_rtl import AutopilotTesterRtl

PLAN = pathlib.Path(__file__).resolve().parent / "plans" / "multicopter_mission_geofence_avoid.plan"


@case("Return direct with geofence obstruction", "[multicopter]")
async def return_direct_with_geofence_obstruction(url: str = CONNECTION_URL) -> None:
    tester = AutopilotTesterRtl()
    await tester.connect(url)
    await tester.wait_until_ready()
    await tester.store_home()
    await tester.load_qgc_mission_and_geofence_here(str(PLAN))
    await tester.set_param_int("GF_ACTION", 1)
    await tester.set_rtl_type(0)
    await tester.set_rtl_appr_force(0)
    await tester.sleep_for(3)
    await tester.arm()
    tester.start_monitoring_geofence_breach()
    await tester.execute_rtl_when_reaching_mission_sequence(3)
    await tester.wait_until_disarmed(400)
    tester.check_no_geofence_breach()
    await tester.check_home_within(5.0)
