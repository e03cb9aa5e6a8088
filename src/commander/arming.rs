//! Arming and disarming. Arming is refused (unless forced) outside the geofence (while
//! `GF_ACTION` is set), in AUTO.MISSION without a mission, in OFFBOARD without a live setpoint
//! stream, in AUTO.LAND / AUTO.RTL / orbit / follow-me / GOTO, in the stick modes without sticks
//! and with the throttle up where it sets the thrust; a disarm is refused in the air unless
//! forced. Disarming leaves the modes that only make sense armed.

use crate::control::VehicleState;
use crate::navigation::Guidance;

use super::{Commander, FlightMode, Outcome};

impl Commander {
    /// ARM: checks the mode (skipped when `force`), then arms and starts the mode's guidance.
    pub(super) fn arm(&mut self, force: bool, x: &VehicleState, t_s: f64) -> Outcome {
        if self.armed {
            return Outcome::Accepted;
        }
        if !force {
            if let Some(refusal) = self.navigation_refusal(self.mode, true) {
                return refusal;
            }
            if self.arming_fence_breach(x).is_some() {
                return Outcome::TemporarilyRejected("Arming denied: vehicle outside geofence".into());
            }
            match self.mode {
                FlightMode::Mission if self.mission.mission.is_empty() => {
                    return Outcome::TemporarilyRejected("Arming denied: no mission".into())
                }
                FlightMode::Offboard if !self.offboard_alive(t_s) => {
                    return Outcome::TemporarilyRejected("Arming denied: no offboard setpoints".into())
                }
                FlightMode::Land
                | FlightMode::ReturnToLaunch
                | FlightMode::Orbit
                | FlightMode::FollowTarget
                | FlightMode::Goto => {
                    return Outcome::TemporarilyRejected(format!("Arming denied: not in {}", self.mode.name()))
                }
                mode => {
                    if let Some(refusal) = self.stick_mode_refusal(mode, t_s, true) {
                        return refusal;
                    }
                }
            }
        }
        self.armed = true;
        self.manual.at_arming = self.sticks_alive(t_s);
        self.manual.lost = false;
        self.armed_at_s = t_s;
        self.took_off = !self.detector.landed();
        self.enter(self.mode, x, t_s);
        Outcome::Accepted
    }

    /// DISARM: refused in the air unless `force`.
    pub(super) fn disarm_request(&mut self, force: bool) -> Outcome {
        if self.in_air() && !force {
            return Outcome::TemporarilyRejected("Disarm refused: vehicle in the air".into());
        }
        self.disarm();
        Outcome::Accepted
    }

    /// Motors off (explicit disarm, auto-disarm on the ground, or a termination).
    pub(super) fn disarm(&mut self) {
        self.armed = false;
        self.blind_descent = false;
        self.guidance = Guidance::Idle;
        self.climbing_out = false;
        if matches!(
            self.mode,
            FlightMode::Takeoff | FlightMode::Land | FlightMode::ReturnToLaunch | FlightMode::Goto
        ) {
            self.mode = FlightMode::Loiter;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::script::Script;
    use super::super::{CommanderParams, FlightMode, Outcome, Request};
    use crate::control::FlatSetpoint;
    use crate::math::Vec3;

    fn temporarily_rejected(outcome: Outcome, text: &str) {
        assert_eq!(outcome, Outcome::TemporarilyRejected(text.into()));
    }

    #[test]
    fn arming_is_refused_in_a_mode_that_cannot_fly_unless_forced() {
        let mut s = Script::new(CommanderParams::default());
        // AUTO.MISSION without a mission (only reachable by the mission being cleared).
        s.c.mode = FlightMode::Mission;
        temporarily_rejected(s.request(Request::Arm { force: false }), "Arming denied: no mission");
        assert!(!s.c.armed());
        // OFFBOARD with a stream that stopped longer than COM_OF_LOSS_T ago.
        let sp = FlatSetpoint::hold(Vec3::new(0.0, 0.0, -2.0), 0.0);
        assert_eq!(s.request(Request::offboard(sp)), Outcome::Accepted);
        assert_eq!(s.request(Request::SetMode(FlightMode::Offboard)), Outcome::Accepted);
        s.fly(1.5);
        temporarily_rejected(
            s.request(Request::Arm { force: false }),
            "Arming denied: no offboard setpoints",
        );
        for (mode, text) in [
            (FlightMode::Land, "Arming denied: not in AUTO.LAND"),
            (FlightMode::ReturnToLaunch, "Arming denied: not in AUTO.RTL"),
        ] {
            assert_eq!(s.request(Request::SetMode(mode)), Outcome::Accepted);
            temporarily_rejected(s.request(Request::Arm { force: false }), text);
            assert!(!s.c.armed());
        }
        assert_eq!(s.request(Request::Arm { force: true }), Outcome::Accepted);
        assert!(s.c.armed() && s.c.mode() == FlightMode::ReturnToLaunch);
    }

    #[test]
    fn armed_in_a_hold_mode_the_motors_idle_and_arming_again_is_accepted() {
        let mut s = Script::new(CommanderParams::default());
        assert_eq!(s.request(Request::Arm { force: false }), Outcome::Accepted);
        assert_eq!(s.request(Request::Arm { force: false }), Outcome::Accepted);
        s.fly(1.0);
        assert!(s.c.armed() && !s.c.in_air());
        assert_eq!(s.last.as_ref().map(|t| t.setpoint), Some(None), "idle on the ground");
        assert_eq!(s.x.pos_w.z, super::super::script::GROUND_Z_M);
    }

    #[test]
    fn a_disarm_in_the_air_is_refused_unless_forced_and_leaves_the_armed_only_modes() {
        let mut s = Script::new(CommanderParams::default());
        s.airborne(3.0);
        assert_eq!(s.request(Request::Land), Outcome::Accepted);
        s.fly(0.5);
        temporarily_rejected(
            s.request(Request::Disarm { force: false }),
            "Disarm refused: vehicle in the air",
        );
        assert!(s.c.armed() && s.c.in_air());
        assert_eq!(s.request(Request::Disarm { force: true }), Outcome::Accepted);
        assert!(!s.c.armed());
        assert_eq!(s.c.mode(), FlightMode::Loiter, "AUTO.LAND needs the motors");
        s.fly(0.1);
        assert_eq!(s.last.as_ref().map(|t| t.setpoint), Some(None), "motors off");
        // On the ground a disarm needs no force.
        assert_eq!(s.request(Request::Arm { force: false }), Outcome::Accepted);
        assert_eq!(s.request(Request::Disarm { force: false }), Outcome::Accepted);
        assert!(!s.c.armed());
    }
}
