"""Flying by hand as QGroundControl's virtual joystick does it: MANUAL_CONTROL at 50 Hz from
pymavlink (x pitch, y roll, z throttle 0..1000 with 500 centred, r yaw), against the binary on
ephemeral ports. POSCTL arms with centred sticks, the throttle takes off, the pitch stick flies
north, centred sticks hold, the throttle down lands and auto-disarms; silent sticks run
NAV_RCL_ACT (return) with its STATUSTEXT."""
import threading
import time

from rotorpilot_gcs import mavlink

# Flown on `rotorpilot run`'s default configuration (realistic sensors), as a joystick meets the
# vehicle: the tolerances (0.5 m hold, 5 m/s at full pitch) are a flight's, not centimetres.
ACCEPTED = mavlink.MAV_RESULT_ACCEPTED


class Joystick:
    """MANUAL_CONTROL at 50 Hz on its own thread, as QGC's joystick thread sends it."""

    def __init__(self, ap):
        self.ap, self.sticks, self.running = ap, (0, 0, 500, 0), True
        self.thread = threading.Thread(target=self.run, daemon=True)
        self.thread.start()

    def run(self):
        while self.running:
            x, y, z, r = self.sticks
            self.ap.vehicle.conn.mav.manual_control_send(1, x, y, z, r, 0)
            time.sleep(0.02)

    def stop(self):
        self.running = False
        self.thread.join()


def position(ap):
    return ap.vehicle.wait("LOCAL_POSITION_NED", timeout=2)


def test_posctl_takes_off_flies_holds_and_lands_on_the_sticks(autopilot):
    ap = autopilot
    stick = Joystick(ap)
    try:
        time.sleep(0.3)
        assert ap.vehicle.command_ack(176, 1, 3, 0).result == ACCEPTED, "POSCTL with sticks"
        ap.vehicle.wait_armable()
        assert ap.vehicle.command_ack(400, 1.0).result == ACCEPTED
        stick.sticks = (0, 0, 1000, 0)
        ap.vehicle.wait_in_air(10)
        ap.vehicle.wait("LOCAL_POSITION_NED", lambda m: m.z < -4.0, 10, what="a climb on the throttle")
        stick.sticks = (0, 0, 500, 0)
        time.sleep(2.0)
        held = position(ap)
        time.sleep(2.0)
        still = position(ap)
        assert abs(still.x - held.x) < 0.5 and abs(still.z - held.z) < 0.5, (held, still)
        stick.sticks = (1000, 0, 500, 0)
        ap.vehicle.wait("LOCAL_POSITION_NED", lambda m: m.vx > 5.0, 8, what="full pitch flying north")
        stick.sticks = (0, 0, 500, 0)
        ap.vehicle.wait("LOCAL_POSITION_NED", lambda m: abs(m.vx) < 0.2 and abs(m.vy) < 0.2, 10)
        assert ap.vehicle.wait_heartbeat(timeout=2).custom_mode == 3 << 16, "still in POSCTL"
        stick.sticks = (0, 0, 0, 0)
        ap.vehicle.wait_on_ground(30)
        ap.vehicle.wait_disarmed(6)  # COM_DISARM_LAND
    finally:
        stick.stop()


def test_stick_loss_in_the_air_returns(autopilot):
    ap = autopilot
    stick = Joystick(ap)
    try:
        time.sleep(0.3)
        ap.vehicle.takeoff()
        stick.stop()
        lost = ap.vehicle.wait("STATUSTEXT", lambda m: m.text.startswith("Manual control lost"), 3)
        assert lost.text == "Manual control lost: returning"
        ap.vehicle.wait_mode("AUTO.LOITER", 3)  # COM_FAIL_ACT_T (5 s) in a hold first, as PX4
        ap.vehicle.wait_mode("AUTO.RTL", 7)
    finally:
        stick.stop()
