//! The inbound messages ArduCopter treats differently from PX4 (docs/ardupilot.md §2–§3), decided
//! before the shared [`ingest`](crate::mav::ingest::ingest), which handles the rest: mode changes
//! by Copter number (SET_MODE, DO_SET_MODE), NAV_TAKEOFF only in GUIDED with p7 above home,
//! NAV_LOITER_UNLIM as LOITER, guided targets (SET_POSITION_TARGET_*, SET_ATTITUDE_TARGET, a
//! MISSION_ITEM with `current` = 2) obeyed only in GUIDED and silently ignored elsewhere. Pure.

use mavlink::dialects::ardupilotmega::{
    MavCmd, MavFrame, MavMessage, MavMissionResult, MavMissionType, COMMAND_LONG_DATA, MISSION_ITEM_INT_DATA,
};
use mavlink::MavHeader;

use super::copter_modes::mode_request;
use crate::commander::{FlightMode, Outcome, Request};
use crate::control::FlatSetpoint;
use crate::mav::identity::Identity;
use crate::mav::ingest::Action;
use crate::mav::mission_xfer::mission_ack;
use crate::mav::translate::{command_int_as_long, CommandDecision};
use crate::telemetry::Snapshot;

/// MAV_MODE_FLAG_CUSTOM_MODE_ENABLED: DO_SET_MODE p1 and SET_MODE `base_mode` must carry it.
const CUSTOM_MODE: u32 = 1;

/// What the ArduCopter face does with `message` from `sender` when the vehicle is in `state`;
/// `None`: what [`ingest`](crate::mav::ingest::ingest) decides.
#[allow(deprecated)]
pub fn copter_ingest(id: &Identity, sender: &MavHeader, message: &MavMessage, state: &Snapshot) -> Option<Action> {
    let ours = |target_system: u8, target_component: u8| id.accepts(sender, target_system, target_component);
    let guided = state.mode == FlightMode::Guided;
    match message {
        MavMessage::SET_MODE(m) if m.target_system == id.system_id => {
            Some(if u32::from(m.base_mode.bits()) & CUSTOM_MODE == 0 {
                Action::Refuse(format!(
                    "Set mode: base mode {} without the custom mode flag",
                    m.base_mode.bits()
                ))
            } else {
                match mode_request(m.custom_mode) {
                    Ok(request) => Action::Request(request),
                    Err(Outcome::Failed(why)) => Action::Refuse(why),
                    Err(other) => Action::Refuse(format!("{other:?}")),
                }
            })
        }
        MavMessage::COMMAND_LONG(c) if ours(c.target_system, c.target_component) => {
            if c.command == MavCmd::MAV_CMD_DO_REPOSITION {
                let decision = crate::mav::reposition::decode_long(c, &state.home);
                return Some(reposition(c.clone(), decision, state));
            }
            command(c, state)
        }
        MavMessage::COMMAND_INT(c) if ours(c.target_system, c.target_component) => {
            let long = command_int_as_long(c);
            if c.command == MavCmd::MAV_CMD_DO_REPOSITION {
                let decision = crate::mav::reposition::decode_int(c, &long, &state.home);
                return Some(reposition(long, decision, state));
            }
            command(&long, state)
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
            let item = MISSION_ITEM_INT_DATA {
                x: (f64::from(m.x) * 1e7).round() as i32,
                y: (f64::from(m.y) * 1e7).round() as i32,
                z: m.z,
                frame: m.frame,
                command: m.command,
                ..Default::default()
            };
            Some(guided_goto(sender, &item, state))
        }
        MavMessage::MISSION_ITEM_INT(m) if ours(m.target_system, m.target_component) && m.current == 2 => {
            Some(guided_goto(sender, m, state))
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
        _ => None,
    }
}

/// The commands Copter reads its own way; `None` for the others.
fn command(c: &COMMAND_LONG_DATA, state: &Snapshot) -> Option<Action> {
    let decision = match c.command {
        MavCmd::MAV_CMD_DO_SET_MODE if (c.param1 as u32) & CUSTOM_MODE == 0 => CommandDecision::Refuse(
            Outcome::Denied(format!("Set mode: p1 {} without the custom mode flag", c.param1)),
        ),
        MavCmd::MAV_CMD_DO_SET_MODE if !(c.param2 >= 0.0 && c.param2.fract() == 0.0) => {
            CommandDecision::Refuse(Outcome::Denied(format!("Set mode: mode {} is not a number", c.param2)))
        }
        MavCmd::MAV_CMD_DO_SET_MODE => match mode_request(c.param2 as u32) {
            Ok(request) => CommandDecision::Execute(request),
            Err(refusal) => CommandDecision::Refuse(refusal),
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
        MavCmd::MAV_CMD_CONDITION_YAW => condition_yaw(c, state.eta.z),
        _ => return None,
    };
    Some(Action::Command {
        command: c.clone(),
        decision,
    })
}

/// DO_REPOSITION as Copter reads it (MAVProxy's `guided LAT LON ALT`), from the target PX4's
/// decoding found: in GUIDED, or with the mode-change flag (then entering GUIDED), the vehicle
/// flies to it in GUIDED (unset coordinates: the current ones); in another mode without the flag,
/// DENIED.
fn reposition(command: COMMAND_LONG_DATA, decision: CommandDecision, state: &Snapshot) -> Action {
    let decision = match decision {
        CommandDecision::Execute(Request::Reposition {
            north_m,
            east_m,
            down_m,
            yaw_rad,
            change_mode,
            ..
        }) => {
            if state.mode != FlightMode::Guided && !change_mode {
                CommandDecision::Refuse(Outcome::Denied(format!(
                    "Reposition: not in GUIDED (mode {}) and no mode change asked",
                    state.mode.name()
                )))
            } else {
                let here = state.pos_w;
                let pos_w = crate::math::Vec3::new(
                    north_m.unwrap_or(here.x),
                    east_m.unwrap_or(here.y),
                    down_m.unwrap_or(here.z),
                );
                CommandDecision::Execute(Request::GuidedGoto { pos_w, yaw_rad })
            }
        }
        other => other,
    };
    Action::Command { command, decision }
}

/// CONDITION_YAW as Copter reads it: p1 the heading [deg, 0–360], p3 the direction of a relative
/// turn (−1 anti-clockwise, else clockwise), p4 1 for a turn relative to the heading `yaw_rad`
/// [rad], 0 for an absolute heading; out of range FAILED. The rate (p2) is the vehicle's own.
fn condition_yaw(c: &COMMAND_LONG_DATA, yaw_rad: f64) -> CommandDecision {
    let (angle, direction, relative) = (c.param1, c.param3, c.param4);
    if !((0.0..=360.0).contains(&angle) && (relative == 0.0 || relative == 1.0)) {
        return CommandDecision::Refuse(Outcome::Failed(format!(
            "Condition yaw: angle {angle} (0-360), relative {relative} (0 or 1)"
        )));
    }
    let angle_rad = f64::from(angle).to_radians();
    let target = if relative == 1.0 {
        yaw_rad + if direction < 0.0 { -angle_rad } else { angle_rad }
    } else {
        angle_rad
    };
    CommandDecision::Execute(Request::TurnTo {
        yaw_rad: crate::math::wrap_pi(target),
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
        MavModeFlag, MISSION_ITEM_DATA, SET_MODE_DATA, SET_POSITION_TARGET_LOCAL_NED_DATA,
    };

    fn id() -> Identity {
        Identity::autopilot(1, 4).with_personality(Personality::ArduPilot)
    }

    fn run(message: MavMessage, mode: FlightMode) -> Option<Action> {
        let mut state = Snapshot::initial(Home::default());
        state.mode = mode;
        copter_ingest(&id(), &gcs_header(0), &message, &state)
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
    fn reposition_flies_in_guided_and_needs_the_mode_change_flag_elsewhere() {
        let home = Home::default();
        let p = [
            -1.0,
            1.0,
            0.0,
            f32::NAN,
            (home.lat_deg + 1e-4) as f32,
            home.lon_deg as f32,
            (home.alt_amsl_m + 30.0) as f32,
        ];
        let decide = |p: [f32; 7], mode| match run(long(MavCmd::MAV_CMD_DO_REPOSITION, p), mode) {
            Some(Action::Command { decision, .. }) => decision,
            other => panic!("{other:?}"),
        };
        let CommandDecision::Execute(Request::GuidedGoto { pos_w, yaw_rad: None }) = decide(p, FlightMode::Loiter)
        else {
            panic!("not a guided go-to");
        };
        assert!(
            (pos_w.x - 11.1).abs() < 0.6 && (pos_w.z + 30.0).abs() < 0.01,
            "{pos_w:?}"
        );
        let without_flag = [p[0], 0.0, p[2], p[3], p[4], p[5], p[6]];
        assert!(matches!(
            decide(without_flag, FlightMode::Loiter),
            CommandDecision::Refuse(Outcome::Denied(_))
        ));
        assert!(matches!(
            decide(without_flag, FlightMode::Guided),
            CommandDecision::Execute(Request::GuidedGoto { .. })
        ));
    }

    #[test]
    fn condition_yaw_turns_to_an_absolute_or_relative_heading() {
        let yaw = |p: [f32; 7]| match run(long(MavCmd::MAV_CMD_CONDITION_YAW, p), FlightMode::Guided) {
            Some(Action::Command {
                decision: CommandDecision::Execute(Request::TurnTo { yaw_rad }),
                ..
            }) => Some(yaw_rad.to_degrees().round()),
            _ => None,
        };
        assert_eq!(yaw([90.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]), Some(90.0));
        assert_eq!(yaw([270.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0]), Some(-90.0));
        assert_eq!(
            yaw([30.0, 10.0, -1.0, 1.0, 0.0, 0.0, 0.0]),
            Some(-30.0),
            "relative to north"
        );
        assert_eq!(yaw([400.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0]), None);
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
}
