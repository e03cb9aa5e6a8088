//! The inbound messages ArduCopter treats differently from PX4 (docs/ardupilot.md §2–§3), decided
//! before the shared [`ingest`](crate::mav::ingest::ingest), which handles the rest: mode changes
//! by Copter number (SET_MODE, DO_SET_MODE), NAV_TAKEOFF only in GUIDED with p7 above home,
//! NAV_LOITER_UNLIM as LOITER, guided targets (SET_POSITION_TARGET_*, SET_ATTITUDE_TARGET, a
//! MISSION_ITEM with `current` = 2) obeyed only in GUIDED and silently ignored elsewhere; the
//! mission numbered from 1 (docs/ardupilot.md §6): MISSION_ITEM as an upload item,
//! MISSION_SET_CURRENT, DO_SET_MISSION_CURRENT and MISSION_START naming the commander's item
//! seq − 1, and AUTO refused armed on the ground unless the mission starts with a take-off. Pure.

use mavlink::dialects::ardupilotmega::{
    MavCmd, MavFrame, MavMessage, MavMissionResult, MavMissionType, MavSeverity, COMMAND_LONG_DATA,
    MISSION_ITEM_INT_DATA,
};
use mavlink::MavHeader;

use super::copter_mission::{commander_index, item_int, starts_with_takeoff, AUTO, MISSING_TAKEOFF};
use super::copter_modes::mode_request;
use crate::commander::{FlightMode, LandedState, Outcome, Request};
use crate::control::FlatSetpoint;
use crate::mav::identity::Identity;
use crate::mav::ingest::{Action, MissionStep};
use crate::mav::mission_xfer::mission_ack;
use crate::mav::stream_messages::status_text;
use crate::mav::translate::{command_int_as_long, decode_command, CommandDecision};
use crate::telemetry::Snapshot;

/// MAV_MODE_FLAG_CUSTOM_MODE_ENABLED: DO_SET_MODE p1 and SET_MODE `base_mode` must carry it.
const CUSTOM_MODE: u32 = 1;

/// What the ArduCopter face does with `message` from `sender` when the vehicle is in `state`
/// with the stored `mission` (as uploaded, item 0 the home slot); `None`: what
/// [`ingest`](crate::mav::ingest::ingest) decides.
#[allow(deprecated)]
pub fn copter_ingest(
    id: &Identity,
    sender: &MavHeader,
    message: &MavMessage,
    state: &Snapshot,
    mission: &[MISSION_ITEM_INT_DATA],
) -> Option<Action> {
    let ours = |target_system: u8, target_component: u8| id.accepts(sender, target_system, target_component);
    let guided = state.mode == FlightMode::Guided;
    let ids = (sender.system_id as u8, sender.component_id);
    let on = Facts { state, mission };
    match message {
        MavMessage::SET_MODE(m) if m.target_system == id.system_id => {
            Some(if u32::from(m.base_mode.bits()) & CUSTOM_MODE == 0 {
                Action::Refuse(format!(
                    "Set mode: base mode {} without the custom mode flag",
                    m.base_mode.bits()
                ))
            } else if m.custom_mode == AUTO && on.auto_refused() {
                Action::Reply(Box::new(status_text(
                    MavSeverity::MAV_SEVERITY_CRITICAL,
                    MISSING_TAKEOFF,
                )))
            } else {
                match mode_request(m.custom_mode) {
                    Ok(request) => Action::Request(request),
                    Err(Outcome::Failed(why)) => Action::Refuse(why),
                    Err(other) => Action::Refuse(format!("{other:?}")),
                }
            })
        }
        MavMessage::COMMAND_LONG(c) if ours(c.target_system, c.target_component) => command(id, sender, c, on),
        MavMessage::COMMAND_INT(c) if ours(c.target_system, c.target_component) => {
            command(id, sender, &command_int_as_long(c), on)
        }
        MavMessage::SET_POSITION_TARGET_LOCAL_NED(t) if ours(t.target_system, t.target_component) && !guided => {
            Some(Action::Ignore)
        }
        MavMessage::SET_POSITION_TARGET_GLOBAL_INT(t) if ours(t.target_system, t.target_component) && !guided => {
            Some(Action::Ignore)
        }
        MavMessage::SET_ATTITUDE_TARGET(t) if ours(t.target_system, t.target_component) && !guided => {
            Some(Action::Ignore)
        }
        MavMessage::MISSION_ITEM(m) if ours(m.target_system, m.target_component) && m.current == 2 => {
            Some(guided_goto(sender, &item_int(m), state))
        }
        MavMessage::MISSION_ITEM_INT(m) if ours(m.target_system, m.target_component) && m.current == 2 => {
            Some(guided_goto(sender, m, state))
        }
        // DroneKit uploads with MISSION_ITEM (float degrees): an item of the upload as any other.
        MavMessage::MISSION_ITEM(m) if ours(m.target_system, m.target_component) => Some(Action::Mission {
            ids,
            step: MissionStep::Item(Box::new(item_int(m))),
        }),
        MavMessage::MISSION_SET_CURRENT(m) if ours(m.target_system, m.target_component) => {
            Some(Action::Request(Request::SetMissionCurrent {
                seq: Some(commander_index(usize::from(m.seq))),
                reset: false,
            }))
        }
        _ => None,
    }
}

/// The Copter mode number `message` from `sender` asks for (SET_MODE, DO_SET_MODE by COMMAND_LONG
/// or COMMAND_INT, addressed to us), whether or not it can be flown.
#[allow(deprecated)]
pub fn asked_mode(id: &Identity, sender: &MavHeader, message: &MavMessage) -> Option<u32> {
    let number = |p2: f32| (p2 >= 0.0 && p2.fract() == 0.0 && p2 < 256.0).then_some(p2 as u32);
    match message {
        MavMessage::SET_MODE(m) if m.target_system == id.system_id => Some(m.custom_mode),
        MavMessage::COMMAND_LONG(c)
            if c.command == MavCmd::MAV_CMD_DO_SET_MODE && id.accepts(sender, c.target_system, c.target_component) =>
        {
            number(c.param2)
        }
        MavMessage::COMMAND_INT(c)
            if c.command == MavCmd::MAV_CMD_DO_SET_MODE && id.accepts(sender, c.target_system, c.target_component) =>
        {
            number(c.param2)
        }
        // MISSION_START switches to AUTO.
        MavMessage::COMMAND_LONG(c)
            if c.command == MavCmd::MAV_CMD_MISSION_START
                && id.accepts(sender, c.target_system, c.target_component) =>
        {
            Some(AUTO)
        }
        MavMessage::COMMAND_INT(c)
            if c.command == MavCmd::MAV_CMD_MISSION_START
                && id.accepts(sender, c.target_system, c.target_component) =>
        {
            Some(AUTO)
        }
        _ => None,
    }
}

/// What a command's decision reads: the vehicle's state and its stored mission (as uploaded).
#[derive(Clone, Copy)]
struct Facts<'a> {
    state: &'a Snapshot,
    mission: &'a [MISSION_ITEM_INT_DATA],
}

impl Facts<'_> {
    /// ArduCopter refuses AUTO armed on the ground when the mission does not start with a
    /// take-off (`ModeAuto::init`).
    fn auto_refused(self) -> bool {
        self.state.armed && self.state.landed == LandedState::OnGround && !starts_with_takeoff(self.mission)
    }
}

/// The commands Copter reads its own way; `None` for the others.
fn command(id: &Identity, sender: &MavHeader, c: &COMMAND_LONG_DATA, on: Facts) -> Option<Action> {
    let state = on.state;
    let decision = match c.command {
        MavCmd::MAV_CMD_DO_SET_MODE if (c.param1 as u32) & CUSTOM_MODE == 0 => CommandDecision::Refuse(
            Outcome::Denied(format!("Set mode: p1 {} without the custom mode flag", c.param1)),
        ),
        MavCmd::MAV_CMD_DO_SET_MODE if !(c.param2 >= 0.0 && c.param2.fract() == 0.0) => {
            CommandDecision::Refuse(Outcome::Denied(format!("Set mode: mode {} is not a number", c.param2)))
        }
        MavCmd::MAV_CMD_DO_SET_MODE if c.param2 as u32 == AUTO && on.auto_refused() => {
            CommandDecision::Critical(MISSING_TAKEOFF.into())
        }
        MavCmd::MAV_CMD_DO_SET_MODE => match mode_request(c.param2 as u32) {
            Ok(request) => CommandDecision::Execute(request),
            Err(refusal) => CommandDecision::Refuse(refusal),
        },
        // The mission's seqs count the home slot: the commander's item is seq − 1.
        MavCmd::MAV_CMD_MISSION_START => match decode_command(id, sender, c, &state.home) {
            CommandDecision::Execute(_) if on.auto_refused() => CommandDecision::Critical(MISSING_TAKEOFF.into()),
            CommandDecision::Execute(Request::StartMission { first }) => {
                CommandDecision::Execute(Request::StartMission {
                    first: commander_index(first),
                })
            }
            other => other,
        },
        MavCmd::MAV_CMD_DO_SET_MISSION_CURRENT => match decode_command(id, sender, c, &state.home) {
            CommandDecision::Execute(Request::SetMissionCurrent { seq, reset }) => {
                CommandDecision::Execute(Request::SetMissionCurrent {
                    seq: seq.map(commander_index),
                    reset,
                })
            }
            other => other,
        },
        // Copter's user take-off: p7 above home [m], in GUIDED (the commander checks the rest:
        // armed, on the ground, above the vehicle).
        MavCmd::MAV_CMD_NAV_TAKEOFF if state.mode != FlightMode::Guided => CommandDecision::Refuse(Outcome::Failed(
            format!("Takeoff: not in GUIDED (mode {})", state.mode.name()),
        )),
        MavCmd::MAV_CMD_NAV_TAKEOFF => CommandDecision::Execute(Request::Takeoff {
            height_m: Some(f64::from(c.param7)),
        }),
        MavCmd::MAV_CMD_NAV_LOITER_UNLIM => CommandDecision::Execute(Request::SetMode(FlightMode::Position)),
        _ => return None,
    };
    Some(Action::Command {
        command: c.clone(),
        decision,
    })
}

/// A MISSION_ITEM(_INT) with `current` = 2, Copter's guided go-to (DroneKit's `simple_goto`): in
/// GUIDED a NAV_WAYPOINT becomes a position target (altitude AMSL in a global frame, above home
/// in a relative one); refused with MISSION_ACK ERROR outside GUIDED or for other commands.
#[allow(deprecated)] // the `_INT` frames: pymavlink scripts still send them
fn guided_goto(sender: &MavHeader, item: &MISSION_ITEM_INT_DATA, state: &Snapshot) -> Action {
    let ids = (sender.system_id as u8, sender.component_id);
    let refuse = || {
        Action::Reply(Box::new(mission_ack(
            ids,
            MavMissionType::MAV_MISSION_TYPE_MISSION,
            MavMissionResult::MAV_MISSION_ERROR,
        )))
    };
    if state.mode != FlightMode::Guided || item.command != MavCmd::MAV_CMD_NAV_WAYPOINT {
        return refuse();
    }
    let (lat, lon) = (f64::from(item.x) * 1e-7, f64::from(item.y) * 1e-7);
    let alt_amsl_m = match item.frame {
        MavFrame::MAV_FRAME_GLOBAL | MavFrame::MAV_FRAME_GLOBAL_INT => f64::from(item.z),
        MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT | MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT_INT => {
            f64::from(item.z) + state.home.alt_amsl_m
        }
        _ => return refuse(),
    };
    if !(lat.abs() <= 90.0 && lon.abs() <= 180.0 && alt_amsl_m.is_finite()) {
        return refuse();
    }
    Action::Request(Request::offboard(FlatSetpoint {
        pos_w: Some(state.home.to_local(lat, lon, alt_amsl_m)),
        ..Default::default()
    }))
}

#[cfg(test)]
#[allow(deprecated)] // SET_MODE and MISSION_ITEM: what the scripts under test send
mod tests {
    use super::*;
    use crate::guidance::Home;
    use crate::mav::gcs::{command_long, gcs_header};
    use crate::mav::identity::Personality;
    use mavlink::dialects::ardupilotmega::{
        MavModeFlag, MISSION_ITEM_DATA, MISSION_SET_CURRENT_DATA, SET_MODE_DATA, SET_POSITION_TARGET_LOCAL_NED_DATA,
    };

    fn id() -> Identity {
        Identity::autopilot(1, 4).with_personality(Personality::ArduPilot)
    }

    fn run(message: MavMessage, mode: FlightMode) -> Option<Action> {
        let mut state = Snapshot::initial(Home::default());
        state.mode = mode;
        copter_ingest(&id(), &gcs_header(0), &message, &state, &[])
    }

    fn long(command: MavCmd, p: [f32; 7]) -> MavMessage {
        MavMessage::COMMAND_LONG(command_long((1, 0), command, p))
    }

    #[test]
    fn modes_change_by_copter_number_as_pymavlink_and_mavproxy_send_them() {
        let set_mode = |p1: f32, p2: f32| match run(
            long(MavCmd::MAV_CMD_DO_SET_MODE, [p1, p2, 0.0, 0.0, 0.0, 0.0, 0.0]),
            FlightMode::Loiter,
        ) {
            Some(Action::Command { decision, .. }) => decision,
            other => panic!("{other:?}"),
        };
        assert_eq!(
            set_mode(1.0, 4.0),
            CommandDecision::Execute(Request::SetMode(FlightMode::Guided))
        );
        assert_eq!(
            set_mode(1.0, 9.0),
            CommandDecision::Execute(Request::SetMode(FlightMode::Land))
        );
        assert!(matches!(
            set_mode(0.0, 4.0),
            CommandDecision::Refuse(Outcome::Denied(_))
        ));
        assert!(matches!(
            set_mode(1.0, 8.0),
            CommandDecision::Refuse(Outcome::Failed(_))
        ));
        let set_mode = |base_mode: u8, custom_mode: u32| {
            let message = MavMessage::SET_MODE(SET_MODE_DATA {
                custom_mode,
                target_system: 1,
                base_mode: MavModeFlag::from_bits_retain(base_mode),
            });
            run(message, FlightMode::Loiter)
        };
        // pymavlink's set_mode_send(sysid, MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, 6).
        assert_eq!(
            set_mode(1, 6),
            Some(Action::Request(Request::SetMode(FlightMode::ReturnToLaunch)))
        );
        assert_eq!(
            set_mode(81, 16),
            Some(Action::Request(Request::SetMode(FlightMode::Position)))
        );
        assert!(
            matches!(set_mode(80, 6), Some(Action::Refuse(_))),
            "no custom mode flag"
        );
        assert_eq!(
            set_mode(1, 14),
            Some(Action::Refuse("Mode change to FLIP failed: not emulated".into()))
        );
    }

    #[test]
    fn takeoff_only_in_guided_and_targets_ignored_elsewhere() {
        let takeoff = long(MavCmd::MAV_CMD_NAV_TAKEOFF, [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 10.0]);
        assert!(matches!(
            run(takeoff.clone(), FlightMode::Loiter),
            Some(Action::Command {
                decision: CommandDecision::Refuse(Outcome::Failed(_)),
                ..
            })
        ));
        assert!(matches!(
            run(takeoff, FlightMode::Guided),
            Some(Action::Command { decision: CommandDecision::Execute(Request::Takeoff { height_m: Some(h) }), .. }) if h == 10.0
        ));
        let target = MavMessage::SET_POSITION_TARGET_LOCAL_NED(SET_POSITION_TARGET_LOCAL_NED_DATA {
            target_system: 1,
            ..Default::default()
        });
        assert_eq!(run(target.clone(), FlightMode::Loiter), Some(Action::Ignore));
        assert_eq!(run(target, FlightMode::Guided), None, "decoded as PX4 decodes it");
    }

    #[test]
    fn a_mission_item_with_current_2_is_a_guided_goto() {
        let home = Home::default();
        let item = MavMessage::MISSION_ITEM(MISSION_ITEM_DATA {
            target_system: 1,
            current: 2,
            frame: MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT,
            command: MavCmd::MAV_CMD_NAV_WAYPOINT,
            x: (home.lat_deg + 1e-4) as f32,
            y: home.lon_deg as f32,
            z: 20.0,
            ..Default::default()
        });
        let Some(Action::Request(Request::OffboardSetpoint { setpoint, .. })) = run(item.clone(), FlightMode::Guided)
        else {
            panic!("not a target");
        };
        let p = setpoint.pos_w.unwrap_or_default();
        assert!(
            (p.x - 11.1).abs() < 0.6 && p.y.abs() < 1.0 && (p.z + 20.0).abs() < 1e-3,
            "{p:?}"
        );
        assert!(setpoint.vel_w.is_none(), "a position target persists");
        assert!(
            matches!(run(item, FlightMode::Loiter), Some(Action::Reply(_))),
            "MISSION_ACK ERROR outside GUIDED"
        );
    }

    #[test]
    fn mission_seqs_count_the_home_slot_and_mission_items_upload() {
        let state = Snapshot::initial(Home::default());
        let at = |message| copter_ingest(&id(), &gcs_header(0), &message, &state, &[]);
        let upload = MavMessage::MISSION_ITEM(MISSION_ITEM_DATA {
            target_system: 1,
            seq: 2,
            x: 47.5,
            command: MavCmd::MAV_CMD_NAV_WAYPOINT,
            ..Default::default()
        });
        let Some(Action::Mission {
            ids: (255, 190),
            step: MissionStep::Item(item),
        }) = at(upload)
        else {
            panic!("an upload item");
        };
        assert_eq!((item.seq, item.x), (2, 475_000_000));
        let set_current = |seq| {
            at(MavMessage::MISSION_SET_CURRENT(MISSION_SET_CURRENT_DATA {
                seq,
                target_system: 1,
                target_component: 1,
            }))
        };
        let current = |seq| {
            Some(Action::Request(Request::SetMissionCurrent {
                seq: Some(seq),
                reset: false,
            }))
        };
        assert_eq!(set_current(3), current(2));
        assert_eq!(set_current(0), current(0), "home names the first item");
        let decided = |command, p1: f32| match at(long(command, [p1, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0])) {
            Some(Action::Command { decision, .. }) => decision,
            other => panic!("{other:?}"),
        };
        assert_eq!(
            decided(MavCmd::MAV_CMD_DO_SET_MISSION_CURRENT, 4.0),
            CommandDecision::Execute(Request::SetMissionCurrent {
                seq: Some(3),
                reset: false
            })
        );
        assert_eq!(
            decided(MavCmd::MAV_CMD_MISSION_START, 0.0),
            CommandDecision::Execute(Request::StartMission { first: 0 })
        );
        assert_eq!(
            decided(MavCmd::MAV_CMD_MISSION_START, 2.0),
            CommandDecision::Execute(Request::StartMission { first: 1 })
        );
        let start = long(MavCmd::MAV_CMD_MISSION_START, [0.0; 7]);
        assert_eq!(asked_mode(&id(), &gcs_header(0), &start), Some(AUTO));
    }

    #[test]
    fn auto_armed_on_the_ground_needs_a_takeoff_first() {
        let item = |seq, command| MISSION_ITEM_INT_DATA {
            seq,
            command,
            ..Default::default()
        };
        let home = item(0, MavCmd::MAV_CMD_NAV_WAYPOINT);
        let no_takeoff = [home.clone(), item(1, MavCmd::MAV_CMD_NAV_WAYPOINT)];
        let takeoff = [home, item(1, MavCmd::MAV_CMD_NAV_TAKEOFF)];
        let mut state = Snapshot::initial(Home::default());
        state.mode = FlightMode::Guided;
        state.armed = true;
        let auto = long(MavCmd::MAV_CMD_DO_SET_MODE, [1.0, 3.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
        let decided = |state: &Snapshot, mission: &[MISSION_ITEM_INT_DATA], message: &MavMessage| match copter_ingest(
            &id(),
            &gcs_header(0),
            message,
            state,
            mission,
        ) {
            Some(Action::Command { decision, .. }) => decision,
            other => panic!("{other:?}"),
        };
        let refused = CommandDecision::Critical(MISSING_TAKEOFF.into());
        assert_eq!(decided(&state, &no_takeoff, &auto), refused);
        let start = long(MavCmd::MAV_CMD_MISSION_START, [0.0; 7]);
        assert_eq!(decided(&state, &no_takeoff, &start), refused);
        let flies = CommandDecision::Execute(Request::SetMode(FlightMode::Mission));
        assert_eq!(decided(&state, &takeoff, &auto), flies);
        state.landed = LandedState::InAir;
        assert_eq!(decided(&state, &no_takeoff, &auto), flies, "in the air");
        state.landed = LandedState::OnGround;
        state.armed = false;
        assert_eq!(decided(&state, &no_takeoff, &auto), flies, "disarmed");
        state.armed = true;
        let set_mode = MavMessage::SET_MODE(SET_MODE_DATA {
            custom_mode: 3,
            target_system: 1,
            base_mode: MavModeFlag::from_bits_retain(1),
        });
        let Some(Action::Reply(said)) = copter_ingest(&id(), &gcs_header(0), &set_mode, &state, &no_takeoff) else {
            panic!("a critical text")
        };
        assert!(matches!(*said, MavMessage::STATUSTEXT(ref t) if t.severity == MavSeverity::MAV_SEVERITY_CRITICAL));
    }
}
