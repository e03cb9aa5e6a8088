//! The commander's reactions to what goes wrong on its own: geofence and battery failsafes,
//! rotor failures and GCS link loss (docs/mavlink.md §11.2). Each announces itself and switches the
//! mode (hold, return, land) or, for a termination, stops the motors. [`FailsafeState`] owns
//! what the failsafes remember (the geofence / battery monitor and the battery gauge, a return
//! or landing waiting out `COM_FAIL_ACT_T` in a hold, the position-loss descent); the decisions
//! are values the commander applies.

use crate::allocation::FailedRotors;
use crate::guidance::Geofence;
use crate::math::Vec3;

use super::{
    ActuatorFailureAction, BatteryGauge, CommanderParams, Failsafe, FailsafeAction, FailsafeMonitor, FlightMode,
    LinkLossAction,
};

/// A motor that just failed, as the flight controller tells the commander.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RotorLoss {
    /// The failed motor (1-based).
    pub rotor: usize,
    /// The motor opposite it, stopped by the allocation as well (1-based), if any.
    pub also_off: Option<usize>,
    /// What the allocation did about it.
    pub allocation: LossAllocation,
}

/// What the allocation did about a motor failure (`CA_FAILURE_MODE`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LossAllocation {
    /// Nothing: `CA_FAILURE_MODE` 0, or a later failure (only the first one is handled).
    Unchanged,
    /// Allocates around the stopped motors now, with what it can still control.
    Around(FailedRotors),
    /// No allocation without the motor exists; the last one stays.
    Impossible,
}

impl RotorLoss {
    /// `Motor 1 failed[, motor 4 off][, yaw lost | , no allocation left]` (within a STATUSTEXT
    /// with any action appended).
    fn text(&self) -> String {
        let off = self.also_off.map(|m| format!(", motor {m} off")).unwrap_or_default();
        let control = match self.allocation {
            LossAllocation::Around(FailedRotors::YawUncontrolled) => ", yaw lost",
            LossAllocation::Impossible => ", no allocation left",
            LossAllocation::Unchanged | LossAllocation::Around(FailedRotors::FullControl) => "",
        };
        format!("Motor {} failed{off}{control}", self.rotor)
    }

    /// The announcement of the loss with `COM_ACT_FAIL_ACT` `action` (`in_air` or not: on the
    /// ground no action runs).
    pub(super) fn announcement(&self, action: ActuatorFailureAction, in_air: bool) -> String {
        let did = match action {
            _ if !in_air => "",
            ActuatorFailureAction::Warn => "",
            ActuatorFailureAction::Hold => ": holding",
            ActuatorFailureAction::Land => ": landing",
            ActuatorFailureAction::Return => ": returning",
            ActuatorFailureAction::Terminate => ": terminating",
        };
        format!("{}{did}", self.text())
    }
}

/// What the commander does about a failure in flight.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Reaction {
    /// Nothing more than the announcement.
    Nothing,
    /// Hold in AUTO.LOITER at once.
    Hold,
    /// A failsafe's return or landing (after the `COM_FAIL_ACT_T` hold).
    FailTo(FlightMode),
    /// Motors off (flight termination).
    Terminate,
}

impl ActuatorFailureAction {
    /// `COM_ACT_FAIL_ACT` in flight in `mode`: nothing more (0), hold (1), land (2) or return
    /// (3), or flight termination (4). A landing under way is never turned into a hold or a
    /// return, and a mode already flown is not entered again.
    pub(super) fn reaction(self, mode: FlightMode) -> Reaction {
        let landing = mode == FlightMode::Land;
        match self {
            ActuatorFailureAction::Warn => Reaction::Nothing,
            ActuatorFailureAction::Hold if !landing && mode != FlightMode::Loiter => Reaction::Hold,
            ActuatorFailureAction::Land if !landing => Reaction::FailTo(FlightMode::Land),
            ActuatorFailureAction::Return if !landing && mode != FlightMode::ReturnToLaunch => {
                Reaction::FailTo(FlightMode::ReturnToLaunch)
            }
            ActuatorFailureAction::Terminate => Reaction::Terminate,
            _ => Reaction::Nothing,
        }
    }
}

impl FailsafeAction {
    /// The mode a failsafe's action switches to, if any (a warning and a termination switch to
    /// none).
    pub(super) fn mode(self) -> Option<FlightMode> {
        match self {
            FailsafeAction::Warn | FailsafeAction::Terminate => None,
            FailsafeAction::Hold => Some(FlightMode::Loiter),
            FailsafeAction::Return => Some(FlightMode::ReturnToLaunch),
            FailsafeAction::Land => Some(FlightMode::Land),
        }
    }
}

impl LinkLossAction {
    /// What a loss action does (the caller has checked the vehicle flies): hold, return, land,
    /// or 5/6 motors off.
    pub(super) fn reaction(self) -> Reaction {
        match self {
            LinkLossAction::Hold => Reaction::Hold,
            LinkLossAction::Return => Reaction::FailTo(FlightMode::ReturnToLaunch),
            LinkLossAction::Land => Reaction::FailTo(FlightMode::Land),
            LinkLossAction::Terminate | LinkLossAction::Disarm => Reaction::Terminate,
            LinkLossAction::Disabled => Reaction::Nothing,
        }
    }
}

/// Below this `COM_FAIL_ACT_T` there is no hold before a failsafe action [s] (PX4's 0.1 s).
const MIN_FAIL_ACTION_DELAY_S: f64 = 0.1;

/// A failsafe's return or landing waiting out `COM_FAIL_ACT_T` in a hold.
#[derive(Debug, Clone, Copy, PartialEq)]
struct DelayedFailsafe {
    /// The mode the failsafe enters.
    mode: FlightMode,
    /// When [s].
    due_s: f64,
    /// The mode before the failsafe (where the pilot is given back if the cause goes away).
    resume: FlightMode,
}

/// How a failsafe's return or landing starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum FailTo {
    /// Another failsafe already waits in its hold: it now ends in this one's mode.
    Retargeted,
    /// It waits out `COM_FAIL_ACT_T`; `hold`: in AUTO.LOITER, entered now (a take-off under way
    /// climbs on instead, ending in a hold of its own).
    Delayed {
        /// Enter AUTO.LOITER now.
        hold: bool,
    },
    /// At once: no delay set, on the ground or already landing.
    Now,
}

/// What the failsafes remember.
#[derive(Debug, Clone, PartialEq, Default)]
pub(super) struct FailsafeState {
    /// The geofence and battery monitor.
    monitor: FailsafeMonitor,
    /// The energy drawn.
    battery: BatteryGauge,
    /// A failsafe's return or landing waiting out `COM_FAIL_ACT_T` in a hold.
    delayed: Option<DelayedFailsafe>,
    /// Descending without a position (the position-loss failsafe) until disarmed.
    blind_descent: bool,
}

impl FailsafeState {
    /// A geofence limit is breached right now.
    pub fn geofence_breached(&self) -> bool {
        self.monitor.geofence_breached()
    }

    /// The battery gauge.
    pub fn battery(&self) -> BatteryGauge {
        self.battery
    }

    /// Draws `power_w` [W] from the battery for `dt_s` [s].
    pub fn draw(&mut self, power_w: f64, dt_s: f64) {
        self.battery.draw(power_w, dt_s);
    }

    /// Runs the geofence and battery checks of `p` for the vehicle at `pos_w` [m], `rel_home_w`
    /// [m] from home, inside `fence` or not, `in_air` or not: the failsafes that fire now.
    pub fn check(
        &mut self,
        p: &CommanderParams,
        rel_home_w: [f64; 3],
        fence: &Geofence,
        pos_w: &Vec3,
        in_air: bool,
    ) -> Vec<Failsafe> {
        self.monitor.check_with_fence(
            &p.failsafe,
            rel_home_w,
            fence,
            pos_w,
            self.battery.fraction(&p.battery),
            in_air,
        )
    }

    /// A failsafe's `mode` (a return or a landing) asked at `t_s` [s] in `current` mode,
    /// `in_air` or not, with `COM_FAIL_ACT_T` `delay_s` [s]: after the delay in a hold (PX4's,
    /// for the pilot to react: a mode chosen meanwhile, or the cause going away, cancels it), at
    /// once without the delay, on the ground or already landing.
    pub fn fail_to(&mut self, mode: FlightMode, current: FlightMode, in_air: bool, t_s: f64, delay_s: f64) -> FailTo {
        if let Some(d) = &mut self.delayed {
            // A later failsafe within the hold (an emergency battery after the critical one)
            // takes over the waiting action, not the hold's end.
            d.mode = mode;
            return FailTo::Retargeted;
        }
        if delay_s >= MIN_FAIL_ACTION_DELAY_S && in_air && current != FlightMode::Land {
            self.delayed = Some(DelayedFailsafe {
                mode,
                due_s: t_s + delay_s,
                resume: current,
            });
            FailTo::Delayed {
                hold: current != FlightMode::Takeoff,
            }
        } else {
            FailTo::Now
        }
    }

    /// The mode of a delayed failsafe whose hold is over at `t_s` [s], if one is (then no
    /// longer waiting).
    pub fn due(&mut self, t_s: f64) -> Option<FlightMode> {
        match self.delayed {
            Some(d) if t_s >= d.due_s => {
                self.delayed = None;
                Some(d.mode)
            }
            _ => None,
        }
    }

    /// The cause of a delayed failsafe went away (the sticks came back) in `current` mode: the
    /// mode the pilot had, to give back, if there was a failsafe waiting, it holds and the
    /// pilot's mode was no hold or take-off.
    pub fn cancel(&mut self, current: FlightMode) -> Option<FlightMode> {
        let d = self.delayed.take()?;
        (current == FlightMode::Loiter && !matches!(d.resume, FlightMode::Loiter | FlightMode::Takeoff))
            .then_some(d.resume)
    }

    /// The pilot chose a mode: a failsafe waiting in its hold gives way (PX4).
    pub fn give_way(&mut self) {
        self.delayed = None;
    }

    /// A failsafe waits in its hold (no stick take-over meanwhile, as PX4).
    pub fn delayed(&self) -> bool {
        self.delayed.is_some()
    }

    /// True while the vehicle descends without a position.
    pub fn descending_blind(&self) -> bool {
        self.blind_descent
    }

    /// The position-loss descent starts.
    pub fn start_blind_descent(&mut self) {
        self.blind_descent = true;
    }

    /// The position-loss descent ends (disarmed, or another mode chosen).
    pub fn end_blind_descent(&mut self) {
        self.blind_descent = false;
    }
}

/// What a loss action did, for the announcement: `what` is the stream lost.
pub(super) fn loss_text(what: &str, action: LinkLossAction) -> String {
    let did = match action {
        LinkLossAction::Hold => ": holding",
        LinkLossAction::Return => ": returning",
        LinkLossAction::Land => ": landing",
        LinkLossAction::Terminate => ": terminating",
        LinkLossAction::Disarm => ": disarming",
        LinkLossAction::Disabled => "",
    };
    format!("{what} lost{did}")
}

#[cfg(test)]
#[path = "reactions_tests.rs"]
mod tests;
