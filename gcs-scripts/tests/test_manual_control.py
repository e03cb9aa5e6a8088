"""Flying by hand as QGroundControl's virtual joystick does it: MANUAL_CONTROL at 50 Hz from
pymavlink (x pitch, y roll, z throttle 0..1000 with 500 centred, r yaw), against the binary on
ephemeral ports. POSCTL arms with centred sticks, the throttle takes off, the pitch stick flies
north, centred sticks hold, the throttle down lands and auto-disarms; silent sticks run
NAV_RCL_ACT (return) with its STATUSTEXT."""
import os
import threading
import time

os.environ["MAVLINK20"] = "1"
from test_autopilot_link import ACCEPTED, Autopilot  # noqa: E402

POSCTL = 3 << 16
RTL_MODE = (4 << 16) | (5 << 24)
ON_GROUND, IN_AIR = 1, 2


class Joystick:
    """MANUAL_CONTROL at 50 Hz on its own thread, as QGC's joystick thread sends it."""

    def __init__(self, ap):
        self.ap, self.sticks, self.running = ap, (0, 0, 500, 0), True
        self.thread = threading.Thread(target=self.run, daemon=True)
        self.thread.start()

    def run(self):
        while self.running:
            x, y, z, r = self.sticks
            self.ap.gcs.mav.manual_control_send(1, x, y, z, r, 0)
            time.sleep(0.02)

    def stop(self):
        self.running = False
        self.thread.join()


def position(ap):
    return ap.wait(lambda m: True, "LOCAL_POSITION_NED", 2)


def test_posctl_takes_off_flies_holds_and_lands_on_the_sticks():
    ap = Autopilot()
    stick = Joystick(ap)
    try:
        ap.heartbeat()
        time.sleep(0.3)
        assert ap.command(176, 1, 3, 0).result == ACCEPTED, "POSCTL with sticks"
        assert ap.command(400, 1.0).result == ACCEPTED
        stick.sticks = (0, 0, 1000, 0)
        assert ap.wait(lambda m: m.landed_state == IN_AIR, "EXTENDED_SYS_STATE", 10) is not None
        assert ap.wait(lambda m: m.z < -4.0, "LOCAL_POSITION_NED", 10) is not None, "climbs on the throttle"
        stick.sticks = (0, 0, 500, 0)
        time.sleep(2.0)
        held = position(ap)
        time.sleep(2.0)
        still = position(ap)
        assert abs(still.x - held.x) < 0.5 and abs(still.z - held.z) < 0.5, (held, still)
        stick.sticks = (1000, 0, 500, 0)
        assert ap.wait(lambda m: m.vx > 5.0, "LOCAL_POSITION_NED", 8) is not None, "full pitch flies north"
        stick.sticks = (0, 0, 500, 0)
        assert ap.wait(lambda m: abs(m.vx) < 0.2 and abs(m.vy) < 0.2, "LOCAL_POSITION_NED", 10) is not None
        hb = ap.wait(lambda m: m.get_srcComponent() == 1, "HEARTBEAT", 2)
        assert hb.custom_mode == POSCTL, "still in POSCTL"
        stick.sticks = (0, 0, 0, 0)
        assert ap.wait(lambda m: m.landed_state == ON_GROUND, "EXTENDED_SYS_STATE", 30) is not None, "landed"
        disarmed = ap.wait(lambda m: m.get_srcComponent() == 1 and not m.base_mode & 128, "HEARTBEAT", 6)
        assert disarmed is not None, "COM_DISARM_LAND"
    finally:
        stick.stop()
        ap.close()


def test_stick_loss_in_the_air_returns():
    ap = Autopilot()
    stick = Joystick(ap)
    try:
        ap.heartbeat()
        time.sleep(0.3)
        ap.take_off()
        stick.stop()
        lost = ap.wait(lambda m: m.text.startswith("Manual control lost"), "STATUSTEXT", 3)
        assert lost is not None and lost.text == "Manual control lost: returning"
        assert ap.wait(lambda m: m.custom_mode == RTL_MODE, "HEARTBEAT", 3) is not None
    finally:
        stick.stop()
        ap.close()
