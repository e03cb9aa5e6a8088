//! The commander's reactions to what goes wrong on its own: geofence and battery failsafes,
//! rotor failures and GCS link loss (docs/mavlink.md §11.2). Each announces itself and switches the
//! mode (hold, return, land) or, for a termination, stops the motors.

use crate::allocation::FailedRotors;
use crate::control::VehicleState;

use super::{ActuatorFailureAction, Commander, Event, FailsafeAction, FlightMode, LinkLossAction, Outcome};

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
}

/// What a loss action did, for the announcement: `what` is the stream lost.
/// Below this `COM_FAIL_ACT_T` there is no hold before a failsafe action [s] (PX4's 0.1 s).
const MIN_FAIL_ACTION_DELAY_S: f64 = 0.1;

/// A failsafe's return or landing waiting out `COM_FAIL_ACT_T` in a hold.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct DelayedFailsafe {
    /// The mode the failsafe enters.
    pub mode: FlightMode,
    /// When [s].
    pub due_s: f64,
    /// The mode before the failsafe (where the pilot is given back if the cause goes away).
    pub resume: FlightMode,
}

fn loss_text(what: &str, action: LinkLossAction) -> String {
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
        let fired = self.failsafes.check_with_fence(
            &self.params.failsafe,
            [rel.x, rel.y, rel.z],
            &self.geofence,
            &x.pos_w,
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
            // Never step back from landing to a return, nor restart a return or landing already
            // running; a hold while in the hold mode stops what it was flying (a DO_REPOSITION).
            match mode {
                _ if self.mode == FlightMode::Land => {}
                Some(mode) if mode != self.mode => self.fail_to(mode, x, t_s, &mut events),
                Some(FlightMode::Loiter) => self.enter(FlightMode::Loiter, x, t_s),
                _ => {}
            }
        }
        events
    }

    /// A motor failed (`loss` says which and what the allocation did about it): announced
    /// (critical) in any case; in flight `COM_ACT_FAIL_ACT` runs: nothing more (0, PX4's
    /// default: the vehicle flies on in its mode), hold (1), land (2) or return (3), the last
    /// two after the `COM_FAIL_ACT_T` hold, or flight termination (4: motors off at once). A
    /// landing under way is never turned into a hold or a return.
    pub fn rotor_failed(&mut self, loss: RotorLoss, x: &VehicleState, t_s: f64) -> Vec<Event> {
        let action = self.params.actuator_failure_action;
        let in_air = self.armed && self.in_air();
        let did = match action {
            _ if !in_air => "",
            ActuatorFailureAction::Warn => "",
            ActuatorFailureAction::Hold => ": holding",
            ActuatorFailureAction::Land => ": landing",
            ActuatorFailureAction::Return => ": returning",
            ActuatorFailureAction::Terminate => ": terminating",
        };
        let mut events = vec![Event::Failsafe(format!("{}{did}", loss.text()))];
        if !in_air {
            return events;
        }
        let landing = self.mode == FlightMode::Land;
        match action {
            ActuatorFailureAction::Warn => {}
            ActuatorFailureAction::Hold if !landing && self.mode != FlightMode::Loiter => {
                self.enter(FlightMode::Loiter, x, t_s);
                events.push(Event::ModeChanged(FlightMode::Loiter));
            }
            ActuatorFailureAction::Land if !landing => self.fail_to(FlightMode::Land, x, t_s, &mut events),
            ActuatorFailureAction::Return if !landing && self.mode != FlightMode::ReturnToLaunch => {
                self.fail_to(FlightMode::ReturnToLaunch, x, t_s, &mut events);
            }
            ActuatorFailureAction::Terminate => {
                self.disarm();
                events.push(Event::Disarmed("flight termination"));
            }
            _ => {}
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
        let event = self.react_to_loss("GCS link", action, x, t_s);
        self.pending.push(event);
        Outcome::Accepted
    }

    /// Runs a loss `action` (hold, return, land, or 5/6 motors off; the caller has checked the
    /// vehicle flies) for the lost stream `what`; the announcement.
    pub(super) fn react_to_loss(&mut self, what: &str, action: LinkLossAction, x: &VehicleState, t_s: f64) -> Event {
        let mut events = Vec::new();
        match action {
            LinkLossAction::Hold => self.enter(FlightMode::Loiter, x, t_s),
            LinkLossAction::Return => self.fail_to(FlightMode::ReturnToLaunch, x, t_s, &mut events),
            LinkLossAction::Land => self.fail_to(FlightMode::Land, x, t_s, &mut events),
            LinkLossAction::Terminate | LinkLossAction::Disarm => self.disarm(),
            LinkLossAction::Disabled => {}
        }
        Event::Failsafe(loss_text(what, action))
    }

    /// A failsafe's `mode` (a return or a landing): after `COM_FAIL_ACT_T` in a hold (PX4's
    /// delay, for the pilot to react: a mode chosen meanwhile, or the cause going away, cancels
    /// it), at once without the delay, on the ground or already landing; a take-off under way
    /// climbs on meanwhile. The hold's mode change is in `events`; the heartbeat shows it either
    /// way.
    pub(super) fn fail_to(&mut self, mode: FlightMode, x: &VehicleState, t_s: f64, events: &mut Vec<Event>) {
        if let Some(d) = &mut self.delayed_failsafe {
            // A later failsafe within the hold (an emergency battery after the critical one)
            // takes over the waiting action, not the hold's end.
            d.mode = mode;
            return;
        }
        let delay = self.params.fail_action_delay_s;
        if delay >= MIN_FAIL_ACTION_DELAY_S && self.in_air() && self.mode != FlightMode::Land {
            let resume = self.mode;
            // A take-off under way climbs on (it ends in a hold of its own); any other mode holds.
            if self.mode != FlightMode::Takeoff {
                self.enter(FlightMode::Loiter, x, t_s);
                events.push(Event::ModeChanged(FlightMode::Loiter));
            }
            self.delayed_failsafe = Some(DelayedFailsafe {
                mode,
                due_s: t_s + delay,
                resume,
            });
        } else {
            self.enter(mode, x, t_s);
            events.push(Event::ModeChanged(mode));
        }
    }

    /// Carries out a delayed failsafe once its hold is over.
    pub(super) fn run_delayed_failsafe(&mut self, x: &VehicleState, t_s: f64, events: &mut Vec<Event>) {
        match self.delayed_failsafe {
            Some(d) if t_s >= d.due_s => {
                self.delayed_failsafe = None;
                self.enter(d.mode, x, t_s);
                events.push(Event::ModeChanged(d.mode));
            }
            _ => {}
        }
    }

    /// The cause of a delayed failsafe went away (the sticks came back): back to the mode the
    /// pilot had; true when there was one.
    pub(super) fn cancel_delayed_failsafe(&mut self, x: &VehicleState, t_s: f64, events: &mut Vec<Event>) -> bool {
        let Some(d) = self.delayed_failsafe.take() else {
            return false;
        };
        if self.mode == FlightMode::Loiter && !matches!(d.resume, FlightMode::Loiter | FlightMode::Takeoff) {
            self.enter(d.resume, x, t_s);
            events.push(Event::ModeChanged(d.resume));
        }
        true
    }

    /// A failsafe waits in its hold (no stick take-over meanwhile, as PX4).
    pub(super) fn failsafe_delayed(&self) -> bool {
        self.delayed_failsafe.is_some()
    }
}

#[cfg(test)]
mod tests {
    use super::super::script::Script;
    use super::super::{BatteryParams, CommanderParams, FailsafeParams, GeofenceAction, LowBatteryAction, Request};
    use super::*;
    use crate::math::Vec3;
    use crate::navigation::{Mission, MissionItem};

    fn failsafe_starting(s: &Script, prefix: &str) -> bool {
        s.events
            .iter()
            .any(|e| matches!(e, Event::Failsafe(t) if t.starts_with(prefix)))
    }

    /// A vehicle whose geofence (10 m around home) holds on a breach.
    fn fenced() -> Script {
        Script::new(CommanderParams {
            failsafe: FailsafeParams {
                geofence_action: GeofenceAction::Hold,
                geofence_max_hor_m: 10.0,
                ..Default::default()
            },
            ..Default::default()
        })
    }

    /// Flies until the breach, then checks the vehicle holds where it happened.
    fn holds_after_breach(s: &mut Script) {
        assert!(s.fly_until(20.0, |s| s.c.geofence_breached()));
        let breached_at = s.x.pos_w;
        assert!(failsafe_starting(s, "Geofence breached"), "{:?}", s.events);
        s.fly(10.0);
        assert!((s.x.pos_w - breached_at).norm() < 1e-9, "holds: {:?}", s.x.pos_w);
        assert!(s.x.pos_w.x < 10.1);
    }

    #[test]
    fn a_geofence_breach_holds_where_it_happened() {
        let mut s = fenced();
        // A mission leg out through the fence.
        let leg = MissionItem::Waypoint {
            pos_w: Vec3::new(30.0, 0.0, -3.0),
            hold_s: 0.0,
            accept_m: Some(0.5),
            yaw_rad: None,
        };
        let mission = Mission {
            items: vec![leg],
            ..Default::default()
        };
        assert_eq!(s.request(Request::SetMission(mission)), Outcome::Accepted);
        assert_eq!(s.request(Request::SetMode(FlightMode::Mission)), Outcome::Accepted);
        assert_eq!(s.request(Request::Arm { force: false }), Outcome::Accepted);
        s.events.clear();
        holds_after_breach(&mut s);
        assert!(
            s.events.contains(&Event::ModeChanged(FlightMode::Loiter)),
            "{:?}",
            s.events
        );
    }

    #[test]
    fn a_geofence_hold_stops_a_reposition_already_holding_mode() {
        let mut s = fenced();
        s.airborne(3.0);
        let out = Request::Reposition {
            north_m: Some(30.0),
            east_m: None,
            down_m: None,
            yaw_rad: None,
            speed_m_s: None,
            change_mode: false,
        };
        assert_eq!(s.request(out), Outcome::Accepted);
        assert_eq!(s.c.mode(), FlightMode::Loiter);
        holds_after_breach(&mut s);
    }

    #[test]
    fn a_geofence_hold_leaves_goto_for_the_hold() {
        let mut s = fenced();
        s.airborne(3.0);
        let out = Request::Reposition {
            north_m: Some(30.0),
            east_m: Some(0.0),
            down_m: None,
            yaw_rad: None,
            speed_m_s: None,
            change_mode: true,
        };
        assert_eq!(s.request(out), Outcome::Accepted);
        assert_eq!(s.c.mode(), FlightMode::Goto);
        holds_after_breach(&mut s);
        assert_eq!(s.c.mode(), FlightMode::Loiter);
        assert!(s.events.contains(&Event::ModeChanged(FlightMode::Loiter)));
    }

    #[test]
    fn a_critical_battery_lands_with_com_low_bat_act_land() {
        let mut s = Script::new(CommanderParams {
            failsafe: FailsafeParams {
                low_battery_action: LowBatteryAction::Land,
                ..Default::default()
            },
            battery: BatteryParams {
                capacity_mah: 100.0,
                cells: 3,
            },
            ..Default::default()
        });
        // 3996 J at 200 W: low after 17 s, critical after 18.6 s.
        s.power_w = 200.0;
        s.airborne(3.0);
        assert!(s.fly_until(30.0, |s| s.c.mode() == FlightMode::Land), "{:?}", s.events);
        assert!(failsafe_starting(&s, "Low battery"));
        assert!(failsafe_starting(&s, "Critical battery"));
        assert_eq!(s.events.last(), Some(&Event::ModeChanged(FlightMode::Land)));
        assert!(s.until_disarmed(30.0), "landed and disarmed");
    }

    fn loss(rotor: usize, also_off: Option<usize>, allocation: LossAllocation) -> RotorLoss {
        RotorLoss {
            rotor,
            also_off,
            allocation,
        }
    }

    #[test]
    fn a_motor_failure_is_announced_and_flown_on_by_default() {
        let mut s = Script::new(CommanderParams::default());
        let on_ground = s.c.rotor_failed(loss(3, None, LossAllocation::Impossible), &s.x, 0.0);
        assert_eq!(
            on_ground,
            vec![Event::Failsafe("Motor 3 failed, no allocation left".into())]
        );
        s.airborne(4.0);
        let (t, mode) = (s.t(), s.c.mode());
        let yaw_lost = LossAllocation::Around(FailedRotors::YawUncontrolled);
        let events = s.c.rotor_failed(loss(1, Some(4), yaw_lost), &s.x, t);
        assert_eq!(
            events,
            vec![Event::Failsafe("Motor 1 failed, motor 4 off, yaw lost".into())],
            "COM_ACT_FAIL_ACT 0: a warning only"
        );
        assert_eq!(s.c.mode(), mode, "flies on");
        assert!(s.c.armed());
    }

    #[test]
    fn com_act_fail_act_holds_lands_returns_or_terminates_in_flight() {
        let full = LossAllocation::Around(FailedRotors::FullControl);
        for (action, text, expect) in [
            (
                ActuatorFailureAction::Hold,
                "Motor 2 failed: holding",
                Some(FlightMode::Loiter),
            ),
            (
                ActuatorFailureAction::Land,
                "Motor 2 failed: landing",
                Some(FlightMode::Land),
            ),
            (
                ActuatorFailureAction::Return,
                "Motor 2 failed: returning",
                Some(FlightMode::ReturnToLaunch),
            ),
            (ActuatorFailureAction::Terminate, "Motor 2 failed: terminating", None),
        ] {
            let mut s = Script::new(CommanderParams {
                actuator_failure_action: action,
                fail_action_delay_s: 0.0,
                ..Default::default()
            });
            s.airborne(4.0);
            assert_eq!(s.request(Request::SetMode(FlightMode::Position)), Outcome::Accepted);
            let t = s.t();
            let events = s.c.rotor_failed(loss(2, None, full), &s.x, t);
            assert_eq!(events.first(), Some(&Event::Failsafe(text.into())), "{action:?}");
            match expect {
                Some(mode) => assert_eq!(s.c.mode(), mode, "{action:?}"),
                None => {
                    assert!(!s.c.armed(), "terminated");
                    assert_eq!(events.last(), Some(&Event::Disarmed("flight termination")));
                }
            }
        }
        // A landing is never turned into a return; the return waits out COM_FAIL_ACT_T in a hold.
        let mut s = Script::new(CommanderParams {
            actuator_failure_action: ActuatorFailureAction::Return,
            ..Default::default()
        });
        s.airborne(4.0);
        let t = s.t();
        s.c.rotor_failed(loss(2, None, full), &s.x, t);
        assert_eq!(s.c.mode(), FlightMode::Loiter, "COM_FAIL_ACT_T hold first");
        assert!(s.fly_until(6.0, |s| s.c.mode() == FlightMode::ReturnToLaunch));
        assert_eq!(s.request(Request::SetMode(FlightMode::Land)), Outcome::Accepted);
        let t = s.t();
        let again = s.c.rotor_failed(loss(3, None, LossAllocation::Unchanged), &s.x, t);
        assert_eq!(again, vec![Event::Failsafe("Motor 3 failed: returning".into())]);
        assert_eq!(s.c.mode(), FlightMode::Land, "still landing");
        assert!(s.until_disarmed(30.0));
    }

    #[test]
    fn gcs_link_loss_runs_nav_dll_act_in_flight_and_announces_it_on_the_next_tick() {
        for (action, expect) in [
            (LinkLossAction::Disabled, Some(FlightMode::Position)),
            (LinkLossAction::Hold, Some(FlightMode::Loiter)),
            (LinkLossAction::Return, Some(FlightMode::ReturnToLaunch)),
            (LinkLossAction::Land, Some(FlightMode::Land)),
            (LinkLossAction::Terminate, None),
            (LinkLossAction::Disarm, None),
        ] {
            let mut s = Script::new(CommanderParams {
                link_loss_action: action,
                fail_action_delay_s: 0.0,
                ..Default::default()
            });
            assert_eq!(s.request(Request::GcsLinkLost), Outcome::Accepted);
            assert!(s.step().is_empty(), "on the ground: nothing ({action:?})");
            s.airborne(3.0);
            assert_eq!(s.request(Request::SetMode(FlightMode::Position)), Outcome::Accepted);
            assert_eq!(s.request(Request::GcsLinkLost), Outcome::Accepted, "{action:?}");
            match expect {
                Some(mode) => assert_eq!(s.c.mode(), mode, "{action:?}"),
                None => assert!(!s.c.armed(), "{action:?}"),
            }
            let announced = s.step();
            if action == LinkLossAction::Disabled {
                assert!(announced.is_empty());
            } else {
                assert_eq!(announced.first(), Some(&Event::Failsafe(loss_text("GCS link", action))));
            }
            assert!(s.step().iter().all(|e| !matches!(e, Event::Failsafe(_))), "once");
        }
    }
}
