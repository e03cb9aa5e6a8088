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

use crate::control::AttitudeTarget;
use crate::guidance::{MotionLimits, StickMotion, StickReference, Sticks};
use crate::math::UnitQuat;

use super::landing::FlightDemand;
use super::{FlightMode, LinkLossAction, ManualParams, Moment, Outcome};

/// `COM_RCL_EXCEPT` bits.
const EXCEPT_MISSION: u8 = 1;
const EXCEPT_HOLD: u8 = 2;
const EXCEPT_OFFBOARD: u8 = 4;
/// `COM_RC_OVERRIDE` bits.
const OVERRIDE_AUTO: u8 = 1;
const OVERRIDE_OFFBOARD: u8 = 2;
/// Arming in a mode where the throttle sets the thrust needs it below this [-].
const ARM_THROTTLE_MAX: f64 = 0.2;

/// The sticks: the latest sample, whether the link declared them silent since, whether they were
/// live at arming, whether their loss was reacted to, and what the stick modes fly from.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(super) struct ManualInput {
    latest: Option<Sticks>,
    /// The link declared the sticks silent (`COM_RC_LOSS_T`) since the latest sample.
    silent: bool,
    at_arming: bool,
    lost: bool,
    /// POSCTL / ALTCTL reference (`None` until the mode's first tick).
    reference: Option<StickReference>,
    /// STABILIZED / MANUAL heading [rad] (`None` until the mode's first tick).
    heading_rad: Option<f64>,
    /// Whether the pilot moves the sticks (stick take-over).
    motion: StickMotion,
}

/// What the sticks' liveness asks of the commander this tick.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum StickWatch {
    /// Nothing: no sticks ever, or a loss already reacted to or that does not apply.
    Quiet,
    /// The sticks are live; `regained` after a loss.
    Alive {
        /// They were lost until now.
        regained: bool,
    },
    /// They were just lost: run this `NAV_RCL_ACT` (Disabled: announce only).
    Lost(LinkLossAction),
}

impl ManualInput {
    /// A MANUAL_CONTROL sample arrived at `t_s` [s].
    pub fn receive(&mut self, sticks: Sticks, t_s: f64) {
        self.latest = Some(sticks);
        self.silent = false;
        self.motion.sample(sticks, t_s);
    }

    /// The link heard no sticks for `COM_RC_LOSS_T` ([`super::Request::StreamLost`]): they
    /// are lost until the next sample.
    pub fn set_silent(&mut self) {
        self.silent = true;
    }

    /// True when sticks arrived and the link has not declared them silent since.
    pub fn alive(&self) -> bool {
        self.latest.is_some() && !self.silent
    }

    /// The latest sticks while they are alive.
    pub fn live(&self) -> Option<Sticks> {
        self.latest.filter(|_| self.alive())
    }

    /// The sticks to fly: the latest while alive, else centred (hold).
    fn sticks(&self) -> Sticks {
        match self.latest {
            Some(s) if self.alive() => s,
            _ => Sticks::CENTRED,
        }
    }

    /// The vehicle was armed: whether the sticks were live then, no loss yet.
    pub fn armed_at(&mut self) {
        self.at_arming = self.alive();
        self.lost = false;
    }

    /// A mode is entered: the stick modes start again from the vehicle.
    pub fn restart(&mut self) {
        self.reference = None;
        self.heading_rad = None;
    }

    /// Why `mode` cannot be entered (or armed in) now: the modes flown by the sticks other than
    /// POSCTL (which holds without them) need live sticks.
    pub fn mode_refusal(&self, mode: FlightMode, arming: bool) -> Option<Outcome> {
        let needs_sticks = mode.flown_by_sticks() && mode != FlightMode::Position;
        if needs_sticks && !self.alive() {
            let what = if arming {
                "Arming denied".to_string()
            } else {
                format!("Mode {}", mode.name())
            };
            return Some(Outcome::TemporarilyRejected(format!("{what}: no manual control input")));
        }
        if arming && mode.manual_thrust() && self.sticks().throttle > ARM_THROTTLE_MAX {
            return Some(Outcome::TemporarilyRejected("Arming denied: throttle above 20%".into()));
        }
        None
    }

    /// One tick `now` of the stick mode `mode`, `landed` the land detector's verdict, within
    /// `motion`: what to fly.
    pub fn command(
        &mut self,
        mode: FlightMode,
        now: Moment,
        landed: bool,
        p: &ManualParams,
        motion: &MotionLimits,
    ) -> FlightDemand {
        let Moment {
            x,
            yaw_rad: yaw,
            dt_s,
            t_s: _,
        } = now;
        let sticks = self.sticks();
        let shaping = p.shaping;
        match mode {
            FlightMode::Position | FlightMode::Altitude => {
                let reference = self.reference.get_or_insert_with(|| StickReference::at(x));
                if landed && shaping.climb(&sticks) <= 0.0 {
                    // Resting on the ground: the reference waits with the vehicle.
                    *reference = StickReference::at(x);
                }
                let sp = if mode == FlightMode::Position {
                    reference.position(&sticks, x, &shaping, motion, dt_s)
                } else {
                    reference.altitude(&sticks, x, &shaping, motion, dt_s)
                };
                FlightDemand::Flat(sp)
            }
            FlightMode::Acro => FlightDemand::Attitude(AttitudeTarget {
                q_wb: None,
                omega_b: Some(shaping.acro_rates(&sticks)),
                thrust_fraction: shaping.thrust(&sticks),
            }),
            _ => {
                let heading = self.heading_rad.get_or_insert(yaw);
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

    /// Each armed tick in `mode` (`in_air` or not): the sticks' loss and return. A loss is
    /// reacted to once, when the sticks were live at arming or the mode is flown by them, with
    /// `NAV_RCL_ACT` unless `COM_RCL_EXCEPT` exempts the mode or the vehicle is on the ground; a
    /// stick mode that cannot fly without sticks holds whatever the action.
    pub fn watch(&mut self, mode: FlightMode, in_air: bool, p: &ManualParams) -> StickWatch {
        if self.latest.is_none() {
            return StickWatch::Quiet;
        }
        if self.alive() {
            return StickWatch::Alive {
                regained: std::mem::take(&mut self.lost),
            };
        }
        if self.lost || !(self.at_arming || mode.flown_by_sticks()) {
            return StickWatch::Quiet;
        }
        self.lost = true;
        let exempt = match mode {
            FlightMode::Mission => p.loss_exceptions & EXCEPT_MISSION != 0,
            FlightMode::Loiter | FlightMode::Takeoff => p.loss_exceptions & EXCEPT_HOLD != 0,
            FlightMode::Offboard => p.loss_exceptions & EXCEPT_OFFBOARD != 0,
            _ => false,
        };
        let stick_mode = mode.flown_by_sticks() && mode != FlightMode::Position;
        StickWatch::Lost(match LinkLossAction::from(p.loss_action) {
            _ if exempt || !in_air => LinkLossAction::Disabled,
            LinkLossAction::Disabled if stick_mode => LinkLossAction::Hold,
            action => action,
        })
    }

    /// In an AUTO mode (and OFFBOARD), sticks moved faster than `COM_RC_STICK_OV` per second
    /// hand the vehicle to the pilot in POSCTL, as `COM_RC_OVERRIDE` allows: true when they do
    /// now in `mode`, `in_air`, no failsafe waiting in its hold (`failsafe_delayed`).
    pub fn takes_over(&self, mode: FlightMode, in_air: bool, failsafe_delayed: bool, p: &ManualParams) -> bool {
        let allowed = match mode {
            FlightMode::Offboard => p.override_bits & OVERRIDE_OFFBOARD != 0,
            // PX4's orbit is not an AUTO mode: its yaw stick steers (yaw behaviour 4); in
            // follow-me the sticks adjust the follow.
            FlightMode::Orbit | FlightMode::FollowTarget => false,
            mode if mode.flown_by_sticks() => false,
            _ => p.override_bits & OVERRIDE_AUTO != 0,
        };
        let moved = self.motion.moving(p.override_threshold);
        allowed && moved && in_air && !failsafe_delayed
    }
}

#[cfg(test)]
#[path = "manual_tests.rs"]
mod tests;
