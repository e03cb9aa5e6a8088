//! Arming and disarming ([`Arming`]): the armed state, when it was armed and whether the
//! vehicle has been in the air since. Arming is refused (unless forced) outside the geofence
//! (while `GF_ACTION` is set), in AUTO.MISSION without a mission, in OFFBOARD without a live
//! setpoint stream, in AUTO.LAND / AUTO.RTL / orbit / follow-me / GOTO, in the stick modes without
//! sticks and with the throttle up where it sets the thrust ([`Arming::refusal`]); a disarm is
//! refused in the air unless forced. Auto-disarm on the ground: `COM_DISARM_LAND` after a
//! touch-down, `COM_DISARM_PRFLT` when never airborne since arming ([`Arming::auto_disarm_reason`]).

use super::{CommanderParams, FlightMode, Outcome};

/// What the pre-arm checks found, each worked out by the concern that owns it.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct ArmingChecks {
    /// The navigation estimate's refusal for the mode, if any.
    pub navigation: Option<Outcome>,
    /// The vehicle is outside the geofence (while `GF_ACTION` is set).
    pub outside_fence: bool,
    /// A mission is stored.
    pub has_mission: bool,
    /// The offboard setpoint stream is alive.
    pub offboard_alive: bool,
    /// The stick modes' refusal for the mode, if any.
    pub sticks: Option<Outcome>,
}

/// The armed state.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(super) struct Arming {
    armed: bool,
    /// When the vehicle was last armed [s].
    armed_at_s: f64,
    /// The vehicle has been in the air since it was armed.
    took_off: bool,
}

impl Arming {
    /// Armed.
    pub fn armed(&self) -> bool {
        self.armed
    }

    /// Why arming in `mode` is refused by `checks` (in this order: the estimate, the fence, the
    /// mode's needs), if it is.
    pub fn refusal(mode: FlightMode, checks: ArmingChecks) -> Option<Outcome> {
        if let Some(refusal) = checks.navigation {
            return Some(refusal);
        }
        if checks.outside_fence {
            return Some(Outcome::TemporarilyRejected(
                "Arming denied: vehicle outside geofence".into(),
            ));
        }
        match mode {
            FlightMode::Mission if !checks.has_mission => {
                Some(Outcome::TemporarilyRejected("Arming denied: no mission".into()))
            }
            FlightMode::Offboard if !checks.offboard_alive => Some(Outcome::TemporarilyRejected(
                "Arming denied: no offboard setpoints".into(),
            )),
            FlightMode::Land
            | FlightMode::ReturnToLaunch
            | FlightMode::Orbit
            | FlightMode::FollowTarget
            | FlightMode::Goto => Some(Outcome::TemporarilyRejected(format!(
                "Arming denied: not in {}",
                mode.name()
            ))),
            _ => checks.sticks,
        }
    }

    /// Arms at `t_s` [s]; `landed` the land detector's verdict (a vehicle armed in the air has
    /// taken off).
    pub fn arm(&mut self, t_s: f64, landed: bool) {
        self.armed = true;
        self.armed_at_s = t_s;
        self.took_off = !landed;
    }

    /// Motors off.
    pub fn disarm(&mut self) {
        self.armed = false;
    }

    /// The land detector saw a lift-off.
    pub fn took_off(&mut self) {
        self.took_off = true;
    }

    /// Why the vehicle, landed since `landed_at_s` [s], disarms at `t_s` [s]: `COM_DISARM_LAND`
    /// after a touch-down, `COM_DISARM_PRFLT` when it has not been in the air since arming.
    pub fn auto_disarm_reason(&self, p: &CommanderParams, landed_at_s: Option<f64>, t_s: f64) -> Option<&'static str> {
        if self.took_off {
            let landed_for = landed_at_s.map(|at| t_s - at);
            (p.disarm_land_s > 0.0 && landed_for.is_some_and(|d| d >= p.disarm_land_s)).then_some("landed")
        } else {
            (p.disarm_preflight_s > 0.0 && t_s - self.armed_at_s >= p.disarm_preflight_s).then_some("no takeoff")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::script::Script;
    use super::super::{CommanderParams, FlightMode, Outcome, Request};
    use super::{Arming, ArmingChecks};
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

    fn passing() -> ArmingChecks {
        ArmingChecks {
            navigation: None,
            outside_fence: false,
            has_mission: true,
            offboard_alive: true,
            sticks: None,
        }
    }

    #[test]
    fn the_refusal_reasons_come_in_order_estimate_fence_mode() {
        let nav = Outcome::TemporarilyRejected("Arming denied: no valid position estimate".into());
        let all_wrong = ArmingChecks {
            navigation: Some(nav.clone()),
            outside_fence: true,
            has_mission: false,
            offboard_alive: false,
            sticks: None,
        };
        assert_eq!(Arming::refusal(FlightMode::Mission, all_wrong.clone()), Some(nav));
        let fence_and_mode = ArmingChecks {
            navigation: None,
            ..all_wrong
        };
        assert_eq!(
            Arming::refusal(FlightMode::Mission, fence_and_mode.clone()),
            Some(Outcome::TemporarilyRejected(
                "Arming denied: vehicle outside geofence".into()
            ))
        );
        let mode_only = ArmingChecks {
            outside_fence: false,
            ..fence_and_mode
        };
        assert_eq!(
            Arming::refusal(FlightMode::Mission, mode_only.clone()),
            Some(Outcome::TemporarilyRejected("Arming denied: no mission".into()))
        );
        assert_eq!(
            Arming::refusal(FlightMode::Offboard, mode_only),
            Some(Outcome::TemporarilyRejected(
                "Arming denied: no offboard setpoints".into()
            ))
        );
        assert_eq!(
            Arming::refusal(FlightMode::Goto, passing()),
            Some(Outcome::TemporarilyRejected(format!(
                "Arming denied: not in {}",
                FlightMode::Goto.name()
            )))
        );
        let sticks = Outcome::TemporarilyRejected("Arming denied: throttle above 20%".into());
        let with_sticks = ArmingChecks {
            sticks: Some(sticks.clone()),
            ..passing()
        };
        assert_eq!(Arming::refusal(FlightMode::Stabilized, with_sticks), Some(sticks));
        assert_eq!(Arming::refusal(FlightMode::Loiter, passing()), None);
    }

    #[test]
    fn auto_disarm_waits_com_disarm_prflt_before_a_take_off_and_com_disarm_land_after() {
        let p = CommanderParams::default();
        let mut a = Arming::default();
        a.arm(10.0, true);
        assert!(a.armed());
        assert_eq!(
            a.auto_disarm_reason(&p, Some(0.0), 10.0 + p.disarm_preflight_s - 0.01),
            None
        );
        assert_eq!(
            a.auto_disarm_reason(&p, Some(0.0), 10.0 + p.disarm_preflight_s),
            Some("no takeoff")
        );
        a.took_off();
        assert_eq!(a.auto_disarm_reason(&p, None, 100.0), None, "in the air");
        assert_eq!(
            a.auto_disarm_reason(&p, Some(50.0), 50.0 + p.disarm_land_s),
            Some("landed")
        );
        let armed_in_the_air = {
            let mut a = Arming::default();
            a.arm(0.0, false);
            a
        };
        assert_eq!(
            armed_in_the_air.auto_disarm_reason(&p, Some(1.0), 1.0 + p.disarm_land_s),
            Some("landed")
        );
        a.disarm();
        assert!(!a.armed());
    }
}
