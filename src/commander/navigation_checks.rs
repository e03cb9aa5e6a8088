//! What the navigation estimate allows (PX4's mode requirements, pre-arm checks and
//! position-loss failsafe, docs/mavlink.md §11.2): a mode that needs a position cannot be
//! entered or armed in without a valid one, and a vehicle that loses its position in flight in
//! such a mode descends level at the landing speed until it touches down ("descend"; PX4 shows
//! it as AUTO.LAND), or with `COM_POSCTL_NAVL` = 0 and live sticks in POSCTL falls back to
//! ALTCTL. The height and the attitude still come from the estimate. Pure.

use super::FailsafeCause;
use super::{FlightMode, Outcome};
use crate::control::{FlatSetpoint, VehicleState};
use crate::math::Vec3;

/// Whether the estimate can be flown on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NavValidity {
    /// Roll, pitch and heading are known.
    pub attitude: bool,
    /// Horizontal position and velocity are known.
    pub horizontal: bool,
    /// Height and vertical velocity are known.
    pub vertical: bool,
    /// What is not consistent enough to arm on (the estimator's pre-flight checks, PX4's
    /// "Preflight Fail" texts), `None` when nothing.
    pub unstable: Option<&'static str>,
}

impl NavValidity {
    /// Everything known (the state sensor).
    pub const EXACT: Self = Self {
        attitude: true,
        horizontal: true,
        vertical: true,
        unstable: None,
    };
}

impl Default for NavValidity {
    fn default() -> Self {
        Self::EXACT
    }
}

impl FlightMode {
    /// True for the modes that hold or steer to a position: POSCTL, the AUTO modes, OFFBOARD,
    /// orbit and follow-me.
    pub fn needs_position(self) -> bool {
        !matches!(
            self,
            Self::Manual | Self::Altitude | Self::Acro | Self::Stabilized | Self::Land
        )
    }

    /// True for the modes that hold a height: every mode but MANUAL, ACRO and STABILIZED.
    pub fn needs_height(self) -> bool {
        !self.manual_thrust()
    }
}

/// What the commander does about the estimate this tick.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum PositionLoss {
    /// Nothing to do.
    Fly,
    /// POSCTL without a position and with live sticks: fall back to ALTCTL.
    Altitude,
    /// Descend level without a position until on the ground.
    Descend,
}

impl NavValidity {
    /// The announcement of a change of the horizontal estimate from `before` to `self`, if it
    /// changed.
    pub(super) fn position_change(&self, before: &NavValidity) -> Option<(FailsafeCause, &'static str)> {
        (self.horizontal != before.horizontal).then_some(if self.horizontal {
            (FailsafeCause::PositionRegained, "Position estimate valid again")
        } else {
            (FailsafeCause::PositionLost, "Position estimate lost")
        })
    }

    /// What to do with this estimate flying (armed, `in_air`) in `mode`, `blind` already
    /// descending without a position, the sticks `sticks_alive`, `COM_POSCTL_NAVL`
    /// (`position_loss_lands`).
    pub(super) fn position_loss(
        &self,
        mode: FlightMode,
        in_air: bool,
        blind: bool,
        sticks_alive: impl FnOnce() -> bool,
        position_loss_lands: bool,
    ) -> PositionLoss {
        if self.horizontal || !in_air || !mode.needs_position() || blind {
            return PositionLoss::Fly;
        }
        if mode == FlightMode::Position && sticks_alive() && !position_loss_lands && self.vertical {
            return PositionLoss::Altitude;
        }
        PositionLoss::Descend
    }

    /// Why `mode` cannot be flown (or armed in, `arming`) on this estimate, `arm_without_gps`
    /// (`COM_ARM_WO_GPS`), if it cannot.
    pub(super) fn refusal(&self, mode: FlightMode, arming: bool, arm_without_gps: bool) -> Option<Outcome> {
        let missing = self.missing(mode, arming, arm_without_gps)?;
        let what = if arming {
            "Arming denied".to_string()
        } else {
            format!("Mode {}", mode.name())
        };
        Some(Outcome::TemporarilyRejected(format!("{what}: {missing}")))
    }

    /// What this estimate lacks for `mode` (or for arming in it), if anything.
    pub(super) fn missing(&self, mode: FlightMode, arming: bool, arm_without_gps: bool) -> Option<&'static str> {
        let v = self;
        if arming && !v.attitude {
            Some("attitude estimate not aligned")
        } else if let (true, Some(why)) = (arming, v.unstable) {
            Some(why)
        } else if (mode.needs_position() || (arming && !arm_without_gps)) && !v.horizontal {
            Some("no valid position estimate")
        } else if mode.needs_height() && !v.vertical {
            Some("no valid height estimate")
        } else {
            None
        }
    }
}

/// A descent without a position holds no horizontal position: the setpoint takes it from
/// the estimate, and asks for zero horizontal velocity and acceleration, so the controller
/// damps the dead-reckoned velocity (good for seconds, drifting slowly) and keeps the
/// attitude near level while height and heading are controlled.
pub(super) fn without_horizontal(sp: FlatSetpoint, x: &VehicleState) -> FlatSetpoint {
    let with_xy = |v: Option<Vec3>, xy: Vec3| v.map(|v| Vec3::new(xy.x, xy.y, v.z));
    FlatSetpoint {
        pos_w: with_xy(sp.pos_w, x.pos_w),
        vel_w: with_xy(sp.vel_w, Vec3::zeros()),
        acc_w: with_xy(sp.acc_w, Vec3::zeros()),
        ..sp
    }
}

#[cfg(test)]
mod tests {
    use super::super::script::Script;
    use super::super::{CommanderParams, Event, Request};
    use super::*;

    const NO_POSITION: NavValidity = NavValidity {
        attitude: true,
        horizontal: false,
        vertical: true,
        unstable: None,
    };

    #[test]
    fn arming_and_modes_wait_for_the_estimate() {
        let mut s = Script::new(CommanderParams::default());
        s.c.check_navigation(
            NavValidity {
                attitude: false,
                ..NO_POSITION
            },
            &s.x.clone(),
            0.0,
        );
        assert_eq!(
            s.request(Request::Arm { force: false }),
            Outcome::TemporarilyRejected("Arming denied: attitude estimate not aligned".into())
        );
        s.c.check_navigation(NO_POSITION, &s.x.clone(), 0.0);
        assert_eq!(
            s.request(Request::Arm { force: false }),
            Outcome::TemporarilyRejected("Arming denied: no valid position estimate".into()),
            "AUTO.LOITER holds a position"
        );
        assert_eq!(
            s.request(Request::SetMode(FlightMode::Mission)),
            Outcome::TemporarilyRejected("Mode AUTO.MISSION: no valid position estimate".into())
        );
        let unstable = NavValidity {
            unstable: Some("height estimate not stable"),
            ..NavValidity::EXACT
        };
        s.c.check_navigation(unstable, &s.x.clone(), 0.0);
        assert_eq!(
            s.request(Request::Arm { force: false }),
            Outcome::TemporarilyRejected("Arming denied: height estimate not stable".into()),
            "the pre-flight checks hold arming back"
        );
        assert_eq!(
            s.request(Request::SetMode(FlightMode::Position)),
            Outcome::Accepted,
            "not modes"
        );
        s.c.check_navigation(NavValidity::EXACT, &s.x.clone(), 0.0);
        assert_eq!(s.request(Request::Arm { force: false }), Outcome::Accepted);
    }

    #[test]
    fn com_arm_wo_gps_0_needs_a_position_to_arm_in_every_mode() {
        let mut s = Script::new(CommanderParams::default());
        s.c.check_navigation(NO_POSITION, &s.x.clone(), 0.0);
        assert_eq!(s.c.navigation_refusal(FlightMode::Stabilized, true), None);
        let mut s = Script::new(CommanderParams {
            arm_without_gps: false,
            ..CommanderParams::default()
        });
        s.c.check_navigation(NO_POSITION, &s.x.clone(), 0.0);
        assert_eq!(
            s.c.navigation_refusal(FlightMode::Stabilized, true),
            Some(Outcome::TemporarilyRejected(
                "Arming denied: no valid position estimate".into()
            ))
        );
        assert_eq!(s.c.navigation_refusal(FlightMode::Stabilized, false), None, "not modes");
    }

    #[test]
    fn a_mode_selected_disarmed_skips_its_checks_and_arming_makes_them() {
        let mut s = Script::new(CommanderParams::default());
        s.c.check_navigation(NO_POSITION, &s.x.clone(), 0.0);
        let refused = Outcome::TemporarilyRejected("Mode POSCTL: no valid position estimate".into());
        assert_eq!(s.request(Request::SetMode(FlightMode::Position)), refused);
        assert_eq!(s.request(Request::SelectMode(FlightMode::Position)), Outcome::Accepted);
        assert_eq!(s.c.mode(), FlightMode::Position);
        assert_eq!(
            s.request(Request::Arm { force: false }),
            Outcome::TemporarilyRejected("Arming denied: no valid position estimate".into()),
            "a mode that cannot fly is never armed in"
        );
        assert_eq!(s.request(Request::SelectMode(FlightMode::Mission)), Outcome::Accepted);
        s.c.check_navigation(NavValidity::EXACT, &s.x.clone(), 0.0);
        assert_eq!(
            s.request(Request::Arm { force: false }),
            Outcome::TemporarilyRejected("Arming denied: no mission".into())
        );
        assert_eq!(s.request(Request::SelectMode(FlightMode::Position)), Outcome::Accepted);
        assert_eq!(s.request(Request::Arm { force: false }), Outcome::Accepted);
        s.c.check_navigation(NO_POSITION, &s.x.clone(), 0.0);
        assert_eq!(
            s.request(Request::SelectMode(FlightMode::Guided)),
            Outcome::TemporarilyRejected("Mode GUIDED: no valid position estimate".into()),
            "armed: checked"
        );
    }

    #[test]
    fn a_lost_position_in_flight_descends_level_to_the_ground_and_disarms() {
        let mut s = Script::new(CommanderParams::default());
        s.airborne(10.0);
        let x = s.x;
        let events = s.c.check_navigation(NO_POSITION, &x, s.t());
        assert_eq!(
            events,
            vec![
                Event::Failsafe(FailsafeCause::PositionLost, "Position estimate lost".into()),
                Event::Failsafe(
                    FailsafeCause::PositionAction(FlightMode::Land),
                    "No position estimate: descending".into()
                ),
                Event::ModeChanged(FlightMode::Land)
            ]
        );
        assert!(s.c.descending_blind());
        // The setpoints carry no horizontal position (the estimate's own) and ask for zero
        // horizontal velocity and acceleration.
        s.x.pos_w.x += 3.0;
        s.x.vel_w.y = 0.4;
        s.step();
        let sp = s.last.as_ref().and_then(|t| t.setpoint).expect("flying");
        let (p, v, a) = (sp.pos_w.unwrap(), sp.vel_w.unwrap(), sp.acc_w.unwrap());
        assert_eq!((p.x, v.y, a.x, a.y), (s.x.pos_w.x, 0.0, 0.0, 0.0));
        s.fly(1.0);
        let sp = s.last.as_ref().and_then(|t| t.setpoint).expect("flying");
        assert!(sp.vel_w.is_some_and(|v| v.z > 0.3), "descending: {sp:?}");
        assert_eq!(
            s.request(Request::SetMode(FlightMode::ReturnToLaunch)),
            Outcome::TemporarilyRejected("Mode AUTO.RTL: no valid position estimate".into())
        );
        s.x.vel_w.y = 0.0;
        assert!(s.fly_until(60.0, |s| !s.c.armed()), "lands and disarms");
        assert!(!s.c.descending_blind());
    }

    #[test]
    fn a_lost_position_descends_unless_posctl_with_sticks_falls_back_to_altctl() {
        let rtl = FlightMode::ReturnToLaunch;
        assert_eq!(
            NavValidity::EXACT.position_loss(rtl, true, false, || true, false),
            PositionLoss::Fly
        );
        assert_eq!(
            NO_POSITION.position_loss(rtl, false, false, || true, false),
            PositionLoss::Fly,
            "ground"
        );
        assert_eq!(
            NO_POSITION.position_loss(rtl, true, true, || true, false),
            PositionLoss::Fly,
            "already"
        );
        assert_eq!(
            NO_POSITION.position_loss(FlightMode::Altitude, true, false, || true, false),
            PositionLoss::Fly
        );
        assert_eq!(
            NO_POSITION.position_loss(rtl, true, false, || true, false),
            PositionLoss::Descend
        );
        let pos = FlightMode::Position;
        assert_eq!(
            NO_POSITION.position_loss(pos, true, false, || true, false),
            PositionLoss::Altitude
        );
        assert_eq!(
            NO_POSITION.position_loss(pos, true, false, || false, false),
            PositionLoss::Descend
        );
        assert_eq!(
            NO_POSITION.position_loss(pos, true, false, || true, true),
            PositionLoss::Descend
        );
        assert_eq!(
            NO_POSITION.position_change(&NavValidity::EXACT),
            Some((FailsafeCause::PositionLost, "Position estimate lost"))
        );
        assert_eq!(
            NavValidity::EXACT.position_change(&NO_POSITION),
            Some((FailsafeCause::PositionRegained, "Position estimate valid again"))
        );
        assert_eq!(NO_POSITION.position_change(&NO_POSITION), None);
        assert_eq!(NO_POSITION.missing(FlightMode::Stabilized, true, true), None);
        assert_eq!(
            NO_POSITION.missing(FlightMode::Stabilized, true, false),
            Some("no valid position estimate")
        );
    }
}
