//! OFFBOARD: the latest setpoint of the stream, flown through the [`SetpointLimiter`] (speed,
//! acceleration and heading-rate limits, yaw rate integrated into the heading), attitude and
//! rate targets flown as they come, and the stream's loss (`COM_OF_LOSS_T`, `COM_OBL_RC_ACT`).

use crate::control::{AttitudeTarget, FlatSetpoint, VehicleState};
use crate::math::Vec3;
use crate::navigation::SetpointLimiter;

use super::landing::{asks_climb, Command};
use super::{Commander, Event, FlightMode, OffboardLossAction};

/// The latest offboard target.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum OffboardTarget {
    /// Position / velocity / acceleration, with the body-frame flag.
    Flat(FlatSetpoint, bool),
    /// Attitude or rates with thrust.
    Attitude(AttitudeTarget),
}

/// The offboard stream: its latest target with the time it arrived, and the limiter the
/// position / velocity targets are flown through (`None` until the first tick in OFFBOARD).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(super) struct Offboard {
    pub latest: Option<(OffboardTarget, f64)>,
    pub limiter: Option<SetpointLimiter>,
}

impl Commander {
    /// Restamps the latest offboard setpoint at `t_s` [s]: the runtime calls this while the
    /// setpoint stream is alive in wall time, so a ground station streaming in wall time does not
    /// lose offboard just because simulated time runs faster. A stream that stops is lost once
    /// it is silent for `COM_OF_LOSS_T` in both clocks.
    pub fn refresh_offboard(&mut self, t_s: f64) {
        if let Some((_, t)) = &mut self.offboard.latest {
            *t = t.max(t_s);
        }
    }

    /// True when an offboard setpoint arrived within `COM_OF_LOSS_T` of `t_s`.
    pub(super) fn offboard_alive(&self, t_s: f64) -> bool {
        self.offboard
            .latest
            .is_some_and(|(_, t)| t_s - t < self.params.offboard_loss_s)
    }

    /// One OFFBOARD tick at heading `yaw` [rad], `dt_s` [s] after the last: what to fly, or
    /// `None` when the stream was lost and another mode took over.
    pub(super) fn offboard_command(
        &mut self,
        x: &VehicleState,
        yaw: f64,
        dt_s: f64,
        t_s: f64,
        events: &mut Vec<Event>,
    ) -> Option<Command> {
        match self.offboard.latest {
            Some((OffboardTarget::Flat(sp, body_frame), _)) if self.offboard_alive(t_s) => {
                let raw = if body_frame { heading_to_world(sp, yaw) } else { sp };
                let limiter = self.offboard.limiter.get_or_insert_with(|| SetpointLimiter::at(x));
                if self.detector.landed() && !asks_climb(&raw, x) {
                    // Resting on the ground: the reference waits with the vehicle.
                    *limiter = SetpointLimiter::at(x);
                }
                Some(Command::Flat(limiter.step(&raw, x, &self.params.motion, dt_s)))
            }
            Some((OffboardTarget::Attitude(target), _)) if self.offboard_alive(t_s) => {
                self.offboard.limiter = None;
                Some(Command::Attitude(target))
            }
            _ => {
                self.offboard_lost(x, t_s, events);
                None
            }
        }
    }

    /// `COM_OBL_RC_ACT`: without RC the stick modes hold position; 3 return, 4 land, 5 hold,
    /// 6 and 7 stop the motors (the parameter's own choice of termination).
    fn offboard_lost(&mut self, x: &VehicleState, t_s: f64, events: &mut Vec<Event>) {
        events.push(Event::OffboardLost);
        let mode = match self.params.offboard_loss_action {
            OffboardLossAction::Position | OffboardLossAction::Altitude | OffboardLossAction::Manual => {
                Some(FlightMode::Position)
            }
            OffboardLossAction::Return => Some(FlightMode::ReturnToLaunch),
            OffboardLossAction::Land => Some(FlightMode::Land),
            OffboardLossAction::Hold => Some(FlightMode::Loiter),
            OffboardLossAction::Terminate | OffboardLossAction::Disarm => None,
        };
        match mode {
            Some(mode) => {
                self.enter(mode, x, t_s);
                events.push(Event::ModeChanged(mode));
            }
            None => {
                self.disarm();
                events.push(Event::Disarmed("offboard lost (COM_OBL_RC_ACT)"));
            }
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
