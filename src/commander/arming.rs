//! Arming and disarming. Arming is refused (unless forced) in AUTO.MISSION without a mission,
//! in OFFBOARD without a live setpoint stream and in AUTO.LAND / AUTO.RTL; a disarm is refused
//! in the air unless forced. Disarming leaves the modes that only make sense armed.

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
            match self.mode {
                FlightMode::Mission if self.mission.mission.is_empty() => {
                    return Outcome::TemporarilyRejected("Arming denied: no mission".into())
                }
                FlightMode::Offboard if !self.offboard_alive(t_s) => {
                    return Outcome::TemporarilyRejected("Arming denied: no offboard setpoints".into())
                }
                FlightMode::Land | FlightMode::ReturnToLaunch => {
                    return Outcome::TemporarilyRejected(format!("Arming denied: not in {}", self.mode.name()))
                }
                _ => {}
            }
        }
        self.armed = true;
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
        self.guidance = Guidance::Idle;
        self.climbing_out = false;
        if matches!(
            self.mode,
            FlightMode::Takeoff | FlightMode::Land | FlightMode::ReturnToLaunch
        ) {
            self.mode = FlightMode::Loiter;
        }
    }
}
