//! The stick modes (PX4's manual modes) and the sticks' loss:
//! - POSCTL: the sticks fly a velocity, centred sticks hold position ([`StickReference`]);
//! - ALTCTL: the sticks set the tilt and the climb rate, the height holds;
//! - STABILIZED and MANUAL: the sticks set the tilt and the heading rate, the throttle the thrust;
//! - ACRO: the sticks set the body rates, the throttle the thrust.
//!
//! The sticks are lost after `COM_RC_LOSS_T` of silence in both clocks (the link's word covers
//! wall time, as for offboard). Their loss runs `NAV_RCL_ACT` in flight, once per loss, unless
//! `COM_RCL_EXCEPT` exempts the mode; it applies when the sticks were live at arming or the mode
//! is flown by them. A stick mode that cannot fly without sticks then holds position whatever
//! the action. In the AUTO modes, a stick moved faster than `COM_RC_STICK_OV` per second (its
//! rate of change, low-passed over 0.1 s, as PX4's manual control judges it: a stick held
//! deflected, or a throttle resting low, is not moving) takes over in POSCTL when
//! `COM_RC_OVERRIDE` allows it.

use crate::control::{AttitudeTarget, VehicleState};
use crate::math::UnitQuat;
use crate::navigation::{StickMotion, StickReference, Sticks};

use super::landing::FlightDemand;
use super::{Commander, Event, FlightMode, LinkLossAction, Outcome};

/// `COM_RCL_EXCEPT` bits.
const EXCEPT_MISSION: u8 = 1;
const EXCEPT_HOLD: u8 = 2;
const EXCEPT_OFFBOARD: u8 = 4;
/// `COM_RC_OVERRIDE` bits.
const OVERRIDE_AUTO: u8 = 1;
const OVERRIDE_OFFBOARD: u8 = 2;
/// Arming in a mode where the throttle sets the thrust needs it below this [-].
const ARM_THROTTLE_MAX: f64 = 0.2;

/// The sticks: the latest sample with the simulated time it arrived, the link's word on their
/// liveness in wall time, whether they were live at arming, whether their loss was reacted to,
/// and what the stick modes fly from.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(super) struct ManualInput {
    pub latest: Option<(Sticks, f64)>,
    pub alive_in_wall_time: bool,
    pub at_arming: bool,
    pub lost: bool,
    /// POSCTL / ALTCTL reference (`None` until the mode's first tick).
    pub reference: Option<StickReference>,
    /// STABILIZED / MANUAL heading [rad] (`None` until the mode's first tick).
    pub heading_rad: Option<f64>,
    /// Whether the pilot moves the sticks (stick take-over).
    pub motion: StickMotion,
}

impl Commander {
    /// True when sticks arrived within `COM_RC_LOSS_T` of `t_s` [s] or the link says they are
    /// alive in wall time.
    pub(super) fn sticks_alive(&self, t_s: f64) -> bool {
        self.manual
            .latest
            .is_some_and(|(_, t)| self.manual.alive_in_wall_time || t_s - t < self.params.manual.loss_s)
    }

    /// The sticks to fly: the latest while alive, else centred (hold).
    fn sticks(&self, t_s: f64) -> Sticks {
        match self.manual.latest {
            Some((s, _)) if self.sticks_alive(t_s) => s,
            _ => Sticks::CENTRED,
        }
    }

    /// Why `mode` cannot be entered (or armed in) now: the modes flown by the sticks other than
    /// POSCTL (which holds without them) need live sticks.
    pub(super) fn stick_mode_refusal(&self, mode: FlightMode, t_s: f64, arming: bool) -> Option<Outcome> {
        let needs_sticks = mode.flown_by_sticks() && mode != FlightMode::Position;
        if needs_sticks && !self.sticks_alive(t_s) {
            let what = if arming {
                "Arming denied".to_string()
            } else {
                format!("Mode {}", mode.name())
            };
            return Some(Outcome::TemporarilyRejected(format!("{what}: no manual control input")));
        }
        if arming && mode.manual_thrust() && self.sticks(t_s).throttle > ARM_THROTTLE_MAX {
            return Some(Outcome::TemporarilyRejected("Arming denied: throttle above 20%".into()));
        }
        None
    }

    /// One tick of a stick mode, `dt_s` [s] after the last: what to fly.
    pub(super) fn stick_command(&mut self, x: &VehicleState, yaw: f64, dt_s: f64, t_s: f64) -> FlightDemand {
        let sticks = self.sticks(t_s);
        let shaping = self.params.manual.shaping;
        let landed = self.detector.landed();
        match self.mode {
            FlightMode::Position | FlightMode::Altitude => {
                let reference = self.manual.reference.get_or_insert_with(|| StickReference::at(x));
                if landed && shaping.climb(&sticks) <= 0.0 {
                    // Resting on the ground: the reference waits with the vehicle.
                    *reference = StickReference::at(x);
                }
                let sp = if self.mode == FlightMode::Position {
                    reference.position(&sticks, x, &shaping, &self.params.motion, dt_s)
                } else {
                    reference.altitude(&sticks, x, &shaping, &self.params.motion, dt_s)
                };
                FlightDemand::Flat(sp)
            }
            FlightMode::Acro => FlightDemand::Attitude(AttitudeTarget {
                q_wb: None,
                omega_b: Some(shaping.acro_rates(&sticks)),
                thrust_fraction: shaping.thrust(&sticks),
            }),
            _ => {
                let heading = self.manual.heading_rad.get_or_insert(yaw);
                if landed {
                    *heading = yaw;
                } else {
                    *heading = crate::math::wrap_pi(*heading + shaping.yaw_rate(&sticks) * dt_s);
                }
                let (roll, pitch) = shaping.tilt(&sticks);
                FlightDemand::Attitude(AttitudeTarget {
                    q_wb: Some(UnitQuat::from_euler_angles(roll, pitch, *heading)),
                    omega_b: None,
                    thrust_fraction: shaping.thrust(&sticks),
                })
            }
        }
    }

    /// Each armed tick: the sticks' loss and return, and a pilot taking over an AUTO mode.
    pub(super) fn watch_sticks(&mut self, x: &VehicleState, t_s: f64, events: &mut Vec<Event>) {
        if self.manual.latest.is_none() {
            return;
        }
        if self.sticks_alive(t_s) {
            if std::mem::take(&mut self.manual.lost) {
                events.push(Event::Failsafe("Manual control regained".into()));
                self.cancel_delayed_failsafe(x, t_s, events);
            }
            self.take_over_by_sticks(x, t_s, events);
            return;
        }
        if self.manual.lost || !(self.manual.at_arming || self.mode.flown_by_sticks()) {
            return;
        }
        self.manual.lost = true;
        let p = self.params.manual;
        let exempt = match self.mode {
            FlightMode::Mission => p.loss_exceptions & EXCEPT_MISSION != 0,
            FlightMode::Loiter | FlightMode::Takeoff => p.loss_exceptions & EXCEPT_HOLD != 0,
            FlightMode::Offboard => p.loss_exceptions & EXCEPT_OFFBOARD != 0,
            _ => false,
        };
        let stick_mode = self.mode.flown_by_sticks() && self.mode != FlightMode::Position;
        let action = match LinkLossAction::from(p.loss_action) {
            _ if exempt || !self.in_air() => LinkLossAction::Disabled,
            LinkLossAction::Disabled if stick_mode => LinkLossAction::Hold,
            action => action,
        };
        events.push(self.react_to_loss("Manual control", action, x, t_s));
    }

    /// In an AUTO mode (and OFFBOARD), sticks moved faster than `COM_RC_STICK_OV` per second
    /// hand the vehicle to the pilot in POSCTL, as `COM_RC_OVERRIDE` allows.
    fn take_over_by_sticks(&mut self, x: &VehicleState, t_s: f64, events: &mut Vec<Event>) {
        let p = &self.params.manual;
        let allowed = match self.mode {
            FlightMode::Offboard => p.override_bits & OVERRIDE_OFFBOARD != 0,
            // PX4's orbit is not an AUTO mode: its yaw stick steers (yaw behaviour 4); in
            // follow-me the sticks adjust the follow.
            FlightMode::Orbit | FlightMode::FollowTarget => false,
            mode if mode.flown_by_sticks() => false,
            _ => p.override_bits & OVERRIDE_AUTO != 0,
        };
        let moved = self.manual.motion.moving(p.override_threshold);
        if allowed && moved && self.in_air() && !self.failsafe_delayed() {
            self.enter(FlightMode::Position, x, t_s);
            events.push(Event::Failsafe("Pilot took over using sticks".into()));
            events.push(Event::ModeChanged(FlightMode::Position));
        }
    }
}

#[cfg(test)]
#[path = "manual_tests.rs"]
mod tests;
