//! One inbound message → what the link does with it (docs/mavlink.md §1–§9), decided without
//! sockets, clocks or shared state. Pure: the link state machine ([`LinkMachine`](super::link::LinkMachine),
//! `inbound.rs`) matches on the [`Action`] and carries it out; the fuzz target `mavlink_ingest` does the same without sockets.
//!
//! The decision functions are the protocol modules' own ([`decode_command`],
//! [`decode_command_int`], the offboard decoders, [`decode_param_set_as`], …); this module only
//! routes a message to them and applies the addressing rule of docs/mavlink.md §3.1 to the
//! messages that carry a target.

use mavlink::dialects::ardupilotmega::{MavMessage, MavMissionResult, MavMissionType, MavType, COMMAND_LONG_DATA};
use mavlink::MavHeader;

use crate::commander::Request;
use crate::guidance::{Home, Sticks};

use super::logs::LogRequest;
use super::mission_xfer::{mission_ack, uploadable, Ids};
use super::offboard::{decode_attitude_target, decode_global_target, decode_local_target};
use super::param_encoding::{decode_param_set_as, name_of};
use super::services::{ping_reply, timesync_reply};
use super::signing::SigningKey;
use super::translate::{
    command_int_as_long, decode_command, decode_command_int, decode_set_mode, CommandDecision, Identity,
};

/// What the link does with one inbound message.
#[derive(Debug, Clone, PartialEq)]
pub enum Action {
    /// Nothing: not addressed to us, or a message we only log.
    Ignore,
    /// A ground station's HEARTBEAT: restarts the GCS link-loss timer.
    GcsHeartbeat,
    /// A COMMAND_LONG, or a COMMAND_INT as the equivalent COMMAND_LONG (for the duplicate cache
    /// and the ACK), and what it means; every decision but `NotForUs` gets exactly one ACK.
    Command {
        /// The command as a COMMAND_LONG.
        command: COMMAND_LONG_DATA,
        /// What to do.
        decision: CommandDecision,
    },
    /// A commander request that gets no ACK: an offboard setpoint, MANUAL_CONTROL or SET_MODE.
    Request(Request),
    /// SET_MODE to a vehicle presented as ArduCopter, decided as DO_SET_MODE and answered, as
    /// Copter answers it, with a COMMAND_ACK whose command is the message's id, 11
    /// (docs/ardupilot.md §2).
    SetModeMessage(CommandDecision),
    /// RC_CHANNELS_OVERRIDE addressed to an ArduCopter-faced vehicle: for its RC receiver.
    RcOverride(Box<mavlink::dialects::ardupilotmega::RC_CHANNELS_OVERRIDE_DATA>),
    /// A refused message: announce the reason to the sender in a STATUSTEXT warning.
    Refuse(String),
    /// Reply to the sender with this message (PING, TIMESYNC, mission-type refusals).
    Reply(Box<MavMessage>),
    /// REQUEST_DATA_STREAM on this link.
    DataStream {
        /// MAV_DATA_STREAM id.
        stream_id: u8,
        /// Rate [Hz].
        rate_hz: u16,
        /// Start (true) or stop.
        start: bool,
    },
    /// FILE_TRANSFER_PROTOCOL addressed to us: the 251-byte MAVLink FTP payload.
    Ftp(Box<[u8; 251]>),
    /// LOG_REQUEST_LIST, LOG_REQUEST_DATA, LOG_REQUEST_END or LOG_ERASE addressed to us.
    Log(LogRequest),
    /// SERIAL_CONTROL for the shell device addressed to us (not a reply).
    Shell(Box<mavlink::dialects::ardupilotmega::SERIAL_CONTROL_DATA>),
    /// PARAM_REQUEST_LIST: stream every parameter to the sender.
    ParamList,
    /// PARAM_REQUEST_READ: one parameter by `index`, or by `name` when no index is given.
    ParamRead {
        /// Parameter name (used when `index` is `None`).
        name: String,
        /// Parameter index.
        index: Option<usize>,
    },
    /// PARAM_SET: set `name` to `value` (decoded by its MAV_PARAM_TYPE).
    ParamSet {
        /// Parameter name.
        name: String,
        /// Value (INT32 types decoded byte-wise).
        value: f64,
    },
    /// SETUP_SIGNING addressed to us exactly (never broadcast): the new key (all zero: signing
    /// off) and initial timestamp [10 µs]. Whether it may apply (not armed; signed with the
    /// current key once there is one) is the link's to check.
    SetupSigning {
        /// The key (its `Debug` is redacted).
        key: SigningKey,
        /// Initial timestamp [10 µs since 2015].
        initial_timestamp: u64,
    },
    /// A step of the mission protocol from the peer with MAVLink ids `ids`.
    Mission {
        /// The sender's system and component ids (targets of the replies).
        ids: Ids,
        /// What it asks.
        step: MissionStep,
    },
}

/// A mission-protocol message addressed to us (docs/mavlink.md §7), mission type already checked
/// where the protocol step needs it; the replies carry the request's mission type.
#[derive(Debug, Clone, PartialEq)]
pub enum MissionStep {
    /// MISSION_COUNT: start (or, with 0, clear) an upload.
    Count(mavlink::dialects::ardupilotmega::MISSION_COUNT_DATA),
    /// MISSION_ITEM_INT of an upload.
    Item(Box<mavlink::dialects::ardupilotmega::MISSION_ITEM_INT_DATA>),
    /// MISSION_CLEAR_ALL of the mission, fence or rally plan, or of all three (MAV_MISSION_TYPE_ALL).
    Clear(MavMissionType),
    /// MISSION_REQUEST_LIST: start a download of the mission, fence or rally plan.
    RequestList(MavMissionType),
    /// MISSION_REQUEST_INT / MISSION_REQUEST: one item of a download.
    RequestItem {
        /// Item index.
        seq: u16,
        /// The plan asked for.
        mission_type: MavMissionType,
        /// Asked with MISSION_REQUEST_INT (false: MISSION_REQUEST, which ArduCopter answers with
        /// MISSION_ITEM; PX4 answers both with MISSION_ITEM_INT).
        int_form: bool,
    },
}

/// FOLLOW_TARGET (it names no target: every vehicle hears it): the target's position (degE7,
/// AMSL) and, when the capabilities' velocity bit (1) is set, its velocity; a position that is
/// not a place is refused by name.
fn follow_target(t: &mavlink::dialects::ardupilotmega::FOLLOW_TARGET_DATA, origin: &Home) -> Action {
    let (lat, lon, alt) = (f64::from(t.lat) * 1e-7, f64::from(t.lon) * 1e-7, f64::from(t.alt));
    if !(lat.abs() <= 90.0 && lon.abs() <= 180.0 && alt.is_finite()) {
        return Action::Refuse(format!("FOLLOW_TARGET: {lat}, {lon}, {alt} m is not a place"));
    }
    let vel = t.vel.map(f64::from);
    let vel_w = if t.est_capabilities & 2 != 0 && vel.iter().all(|v| v.is_finite()) {
        crate::math::Vec3::new(vel[0], vel[1], vel[2])
    } else {
        crate::math::Vec3::zeros()
    };
    Action::Request(Request::FollowTarget {
        pos_w: origin.to_local(lat, lon, alt),
        vel_w,
    })
}

/// What the link does with `message` from `sender`; `origin` is the vehicle's home (global
/// coordinates → local NED) and `now_ns` the link's clock for TIMESYNC [ns].
///
/// ```
/// use rotorpilot::commander::Request;
/// use rotorpilot::mav::ingest::{ingest, Action};
/// use rotorpilot::mav::translate::{CommandDecision, Identity};
/// use rotorpilot::mav::gcs::{command_long, gcs_header};
/// use rotorpilot::mav::{MavCmd, MavMessage};
/// let arm = command_long((1, 1), MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
/// let message = MavMessage::COMMAND_LONG(arm);
/// let action = ingest(&Identity::autopilot(1, 4), &gcs_header(0), &message, &Default::default(), 0);
/// assert!(matches!(action, Action::Command {
///     decision: CommandDecision::Execute(Request::Arm { force: false }), ..
/// }));
/// ```
#[allow(deprecated)]
pub fn ingest(id: &Identity, sender: &MavHeader, message: &MavMessage, origin: &Home, now_ns: i64) -> Action {
    let ours = |target_system: u8, target_component: u8| id.accepts(sender, target_system, target_component);
    let ids = (sender.system_id as u8, sender.component_id);
    let mission = |step: MissionStep| Action::Mission { ids, step };
    let clearable = |t: MavMissionType| uploadable(t) || t == MavMissionType::MAV_MISSION_TYPE_ALL;
    let unsupported_type =
        |t: MavMissionType| Action::Reply(Box::new(mission_ack(ids, t, MavMissionResult::MAV_MISSION_UNSUPPORTED)));
    let offboard = |decoded: Result<super::offboard::DecodedOffboard, String>| match decoded {
        Ok(target) => Action::Request(Request::OffboardSetpoint {
            setpoint: target.setpoint,
            body_frame: target.body_frame,
        }),
        Err(why) => Action::Refuse(why),
    };
    match message {
        MavMessage::MISSION_COUNT(m) if ours(m.target_system, m.target_component) => {
            mission(MissionStep::Count(m.clone()))
        }
        MavMessage::MISSION_ITEM_INT(m) if ours(m.target_system, m.target_component) => {
            mission(MissionStep::Item(Box::new(m.clone())))
        }
        MavMessage::MISSION_CLEAR_ALL(m) if ours(m.target_system, m.target_component) => {
            if clearable(m.mission_type) {
                mission(MissionStep::Clear(m.mission_type))
            } else {
                unsupported_type(m.mission_type)
            }
        }
        MavMessage::MISSION_REQUEST_LIST(m) if ours(m.target_system, m.target_component) => match m.mission_type {
            MavMissionType::MAV_MISSION_TYPE_MISSION
            | MavMissionType::MAV_MISSION_TYPE_FENCE
            | MavMissionType::MAV_MISSION_TYPE_RALLY => mission(MissionStep::RequestList(m.mission_type)),
            other => unsupported_type(other),
        },
        MavMessage::MISSION_REQUEST_INT(m) if ours(m.target_system, m.target_component) => {
            mission(MissionStep::RequestItem {
                seq: m.seq,
                mission_type: m.mission_type,
                int_form: true,
            })
        }
        MavMessage::MISSION_REQUEST(m) if ours(m.target_system, m.target_component) => {
            mission(MissionStep::RequestItem {
                seq: m.seq,
                mission_type: m.mission_type,
                int_form: false,
            })
        }
        MavMessage::MISSION_SET_CURRENT(m) if ours(m.target_system, m.target_component) => {
            Action::Request(Request::SetMissionCurrent {
                seq: Some(usize::from(m.seq)),
                reset: false,
            })
        }
        MavMessage::HEARTBEAT(hb) if hb.mavtype == MavType::MAV_TYPE_GCS => Action::GcsHeartbeat,
        MavMessage::COMMAND_LONG(cmd) => Action::Command {
            command: cmd.clone(),
            decision: decode_command(id, sender, cmd, origin),
        },
        MavMessage::COMMAND_INT(cmd) => Action::Command {
            command: command_int_as_long(cmd),
            decision: decode_command_int(id, sender, cmd, origin),
        },
        MavMessage::PING(p) => ping_reply(sender, p).map_or(Action::Ignore, |r| Action::Reply(Box::new(r))),
        MavMessage::TIMESYNC(t) => {
            timesync_reply(sender, t, now_ns).map_or(Action::Ignore, |r| Action::Reply(Box::new(r)))
        }
        MavMessage::SET_POSITION_TARGET_LOCAL_NED(t) if ours(t.target_system, t.target_component) => {
            offboard(decode_local_target(t))
        }
        MavMessage::SET_POSITION_TARGET_GLOBAL_INT(t) if ours(t.target_system, t.target_component) => {
            offboard(decode_global_target(t, origin))
        }
        MavMessage::SET_ATTITUDE_TARGET(t) if ours(t.target_system, t.target_component) => {
            match decode_attitude_target(t) {
                Ok(target) => Action::Request(Request::OffboardAttitude(target)),
                Err(why) => Action::Refuse(why),
            }
        }
        MavMessage::FOLLOW_TARGET(t) => follow_target(t, origin),
        MavMessage::REQUEST_EVENT(r) if ours(r.target_system, r.target_component) => {
            Action::Reply(Box::new(super::events::event_unavailable(r, ids)))
        }
        MavMessage::MANUAL_CONTROL(m) if ours(m.target, 0) => match Sticks::from_manual_control(m.x, m.y, m.z, m.r) {
            Ok(sticks) => Action::Request(Request::ManualControl(sticks)),
            Err(why) => Action::Refuse(why.to_string()),
        },
        MavMessage::REQUEST_DATA_STREAM(r) if ours(r.target_system, r.target_component) => Action::DataStream {
            stream_id: r.req_stream_id as u8,
            rate_hz: r.req_message_rate,
            start: r.start_stop != 0,
        },
        MavMessage::PARAM_REQUEST_LIST(r) if ours(r.target_system, r.target_component) => Action::ParamList,
        MavMessage::PARAM_REQUEST_READ(r) if ours(r.target_system, r.target_component) => Action::ParamRead {
            name: name_of(&r.param_id),
            index: usize::try_from(r.param_index).ok(),
        },
        MavMessage::PARAM_SET(set) if ours(set.target_system, set.target_component) => {
            let (name, value) = decode_param_set_as(id.personality, set);
            Action::ParamSet { name, value }
        }
        MavMessage::FILE_TRANSFER_PROTOCOL(f) if ours(f.target_system, f.target_component) => {
            Action::Ftp(Box::new(f.payload))
        }
        MavMessage::SERIAL_CONTROL(m)
            if ours(m.target_system, m.target_component)
                && m.device == mavlink::dialects::ardupilotmega::SerialControlDev::SERIAL_CONTROL_DEV_SHELL
                && !m
                    .flags
                    .contains(mavlink::dialects::ardupilotmega::SerialControlFlag::SERIAL_CONTROL_FLAG_REPLY) =>
        {
            Action::Shell(Box::new(m.clone()))
        }
        MavMessage::SETUP_SIGNING(m) if m.target_system == id.system_id && m.target_component == id.component_id => {
            Action::SetupSigning {
                key: SigningKey::from_bytes(m.secret_key),
                initial_timestamp: m.initial_timestamp,
            }
        }
        MavMessage::LOG_REQUEST_LIST(r) if ours(r.target_system, r.target_component) => Action::Log(LogRequest::List {
            start: r.start,
            end: r.end,
        }),
        MavMessage::LOG_REQUEST_DATA(r) if ours(r.target_system, r.target_component) => Action::Log(LogRequest::Data {
            id: r.id,
            offset: r.ofs,
            count: r.count,
        }),
        MavMessage::LOG_REQUEST_END(r) if ours(r.target_system, r.target_component) => Action::Log(LogRequest::End),
        MavMessage::LOG_ERASE(r) if ours(r.target_system, r.target_component) => Action::Log(LogRequest::Erase),
        // MISSION_ACK ends a download; nothing to answer.
        MavMessage::MISSION_ACK(_) => Action::Ignore,
        // SET_MODE has no ACK; the next heartbeat shows the result.
        other => decode_set_mode(id, other).map_or(Action::Ignore, |mode| Action::Request(Request::SetMode(mode))),
    }
}

#[cfg(test)]
#[allow(deprecated)]
mod tests {
    use super::*;
    use crate::commander::FlightMode;
    use crate::mav::gcs::{command_long, gcs_header};
    use mavlink::dialects::ardupilotmega::{
        MavCmd, MavFrame, PositionTargetTypemask, HEARTBEAT_DATA, MISSION_CLEAR_ALL_DATA, MISSION_COUNT_DATA,
        MISSION_REQUEST_LIST_DATA, PARAM_REQUEST_READ_DATA, PARAM_SET_DATA, SET_MODE_DATA,
        SET_POSITION_TARGET_LOCAL_NED_DATA,
    };

    fn run(message: MavMessage) -> Action {
        ingest(
            &Identity::autopilot(1, 4),
            &gcs_header(0),
            &message,
            &Home::default(),
            0,
        )
    }

    #[test]
    fn commands_heartbeats_and_set_mode_route_to_their_decoders() {
        let takeoff = command_long((1, 1), MavCmd::MAV_CMD_NAV_TAKEOFF, [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 3.0]);
        assert_eq!(
            run(MavMessage::COMMAND_LONG(takeoff.clone())),
            Action::Command {
                command: takeoff,
                decision: CommandDecision::Execute(Request::Takeoff { height_m: Some(3.0) })
            }
        );
        let gcs_hb = HEARTBEAT_DATA {
            mavtype: MavType::MAV_TYPE_GCS,
            ..Default::default()
        };
        assert_eq!(run(MavMessage::HEARTBEAT(gcs_hb)), Action::GcsHeartbeat);
        assert_eq!(run(MavMessage::HEARTBEAT(HEARTBEAT_DATA::default())), Action::Ignore);
        let set_mode = SET_MODE_DATA {
            custom_mode: FlightMode::Land.custom_mode(),
            target_system: 1,
            ..Default::default()
        };
        assert_eq!(
            run(MavMessage::SET_MODE(set_mode)),
            Action::Request(Request::SetMode(FlightMode::Land))
        );
    }

    #[test]
    fn offboard_setpoints_and_refusals() {
        let mut sp = SET_POSITION_TARGET_LOCAL_NED_DATA {
            z: -2.0,
            type_mask: PositionTargetTypemask::from_bits_truncate(2552),
            coordinate_frame: MavFrame::MAV_FRAME_LOCAL_NED,
            target_system: 1,
            target_component: 1,
            ..Default::default()
        };
        assert!(matches!(
            run(MavMessage::SET_POSITION_TARGET_LOCAL_NED(sp.clone())),
            Action::Request(Request::OffboardSetpoint { body_frame: false, .. })
        ));
        sp.coordinate_frame = MavFrame::MAV_FRAME_GLOBAL;
        assert!(matches!(
            run(MavMessage::SET_POSITION_TARGET_LOCAL_NED(sp.clone())),
            Action::Refuse(why) if why.contains("frame")
        ));
        sp.target_system = 2;
        assert_eq!(run(MavMessage::SET_POSITION_TARGET_LOCAL_NED(sp)), Action::Ignore);
    }

    #[test]
    fn parameters_and_missions_are_addressed() {
        let mut id = [0u8; 16];
        id[..7].copy_from_slice(b"RP_CTRL");
        let set = PARAM_SET_DATA {
            param_value: f32::from_bits(2),
            target_system: 1,
            target_component: 1,
            param_id: id.into(),
            param_type: mavlink::dialects::ardupilotmega::MavParamType::MAV_PARAM_TYPE_INT32,
        };
        assert_eq!(
            run(MavMessage::PARAM_SET(set)),
            Action::ParamSet {
                name: "RP_CTRL".into(),
                value: 2.0
            }
        );
        let read = PARAM_REQUEST_READ_DATA {
            param_index: -1,
            target_system: 0,
            target_component: 0,
            param_id: id.into(),
        };
        assert_eq!(
            run(MavMessage::PARAM_REQUEST_READ(read)),
            Action::ParamRead {
                name: "RP_CTRL".into(),
                index: None
            }
        );
        let count = MISSION_COUNT_DATA {
            count: 3,
            target_system: 1,
            target_component: 1,
            ..Default::default()
        };
        assert_eq!(
            run(MavMessage::MISSION_COUNT(count.clone())),
            Action::Mission {
                ids: (255, 190),
                step: MissionStep::Count(count)
            }
        );
        let (fence, rally) = (
            MavMissionType::MAV_MISSION_TYPE_FENCE,
            MavMissionType::MAV_MISSION_TYPE_RALLY,
        );
        let clear = |mission_type| {
            run(MavMessage::MISSION_CLEAR_ALL(MISSION_CLEAR_ALL_DATA {
                target_system: 1,
                target_component: 1,
                mission_type,
            }))
        };
        for t in [fence, MavMissionType::MAV_MISSION_TYPE_ALL] {
            let step = MissionStep::Clear(t);
            assert_eq!(clear(t), Action::Mission { ids: (255, 190), step });
        }
        let other = MavMissionType::MAV_MISSION_TYPE_MISSION;
        assert!(matches!(clear(other), Action::Mission { .. }));
        let rally_list = MISSION_REQUEST_LIST_DATA {
            target_system: 1,
            target_component: 1,
            mission_type: rally,
        };
        let step = MissionStep::RequestList(rally);
        assert_eq!(
            run(MavMessage::MISSION_REQUEST_LIST(rally_list)),
            Action::Mission { ids: (255, 190), step }
        );
        let setup = |target_system, target_component| {
            run(MavMessage::SETUP_SIGNING(
                mavlink::dialects::ardupilotmega::SETUP_SIGNING_DATA {
                    initial_timestamp: 9,
                    target_system,
                    target_component,
                    secret_key: [4; 32],
                },
            ))
        };
        assert_eq!(
            setup(1, 1),
            Action::SetupSigning {
                key: SigningKey::from_bytes([4; 32]),
                initial_timestamp: 9
            }
        );
        assert_eq!(setup(0, 0), Action::Ignore, "never broadcast");
        assert_eq!(setup(1, 0), Action::Ignore);
        let other_system = MISSION_REQUEST_LIST_DATA {
            target_system: 7,
            target_component: 1,
            ..Default::default()
        };
        assert_eq!(run(MavMessage::MISSION_REQUEST_LIST(other_system)), Action::Ignore);
    }

    #[test]
    fn follow_target_reports_become_local_targets_and_bad_places_are_refused() {
        let home = Home::default();
        let report = |lat: f64, caps: u8| {
            MavMessage::FOLLOW_TARGET(mavlink::dialects::ardupilotmega::FOLLOW_TARGET_DATA {
                lat: (lat * 1e7).round() as i32,
                lon: (home.lon_deg * 1e7).round() as i32,
                alt: home.alt_amsl_m as f32,
                vel: [1.0, 2.0, 0.0],
                est_capabilities: caps,
                ..Default::default()
            })
        };
        let Action::Request(Request::FollowTarget { pos_w, vel_w }) = run(report(home.lat_deg + 1e-4, 3)) else {
            panic!()
        };
        assert!(
            (pos_w.x - 11.1).abs() < 0.1 && pos_w.y.abs() < 0.01 && pos_w.z.abs() < 0.01,
            "{pos_w:?}"
        );
        assert_eq!(vel_w, crate::math::Vec3::new(1.0, 2.0, 0.0));
        let Action::Request(Request::FollowTarget { vel_w, .. }) = run(report(home.lat_deg, 1)) else {
            panic!()
        };
        assert_eq!(vel_w, crate::math::Vec3::zeros(), "no velocity capability: none used");
        assert!(matches!(run(report(95.0, 1)), Action::Refuse(_)));
    }
}
