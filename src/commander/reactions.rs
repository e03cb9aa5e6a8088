//! The commander's reactions to what goes wrong on its own: geofence and battery failsafes,
//! rotor failures and GCS link loss (mavlink.md §6). Each announces itself and switches the
//! mode (hold, return, land) or, for a termination, stops the motors.

use crate::allocation::FailedRotors;
use crate::control::VehicleState;

use super::{Commander, Event, FailsafeAction, FlightMode, LinkLossAction, Outcome};

/// What NAV_DLL_ACT did, for the announcement.
fn link_loss_text(action: LinkLossAction) -> &'static str {
    match action {
        LinkLossAction::Hold => "GCS link lost: holding",
        LinkLossAction::Return => "GCS link lost: returning",
        LinkLossAction::Land => "GCS link lost: landing",
        LinkLossAction::Terminate => "GCS link lost: terminating",
        LinkLossAction::Disarm => "GCS link lost: disarming",
        LinkLossAction::Disabled => "GCS link lost",
    }
}

impl Commander {
    /// A geofence limit is breached right now (SYS_STATUS health).
    pub fn geofence_breached(&self) -> bool {
        self.failsafes.geofence_breached()
    }

    /// Draws `power_w` [W] from the battery for `dt_s` [s], then runs the geofence and battery
    /// failsafes for state `x` at `t_s` [s]: each announces itself and switches the mode (hold,
    /// return, land) or terminates, which the next heartbeat shows.
    pub fn check_failsafes(&mut self, x: &VehicleState, power_w: f64, dt_s: f64, t_s: f64) -> Vec<Event> {
        self.battery.draw(power_w, dt_s);
        let rel = x.pos_w - self.home_w;
        let in_air = self.in_air();
        let fired = self.failsafes.check(
            &self.params.failsafe,
            [rel.x, rel.y, rel.z],
            self.battery.fraction(&self.params.battery),
            in_air,
        );
        let mut events = Vec::new();
        for failsafe in fired {
            events.push(Event::Failsafe(failsafe.text));
            let mode = match failsafe.action {
                FailsafeAction::Warn => None,
                FailsafeAction::Hold => Some(FlightMode::Loiter),
                FailsafeAction::Return => Some(FlightMode::ReturnToLaunch),
                FailsafeAction::Land => Some(FlightMode::Land),
                FailsafeAction::Terminate => {
                    self.disarm();
                    events.push(Event::Disarmed("flight termination"));
                    None
                }
            };
            // Never step back from landing to a return, nor restart a mode already running.
            let landing = self.mode == FlightMode::Land;
            if let Some(mode) = mode.filter(|m| *m != self.mode && !landing) {
                self.enter(mode, x, t_s);
                events.push(Event::ModeChanged(mode));
            }
        }
        events
    }

    /// Rotor `rotor` (1-based) has failed; `control` says what the allocation can still do
    /// (`None`: nothing useful). In flight the vehicle lands where it is, as well as it can.
    pub fn rotor_failed(
        &mut self,
        rotor: usize,
        control: Option<FailedRotors>,
        x: &VehicleState,
        t_s: f64,
    ) -> Vec<Event> {
        let what = match control {
            Some(FailedRotors::FullControl) => "",
            Some(FailedRotors::YawUncontrolled) => ", yaw lost",
            None => ", no allocation left",
        };
        let in_air = self.in_air();
        let mut events = vec![Event::Failsafe(format!(
            "Motor {rotor} failed{what}{}",
            if in_air { ": landing" } else { "" }
        ))];
        if in_air && self.mode != FlightMode::Land {
            self.enter(FlightMode::Land, x, t_s);
            events.push(Event::ModeChanged(FlightMode::Land));
        }
        events
    }

    /// No GCS heartbeat for `COM_DL_LOSS_T`: runs `NAV_DLL_ACT` once if flying (hold, return,
    /// land, or 5/6 motors off). Always accepted; a reaction is announced as an
    /// [`Event::Failsafe`] of the next tick.
    pub(super) fn gcs_link_lost(&mut self, x: &VehicleState, t_s: f64) -> Outcome {
        let action = self.params.link_loss_action;
        if action == LinkLossAction::Disabled || !self.armed || !self.in_air() {
            return Outcome::Accepted;
        }
        match action {
            LinkLossAction::Hold => self.enter(FlightMode::Loiter, x, t_s),
            LinkLossAction::Return => self.enter(FlightMode::ReturnToLaunch, x, t_s),
            LinkLossAction::Land => self.enter(FlightMode::Land, x, t_s),
            LinkLossAction::Terminate | LinkLossAction::Disarm => self.disarm(),
            LinkLossAction::Disabled => {}
        }
        self.pending.push(Event::Failsafe(link_loss_text(action).to_string()));
        Outcome::Accepted
    }
}
