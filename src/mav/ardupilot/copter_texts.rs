//! What ArduCopter says where PX4 says it otherwise (docs/ardupilot.md §2): the refusal of an
//! arming ("PreArm: …", FAILED) or of a mode change ("Mode change to GUIDED failed: …", FAILED),
//! "Arming motors" / "Disarming motors" when the armed state changes, "PreArm: …" every 30 s
//! while a check fails, and the commander's own announcements Copter makes none of (mode
//! changes, take-off and landing detected). Pure.

use mavlink::dialects::ardupilotmega::MavCmd;

use super::copter_modes::CopterMode;
use crate::commander::{Event, Outcome};
use crate::telemetry::Snapshot;

/// The commander's arming refusals as Copter's pre-arm checks word them (`AP_Arming`,
/// `AP_Arming_Copter`): (the commander's reason, Copter's).
const PREARM_TEXTS: [(&str, &str); 6] = [
    ("no valid position estimate", "Need Position Estimate"),
    ("no valid height estimate", "Need Alt Estimate"),
    ("attitude estimate not aligned", "EKF attitude is bad"),
    ("vehicle outside geofence", "Fence: vehicle outside fence"),
    ("throttle above 20%", "Throttle too high"),
    ("no mission", "Auto: Missing Takeoff Cmd"),
];

/// The answer Copter gives where the commander answered `outcome` to `command` (its ACK and the
/// STATUSTEXT of its reason): an arming refusal is FAILED with "PreArm: " and Copter's wording,
/// or "Arm: NAME mode not armable" for a mode that cannot be armed in (`shown`: the Copter mode
/// number the vehicle shows); a mode change refused is FAILED with "Mode change to NAME failed: "
/// and the reason (the mode named by DO_SET_MODE's `asked` number); every other outcome as it is.
pub fn copter_outcome(command: MavCmd, (asked, shown): (Option<u32>, u8), outcome: Outcome) -> Outcome {
    let reason = match &outcome {
        Outcome::Accepted => return outcome,
        Outcome::TemporarilyRejected(why) | Outcome::Denied(why) | Outcome::Failed(why) | Outcome::Unsupported(why) => {
            why.clone()
        }
    };
    match command {
        MavCmd::MAV_CMD_COMPONENT_ARM_DISARM if reason.starts_with("Arming denied") => {
            let detail = reason.split_once(": ").map_or("", |(_, d)| d);
            if detail.starts_with("not in ") {
                let name = CopterMode::by_number(u32::from(shown)).map_or("this", |m| m.name);
                return Outcome::Failed(format!("Arm: {name} mode not armable"));
            }
            let copter = PREARM_TEXTS
                .iter()
                .find(|(ours, _)| *ours == detail)
                .map_or(detail, |(_, copter)| copter);
            Outcome::Failed(format!("PreArm: {copter}"))
        }
        MavCmd::MAV_CMD_DO_SET_MODE if !reason.starts_with("Mode change to") && !reason.starts_with("No such") => {
            let name = asked.and_then(CopterMode::by_number).map_or("?", |m| m.name);
            let detail = reason.split_once(": ").map_or(reason.as_str(), |(_, d)| d);
            Outcome::Failed(format!("Mode change to {name} failed: {detail}"))
        }
        _ => outcome,
    }
}

/// The commander's announcement of `event` as Copter makes it: `None` for those Copter does not
/// make (mode changes, take-off and landing detected, an auto-disarm: the armed state's change
/// is announced by [`ArmedNotices`]), the same for the rest.
pub fn copter_announces(event: &Event) -> bool {
    !matches!(
        event,
        Event::ModeChanged(_) | Event::Landed | Event::Airborne | Event::Disarmed(_)
    )
}

/// "Arming motors" / "Disarming motors" (ArduCopter SITL's texts) once per change of the armed
/// state the vehicle reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ArmedNotices {
    armed: bool,
}

impl ArmedNotices {
    /// The text to announce for the vehicle's latest `state`, if its armed state changed.
    pub fn handle_state(&mut self, state: &Snapshot) -> Option<&'static str> {
        if state.armed == self.armed {
            return None;
        }
        self.armed = state.armed;
        Some(if state.armed {
            "Arming motors"
        } else {
            "Disarming motors"
        })
    }
}

/// How often Copter repeats a failing pre-arm check [s] (`AP_Arming`'s display period).
pub const PREARM_PERIOD_S: f64 = 30.0;

/// Copter's periodic "PreArm: …" while disarmed and a check fails: the first failing check of
/// the navigation estimate, at once and then every [`PREARM_PERIOD_S`] of simulated time.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PreArmNotices {
    next_s: Option<f64>,
}

impl PreArmNotices {
    /// The text to say at simulated time `now_s` [s] for `state`, if one is due.
    pub fn handle_state(&mut self, now_s: f64, state: &Snapshot) -> Option<String> {
        let v = &state.nav.validity;
        let failing = if state.armed || state.nav.armable {
            None
        } else if !v.attitude {
            Some("EKF attitude is bad")
        } else if !v.horizontal {
            Some("Need Position Estimate")
        } else if !v.vertical {
            Some("Need Alt Estimate")
        } else {
            v.unstable
        };
        let Some(failing) = failing else {
            self.next_s = None;
            return None;
        };
        if self.next_s.is_some_and(|next| now_s < next) {
            return None;
        }
        self.next_s = Some(now_s + PREARM_PERIOD_S);
        Some(format!("PreArm: {failing}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::commander::{FailsafeCause, FlightMode};
    use crate::guidance::Home;

    const ARM: MavCmd = MavCmd::MAV_CMD_COMPONENT_ARM_DISARM;

    #[test]
    fn refusals_are_worded_as_copter_words_them() {
        let refused = |why: &str| Outcome::TemporarilyRejected(why.into());
        assert_eq!(
            copter_outcome(ARM, (None, 4), refused("Arming denied: no valid position estimate")),
            Outcome::Failed("PreArm: Need Position Estimate".into())
        );
        assert_eq!(
            copter_outcome(ARM, (None, 4), refused("Arming denied: something new")),
            Outcome::Failed("PreArm: something new".into())
        );
        assert_eq!(
            copter_outcome(ARM, (None, 4), refused("Disarm refused: vehicle in the air")),
            refused("Disarm refused: vehicle in the air"),
            "not an arming refusal"
        );
        assert_eq!(
            copter_outcome(
                MavCmd::MAV_CMD_DO_SET_MODE,
                (Some(3), 17),
                refused("Mode AUTO.MISSION: no mission")
            ),
            Outcome::Failed("Mode change to AUTO failed: no mission".into())
        );
        assert_eq!(copter_outcome(ARM, (None, 4), Outcome::Accepted), Outcome::Accepted);
        assert_eq!(
            copter_outcome(ARM, (None, 9), refused("Arming denied: not in AUTO.LAND")),
            Outcome::Failed("Arm: LAND mode not armable".into())
        );
    }

    #[test]
    fn a_failing_prearm_check_is_said_at_once_then_every_30_s() {
        let mut notices = PreArmNotices::default();
        let mut s = Snapshot::initial(Home::default());
        s.nav.armable = false;
        s.nav.validity.horizontal = false;
        assert_eq!(
            notices.handle_state(0.0, &s).as_deref(),
            Some("PreArm: Need Position Estimate")
        );
        assert_eq!(notices.handle_state(29.0, &s), None);
        assert!(notices.handle_state(30.0, &s).is_some());
        s.nav.armable = true;
        assert_eq!(notices.handle_state(31.0, &s), None);
        s.nav.armable = false;
        assert!(
            notices.handle_state(32.0, &s).is_some(),
            "a new failure is said at once"
        );
        s.armed = true;
        assert_eq!(notices.handle_state(100.0, &s), None);
    }

    #[test]
    fn the_armed_state_is_announced_once_per_change_and_mode_changes_not_at_all() {
        let mut notices = ArmedNotices::default();
        let mut s = Snapshot::initial(Home::default());
        assert_eq!(notices.handle_state(&s), None);
        s.armed = true;
        assert_eq!(notices.handle_state(&s), Some("Arming motors"));
        assert_eq!(notices.handle_state(&s), None);
        s.armed = false;
        assert_eq!(notices.handle_state(&s), Some("Disarming motors"));
        assert!(!copter_announces(&Event::ModeChanged(FlightMode::Loiter)));
        assert!(copter_announces(&Event::Failsafe(
            FailsafeCause::Other,
            "Battery low".into()
        )));
    }
}
