//! OFFBOARD: the latest setpoint of the stream, flown through the [`SetpointLimiter`] (speed,
//! acceleration and heading-rate limits, yaw rate integrated into the heading), attitude and
//! rate targets flown as they come, and the stream's loss (`COM_OF_LOSS_T`, `COM_OBL_RC_ACT`).

use crate::control::{AttitudeTarget, FlatSetpoint};
use crate::guidance::{MotionLimits, SetpointLimiter};
use crate::math::Vec3;

use super::landing::{asks_climb, FlightDemand};
use super::{FlightMode, Moment, OffboardLossAction};

/// The latest offboard target.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum OffboardTarget {
    /// Position / velocity / acceleration, with the body-frame flag.
    Flat(FlatSetpoint, bool),
    /// Attitude or rates with thrust.
    Attitude(AttitudeTarget),
}

/// The offboard stream: its latest target with the simulated time it arrived, the link's word
/// on its liveness in wall time, and the limiter the position / velocity targets are flown
/// through (`None` until the first tick in OFFBOARD).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(super) struct Offboard {
    latest: Option<(OffboardTarget, f64)>,
    alive_in_wall_time: bool,
    limiter: Option<SetpointLimiter>,
}

impl Offboard {
    /// A new target, arrived at `t_s` [s].
    pub fn receive(&mut self, target: OffboardTarget, t_s: f64) {
        self.latest = Some((target, t_s));
    }

    /// The link's word on the stream's liveness in wall time.
    pub fn set_alive_in_wall_time(&mut self, alive: bool) {
        self.alive_in_wall_time = alive;
    }

    /// The mode is entered or left: the reference starts again from the vehicle.
    pub fn restart(&mut self) {
        self.limiter = None;
    }

    /// True when an offboard setpoint arrived within `loss_s` (`COM_OF_LOSS_T`) [s] of `t_s`
    /// [s], or the link says the stream is alive in wall time ([`super::Request::StreamInWallTime`]):
    /// a ground station streaming in wall time does not lose offboard just because simulated
    /// time runs faster, and a stream that stops is lost once it is silent in both clocks.
    pub fn alive(&self, t_s: f64, loss_s: f64) -> bool {
        self.latest
            .is_some_and(|(_, t)| self.alive_in_wall_time || t_s - t < loss_s)
    }

    /// One OFFBOARD tick `now`, `landed` the land detector's verdict, within `motion` and with
    /// the stream lost after `loss_s` [s]: what to fly, or `None` when the stream is lost.
    pub fn command(&mut self, now: Moment, landed: bool, motion: &MotionLimits, loss_s: f64) -> Option<FlightDemand> {
        let Moment {
            x,
            yaw_rad: yaw,
            dt_s,
            t_s,
        } = now;
        match self.latest {
            Some((OffboardTarget::Flat(sp, body_frame), _)) if self.alive(t_s, loss_s) => {
                let raw = if body_frame { heading_to_world(sp, yaw) } else { sp };
                let limiter = self.limiter.get_or_insert_with(|| SetpointLimiter::at(x));
                if landed && !asks_climb(&raw, x) {
                    // Resting on the ground: the reference waits with the vehicle.
                    *limiter = SetpointLimiter::at(x);
                }
                Some(FlightDemand::Flat(limiter.step(&raw, x, motion, dt_s)))
            }
            Some((OffboardTarget::Attitude(target), _)) if self.alive(t_s, loss_s) => {
                self.limiter = None;
                Some(FlightDemand::Attitude(target))
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
    fn a_stream_alive_in_wall_time_is_lost_only_once_silent_in_simulated_time_too() {
        let mut s = Script::new(CommanderParams::default());
        s.airborne(3.0);
        let here = FlatSetpoint::hold(s.x.pos_w, 0.0);
        stream(&mut s, here, 0.1);
        let wall = |alive| Request::StreamInWallTime {
            stream: super::super::InputStream::Offboard,
            alive,
        };
        assert_eq!(s.request(wall(true)), Outcome::Accepted);
        assert_eq!(s.request(Request::SetMode(FlightMode::Offboard)), Outcome::Accepted);
        s.fly(3.0);
        assert_eq!(s.c.mode(), FlightMode::Offboard, "alive in wall time");
        s.events.clear();
        assert_eq!(s.request(wall(false)), Outcome::Accepted);
        s.step();
        assert_eq!(s.events.first(), Some(&Event::OffboardLost), "silent in both clocks");
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
    fn the_stream_lives_com_of_loss_t_in_simulated_time_or_while_the_link_says_so() {
        let mut o = Offboard::default();
        assert!(!o.alive(0.0, 1.0), "nothing received");
        let sp = FlatSetpoint::hold(Vec3::new(0.0, 0.0, -2.0), 0.0);
        o.receive(OffboardTarget::Flat(sp, false), 10.0);
        assert!(o.alive(10.9, 1.0) && !o.alive(11.0, 1.0));
        o.set_alive_in_wall_time(true);
        assert!(o.alive(100.0, 1.0));
        let x = VehicleState {
            t_s: 0.0,
            pos_w: Vec3::new(0.0, 0.0, -2.0),
            vel_w: Vec3::zeros(),
            r_wb: crate::math::Mat3::identity(),
            omega_b: Vec3::zeros(),
        };
        let motion = MotionLimits::default();
        let now = Moment {
            x: &x,
            yaw_rad: 0.0,
            dt_s: 0.01,
            t_s: 100.0,
        };
        assert!(matches!(
            o.command(now, false, &motion, 1.0),
            Some(FlightDemand::Flat(_))
        ));
        o.set_alive_in_wall_time(false);
        assert_eq!(o.command(now, false, &motion, 1.0), None, "lost");
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
