"""The vehicle on a bad link, driven by the rotorpilot_gcs library, judged from what the ground
station gets: with rotorpilot's own impairment (`run --link-loss 20% --link-delay 0..50ms
--link-duplicate 5% --link-seed N`, both directions; one seed, three with
ROTORPILOT_LONG_TESTS=1) and through an external lossy UDP proxy (lossy_proxy.py, so the feature
does not test itself), a 30-item mission, the fence and the rally points go up and come back
identical, the whole parameter list arrives, and a mission is flown to its landing, each transfer
at the first attempt (`upload_mission` raises when an upload fails: none is started over) and
without the vehicle giving up on one (no `Operation timeout`). The last item repeated after the
final MISSION_ACK gets that ACK again."""
import json
import os
import pathlib
import time

import pytest
from lossy_proxy import LossyProxy
from pymavlink import mavutil

import rotorpilot_gcs as gcs
from rotorpilot_gcs import mavlink
from rotorpilot_gcs.missions import FENCE, MISSION, RALLY

PLAN = pathlib.Path(__file__).resolve().parent / "data" / "fence_rally.plan"
HOME = gcs.geo.DEFAULT_HOME
IMPAIRED = ["--link-loss", "20%", "--link-delay", "0..50ms", "--link-duplicate", "5%"]


def at(north_m, east_m):
    """(lat, lon) [degE7] of a point north / east of home."""
    return gcs.geo.offset_to_global(HOME[0], HOME[1], north_m, east_m)


def long_mission():
    """30 waypoints on a 6 × 5 grid, 3 to 9 m high."""
    return [gcs.missions.nav_waypoint(*at(4.0 * (k // 5), 4.0 * (k % 5)), 3.0 + k % 7) for k in range(30)]


def flight():
    """Take off to 4 m, two waypoints 8 m out, land."""
    return [gcs.missions.nav_takeoff(*at(0.0, 0.0), 4.0), gcs.missions.nav_waypoint(*at(8.0, 0.0), 4.0),
            gcs.missions.nav_waypoint(*at(8.0, 8.0), 4.0), gcs.missions.nav_land(*at(8.0, 8.0))]


def round_trips_and_a_flight(vehicle, since):
    """Every transfer at the first attempt over `vehicle`'s lossy link, then a mission flown to
    its landing; no upload dropped by the vehicle since `since` (monotonic)."""
    plan = gcs.plans.load_qgc_plan(PLAN)
    for items, kind in ((long_mission(), MISSION), (plan.fence, FENCE), (plan.rally, RALLY)):
        ack = vehicle.upload_mission(items, kind)
        assert ack.type == mavlink.MAV_MISSION_ACCEPTED
        assert vehicle.download_mission(kind) == items, f"mission type {kind} came back changed"
    params = vehicle.param_list()
    assert len(params) > 100 and params["MPC_XY_VEL_MAX"] == pytest.approx(12.0)
    vehicle.clear_mission(gcs.missions.ALL)
    assert vehicle.download_mission(FENCE) == []
    vehicle.upload_mission(flight())
    vehicle.wait_armable(timeout=60)
    vehicle.set_mode(gcs.AUTO_MISSION)
    vehicle.arm()
    vehicle.wait_in_air(timeout=30)
    vehicle.wait_disarmed(timeout=120)
    assert gcs.link.recent_text(vehicle.conn, since, "Operation timeout") is None


def stopped_line(ap):
    """The JSON line `run` prints when it stops."""
    lines = [json.loads(line) for line in ap.stdout_text().splitlines() if line.startswith("{")]
    return next(line for line in lines if line.get("event") == "stopped")


# One seed in the default run; ROTORPILOT_LONG_TESTS=1 flies three (README, Set-up).
SEEDS = [1, 2, 3] if os.environ.get("ROTORPILOT_LONG_TESTS") == "1" else [1]


@pytest.mark.parametrize("seed", SEEDS)
def test_transfers_and_a_flight_over_the_built_in_impairment(autopilot_factory, seed):
    ap = autopilot_factory(speedup=4, args=[*IMPAIRED, "--link-seed", str(seed)], timeout=10)
    round_trips_and_a_flight(ap.vehicle, time.monotonic())
    ap.stop()
    counts = stopped_line(ap)["link_impairment"][0]["links"]
    gcs_link = next(c for c in counts if c["link"] == "gcs")
    for way in ("up", "down"):
        c = gcs_link[way]
        assert 0.15 < c["dropped"] / c["datagrams"] < 0.25, (way, c)
        assert c["duplicated"] > 0 and c["delayed"] > 0.9 * (c["datagrams"] - c["dropped"]), (way, c)


def test_transfers_and_a_flight_through_an_external_lossy_proxy(autopilot_factory):
    ap = autopilot_factory(speedup=4, timeout=10)
    host, port = ap.gcs_bind.rsplit(":", 1)
    proxy = LossyProxy((host, int(port)), loss=0.2, duplicate=0.05, delay_s=0.05, seed=11)
    conn = mavutil.mavlink_connection(f"udpout:127.0.0.1:{proxy.client_port}", source_system=255,
                                      source_component=190)
    try:
        vehicle = gcs.Vehicle(gcs.connect(conn, timeout=10, quiet=True))
        round_trips_and_a_flight(vehicle, time.monotonic())
        assert proxy.counts["dropped"] > 100 and proxy.counts["duplicated"] > 10, proxy.counts
    finally:
        gcs.link.forget(conn)
        conn.close()
        proxy.close()


def test_the_last_item_repeated_after_the_final_ack_gets_the_ack_again(vehicle):
    items = flight()
    conn = vehicle.conn
    conn.mav.mission_count_send(1, 1, len(items), MISSION)
    for seq, it in enumerate(items):
        request = vehicle.wait("MISSION_REQUEST_INT", lambda m, s=seq: m.seq == s, timeout=5)
        conn.mav.mission_item_int_send(1, 1, request.seq, it.frame, it.command, 0, it.autocontinue, it.param1,
                                       it.param2, it.param3, it.param4, it.x, it.y, it.z, MISSION)
    first = vehicle.wait("MISSION_ACK", timeout=5)
    assert first.type == mavlink.MAV_MISSION_ACCEPTED
    # As if that ACK had been lost: the client sends its last item again, and again.
    last = items[-1]
    for _ in range(3):
        conn.mav.mission_item_int_send(1, 1, len(items) - 1, last.frame, last.command, 0, last.autocontinue,
                                       last.param1, last.param2, last.param3, last.param4, last.x, last.y, last.z,
                                       MISSION)
        again = vehicle.wait("MISSION_ACK", timeout=2)
        assert again.type == mavlink.MAV_MISSION_ACCEPTED
    assert vehicle.download_mission() == items
