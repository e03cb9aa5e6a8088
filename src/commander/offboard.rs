//! OFFBOARD: the latest setpoint of the stream, flown through the [`SetpointLimiter`] (speed,
//! acceleration and heading-rate limits, yaw rate integrated into the heading), attitude and
//! rate targets flown as they come, and the stream's loss (`COM_OF_LOSS_T`, `COM_OBL_RC_ACT`).

use crate::control::{AttitudeTarget, FlatSetpoint};
use crate::guidance::{MotionLimits, SetpointLimiter};
use crate::math::Vec3;

use super::landing::{asks_climb, FlightDemand};
use super::{FlightMode, Lean, Moment, OffboardLossAction};

/// The latest offboard target.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum OffboardTarget {
    /// Position / velocity / acceleration, with the body-frame flag.
    Flat(FlatSetpoint, bool),
    /// Attitude or rates with thrust.
    Attitude(AttitudeTarget),
    /// ArduCopter's attitude with a climb rate (GUIDED).
    Lean(Lean),
}

/// What GUIDED flies this tick ([`Offboard::guided`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum GuidedStep {
    /// The latest target.
    Fly(FlightDemand),
    /// The target's stream went silent: stop and hold here.
    Stop,
    /// No target: the mode's own guidance (a hold, a take-off climb, idle on the ground).
    Nothing,
}

/// The offboard stream: its latest target, whether the link
/// declared it lost since, and the limiter the position / velocity targets are flown
/// through (`None` until the first tick in OFFBOARD).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(super) struct Offboard {
    latest: Option<OffboardTarget>,
    /// The link heard nothing of the stream for `COM_OF_LOSS_T` since the latest target.
    lost: bool,
    limiter: Option<SetpointLimiter>,
}

impl Offboard {
    /// A new target.
    pub fn receive(&mut self, target: OffboardTarget) {
        self.latest = Some(target);
        self.lost = false;
    }

    /// The link heard nothing of the stream for `COM_OF_LOSS_T` ([`super::Request::StreamLost`]):
    /// it is lost until the next target.
    pub fn set_lost(&mut self) {
        self.lost = true;
    }

    /// The mode is entered or left: the reference starts again from the vehicle.
    pub fn restart(&mut self) {
        self.limiter = None;
    }

    /// True when a target arrived since the last [`Offboard::clear`].
    pub fn has_target(&self) -> bool {
        self.latest.is_some()
    }

    /// Forgets the latest target (GUIDED starts from a hold, whatever came before).
    pub fn clear(&mut self) {
        *self = Self::default();
    }

    /// One GUIDED tick (ArduCopter's rules): the latest target flown as in OFFBOARD; a target of
    /// position alone persists through the stream's silence (ArduCopter's position targets never
    /// time out); any other target, once the link declares its stream lost (`GUID_TIMEOUT`), is
    /// forgotten and the vehicle stops ([`GuidedStep::Stop`], once).
    pub fn guided(&mut self, now: Moment, landed: bool, motion: &MotionLimits) -> GuidedStep {
        match self.latest {
            None => GuidedStep::Nothing,
            Some(OffboardTarget::Flat(sp, _)) if self.lost && sp.vel_w.is_none() && sp.acc_w.is_none() => {
                self.lost = false;
                self.guided(now, landed, motion)
            }
            Some(_) if self.lost => {
                self.clear();
                GuidedStep::Stop
            }
            Some(_) => self
                .command(now, landed, motion)
                .map_or(GuidedStep::Nothing, GuidedStep::Fly),
        }
    }

    /// The latest position / velocity target keeps heading `yaw_rad` [rad] from now on; false
    /// when there is none (an attitude target, or nothing).
    pub fn turn_to(&mut self, yaw_rad: f64) -> bool {
        match &mut self.latest {
            Some(OffboardTarget::Flat(sp, _)) => {
                sp.yaw_rad = Some(yaw_rad);
                sp.yaw_rate_rad_s = None;
                true
            }
            _ => false,
        }
    }

    /// True when a target arrived and the link has not declared the stream lost since.
    pub fn alive(&self) -> bool {
        self.latest.is_some() && !self.lost
    }

    /// One OFFBOARD tick `now`, `landed` the land detector's verdict, within `motion`: what to
    /// fly, or `None` when the stream is lost.
    pub fn command(&mut self, now: Moment, landed: bool, motion: &MotionLimits) -> Option<FlightDemand> {
        let Moment {
            x,
            yaw_rad: yaw,
            dt_s,
            t_s: _,
        } = now;
        match self.latest {
            Some(OffboardTarget::Flat(sp, body_frame)) if self.alive() => {
                let raw = if body_frame { heading_to_world(sp, yaw) } else { sp };
                let limiter = self.limiter.get_or_insert_with(|| SetpointLimiter::at(x));
                if landed && !asks_climb(&raw, x) {
                    // Resting on the ground: the reference waits with the vehicle.
                    *limiter = SetpointLimiter::at(x);
                }
                Some(FlightDemand::Flat(limiter.step(&raw, x, motion, dt_s)))
            }
            Some(OffboardTarget::Attitude(target)) if self.alive() => {
                self.limiter = None;
                Some(FlightDemand::Attitude(target))
            }
            Some(OffboardTarget::Lean(lean)) if self.alive() => {
                self.limiter = None;
                Some(if landed && lean.climb <= 0.0 {
                    FlightDemand::Idle
                } else {
                    FlightDemand::Flat(lean_setpoint(&lean, x, motion))
                })
            }
            _ => None,
        }
    }
}

impl OffboardLossAction {
    /// `COM_OBL_RC_ACT` when the stream is lost, with the sticks live or not: 0–2 the stick mode
    /// it names (without live sticks, POSCTL, which holds position); 3 return, 4 land, 5 hold;
    /// `None` for 6 and 7, which stop the motors (the parameter's own choice of termination).
    pub(super) fn mode_on_loss(self, sticks_alive: bool) -> Option<FlightMode> {
        match self {
            OffboardLossAction::Altitude if sticks_alive => Some(FlightMode::Altitude),
            OffboardLossAction::Manual if sticks_alive => Some(FlightMode::Stabilized),
            OffboardLossAction::Position | OffboardLossAction::Altitude | OffboardLossAction::Manual => {
                Some(FlightMode::Position)
            }
            OffboardLossAction::Return => Some(FlightMode::ReturnToLaunch),
            OffboardLossAction::Land => Some(FlightMode::Land),
            OffboardLossAction::Hold => Some(FlightMode::Loiter),
            OffboardLossAction::Terminate | OffboardLossAction::Disarm => None,
        }
    }
}

/// ArduCopter's lean with a climb rate as a setpoint: the tilt as the horizontal acceleration it
/// gives at the target heading ψ (a_fwd = −g tan θ, a_right = g tan φ, turned by ψ into north and
/// east), the vehicle's own horizontal velocity (so only that acceleration acts across), and the
/// climb demand times the climb or descent speed of `motion` as the vertical velocity.
fn lean_setpoint(lean: &Lean, x: &crate::control::VehicleState, motion: &MotionLimits) -> FlatSetpoint {
    let g = crate::math::GRAVITY_M_S2;
    let (fwd, right) = (-g * lean.pitch_rad.tan(), g * lean.roll_rad.tan());
    let (s, c) = lean.yaw_rad.sin_cos();
    let climb = lean.climb.clamp(-1.0, 1.0);
    let vz = if climb >= 0.0 {
        -climb * motion.up_m_s
    } else {
        -climb * motion.down_m_s
    };
    FlatSetpoint {
        vel_w: Some(Vec3::new(x.vel_w.x, x.vel_w.y, vz)),
        acc_w: Some(Vec3::new(c * fwd - s * right, s * fwd + c * right, 0.0)),
        yaw_rad: Some(lean.yaw_rad),
        ..Default::default()
    }
}

/// Rotates a heading-frame velocity and acceleration into world NED by heading `yaw` [rad].
fn heading_to_world(sp: FlatSetpoint, yaw: f64) -> FlatSetpoint {
    let (s, c) = yaw.sin_cos();
    let rot = |v: Vec3| Vec3::new(c * v.x - s * v.y, s * v.x + c * v.y, v.z);
    FlatSetpoint {
        vel_w: sp.vel_w.map(rot),
        acc_w: sp.acc_w.map(rot),
        ..sp
    }
}

#[cfg(test)]
mod tests {
    use super::super::script::Script;
    use super::super::{CommanderParams, Event, Outcome, Request};
    use super::*;
    use crate::control::VehicleState;

    fn stream(s: &mut Script, setpoint: FlatSetpoint, seconds: f64) {
        let request = Request::offboard(setpoint);
        for _ in 0..(seconds / super::super::script::DT_S).round() as usize {
            assert_eq!(s.request(request.clone()), Outcome::Accepted);
            s.step();
        }
    }

    #[test]
    fn offboard_flies_the_stream_from_the_ground_and_its_loss_runs_com_obl_rc_act() {
        use OffboardLossAction::*;
        for (action, expect) in [
            (Position, Some(FlightMode::Position)),
            (Return, Some(FlightMode::ReturnToLaunch)),
            (Land, Some(FlightMode::Land)),
            (Hold, Some(FlightMode::Loiter)),
            (Disarm, None),
        ] {
            let mut s = Script::new(CommanderParams {
                offboard_loss_action: action,
                ..Default::default()
            });
            let target = FlatSetpoint::hold(Vec3::new(2.0, 1.0, -3.0), 0.0);
            stream(&mut s, target, 0.1);
            assert_eq!(s.request(Request::SetMode(FlightMode::Offboard)), Outcome::Accepted);
            assert_eq!(s.request(Request::Arm { force: false }), Outcome::Accepted);
            stream(&mut s, target, 10.0);
            assert!(s.c.in_air(), "{action:?}");
            assert!((s.x.pos_w - Vec3::new(2.0, 1.0, -3.0)).norm() < 0.01, "{:?}", s.x.pos_w);
            s.events.clear();
            s.fly(0.9);
            assert_eq!(s.c.mode(), FlightMode::Offboard, "within COM_OF_LOSS_T");
            s.fly(0.2);
            assert_eq!(s.events.first(), Some(&Event::OffboardLost), "{action:?}");
            match expect {
                Some(mode) => {
                    assert_eq!(s.c.mode(), mode, "{action:?}");
                    assert_eq!(s.events[1], Event::ModeChanged(mode));
                }
                None => {
                    assert!(!s.c.armed());
                    assert_eq!(s.events[1], Event::Disarmed("offboard lost (COM_OBL_RC_ACT)"));
                }
            }
        }
    }

    #[test]
    fn the_stream_is_lost_at_the_receivers_word_not_by_a_clock_of_the_commanders() {
        let mut s = Script::new(CommanderParams::default());
        s.airborne(3.0);
        let here = FlatSetpoint::hold(s.x.pos_w, 0.0);
        stream(&mut s, here, 0.1);
        assert_eq!(s.request(Request::SetMode(FlightMode::Offboard)), Outcome::Accepted);
        // The last setpoint is older than COM_OF_LOSS_T in simulated time, but the receiver
        // (here the script's link) has not declared the stream lost: it is flown.
        let x = s.x;
        s.c.update(&x, 1.0, s.t() + 3.0);
        assert_eq!(
            s.c.mode(),
            FlightMode::Offboard,
            "alive until the receiver says otherwise"
        );
        s.events.clear();
        let lost = Request::StreamLost(super::super::InputStream::Offboard);
        assert_eq!(s.request(lost), Outcome::Accepted);
        s.step();
        assert_eq!(s.events.first(), Some(&Event::OffboardLost));
        assert_eq!(s.c.mode(), FlightMode::Position);
    }

    #[test]
    fn heading_frame_vectors_turn_with_the_heading() {
        let sp = FlatSetpoint {
            vel_w: Some(Vec3::new(1.0, 0.0, 0.5)),
            acc_w: Some(Vec3::new(0.0, 2.0, 0.0)),
            ..Default::default()
        };
        let w = heading_to_world(sp, std::f64::consts::FRAC_PI_2);
        assert!((w.vel_w.unwrap_or_default() - Vec3::new(0.0, 1.0, 0.5)).norm() < 1e-12);
        assert!((w.acc_w.unwrap_or_default() - Vec3::new(-2.0, 0.0, 0.0)).norm() < 1e-12);
    }

    #[test]
    fn the_stream_lives_from_its_first_target_until_it_is_declared_lost() {
        let mut o = Offboard::default();
        assert!(!o.alive(), "nothing received");
        let sp = FlatSetpoint::hold(Vec3::new(0.0, 0.0, -2.0), 0.0);
        o.receive(OffboardTarget::Flat(sp, false));
        assert!(o.alive());
        let x = VehicleState::at_rest(0.0, Vec3::new(0.0, 0.0, -2.0));
        let motion = MotionLimits::default();
        let now = Moment {
            x: &x,
            yaw_rad: 0.0,
            dt_s: 0.01,
            t_s: 100.0,
        };
        assert!(matches!(o.command(now, false, &motion), Some(FlightDemand::Flat(_))));
        o.set_lost();
        assert!(!o.alive());
        assert_eq!(o.command(now, false, &motion), None, "lost");
        o.receive(OffboardTarget::Flat(sp, false));
        assert!(o.alive(), "alive again with the next target");
    }

    #[test]
    fn com_obl_rc_act_falls_back_to_posctl_without_sticks() {
        use OffboardLossAction::*;
        assert_eq!(Altitude.mode_on_loss(true), Some(FlightMode::Altitude));
        assert_eq!(Altitude.mode_on_loss(false), Some(FlightMode::Position));
        assert_eq!(Manual.mode_on_loss(true), Some(FlightMode::Stabilized));
        assert_eq!(Manual.mode_on_loss(false), Some(FlightMode::Position));
        assert_eq!(Hold.mode_on_loss(false), Some(FlightMode::Loiter));
        assert_eq!(Terminate.mode_on_loss(true), None);
    }
}
