//! Copter's inbound messages on a vehicle presented as ArduCopter: mode numbers, take-off, targets,
//! go-tos, reposition, heading, the mission's seqs.
#![allow(deprecated)] // SET_MODE and MISSION_ITEM: what the scripts under test send

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
    copter_ingest(&id(), &gcs_header(0), &message, &state, &[], 0.0)
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
        CommandDecision::Execute(Request::SelectMode(FlightMode::Guided))
    );
    assert_eq!(
        set_mode(1.0, 9.0),
        CommandDecision::Execute(Request::SelectMode(FlightMode::Land))
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
    // pymavlink's set_mode_send(sysid, MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, 6): decided as
    // DO_SET_MODE, answered with an ACK whose command is 11.
    let decided = |d| Some(Action::SetModeMessage(d));
    let flies = |mode| decided(CommandDecision::Execute(Request::SelectMode(mode)));
    assert_eq!(set_mode(1, 6), flies(FlightMode::ReturnToLaunch));
    assert_eq!(set_mode(81, 16), flies(FlightMode::Position));
    assert_eq!(
        set_mode(80, 6),
        decided(CommandDecision::Unsupported),
        "no custom mode flag"
    );
    assert_eq!(
        set_mode(1, 14),
        decided(CommandDecision::Refuse(Outcome::Failed(
            "Mode change to FLIP failed: not emulated".into()
        )))
    );
}

#[test]
fn do_change_speed_reads_copters_speed_types() {
    let mut state = Snapshot::initial(Home::default());
    state.mode = FlightMode::Guided;
    let speed = |state: &Snapshot, p1: f32, p2: f32| {
        let c = long(MavCmd::MAV_CMD_DO_CHANGE_SPEED, [p1, p2, -1.0, 0.0, 0.0, 0.0, 0.0]);
        match copter_ingest(&id(), &gcs_header(0), &c, state, &[], 0.0) {
            Some(Action::Command { decision, .. }) => decision,
            other => panic!("{other:?}"),
        }
    };
    let execute = CommandDecision::Execute;
    assert_eq!(speed(&state, 1.0, 3.0), execute(Request::ChangeSpeed(3.0)));
    assert_eq!(speed(&state, 0.0, 3.0), execute(Request::ChangeSpeed(3.0)), "airspeed");
    assert_eq!(
        speed(&state, 2.0, 1.5),
        execute(Request::ChangeVerticalSpeed {
            up: true,
            speed_m_s: 1.5
        })
    );
    assert_eq!(
        speed(&state, 3.0, 0.5),
        execute(Request::ChangeVerticalSpeed {
            up: false,
            speed_m_s: 0.5
        })
    );
    assert!(matches!(
        speed(&state, 2.0, 0.0),
        CommandDecision::Refuse(Outcome::Denied(_))
    ));
    assert!(matches!(
        speed(&state, 4.0, 1.0),
        CommandDecision::Refuse(Outcome::Denied(_))
    ));
    state.mode = FlightMode::Position;
    assert!(matches!(
        speed(&state, 2.0, 1.0),
        CommandDecision::Refuse(Outcome::Failed(_))
    ));
}

#[test]
fn takeoff_is_a_user_takeoff_above_home_and_targets_are_ignored_outside_guided() {
    let takeoff = long(MavCmd::MAV_CMD_NAV_TAKEOFF, [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 10.0]);
    assert!(matches!(
        run(takeoff, FlightMode::Guided),
        Some(Action::Command { decision: CommandDecision::Execute(Request::UserTakeoff { height_m }), .. }) if height_m == 10.0
    ));
    let target = MavMessage::SET_POSITION_TARGET_LOCAL_NED(SET_POSITION_TARGET_LOCAL_NED_DATA {
        target_system: 1,
        ..Default::default()
    });
    assert_eq!(run(target.clone(), FlightMode::Loiter), Some(Action::Ignore));
    assert!(
        matches!(
            run(target, FlightMode::Guided),
            Some(Action::Request(Request::OffboardSetpoint { .. }))
        ),
        "in GUIDED a target is flown (a frame Copter does not take: a stop where the vehicle is)"
    );
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
    let CommandDecision::Execute(Request::GuidedGoto { pos_w, yaw_rad: None }) = decide(p, FlightMode::Loiter) else {
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

#[test]
fn mission_seqs_count_the_home_slot_and_mission_items_upload() {
    let state = Snapshot::initial(Home::default());
    let at = |message| copter_ingest(&id(), &gcs_header(0), &message, &state, &[], 0.0);
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
        0.0,
    ) {
        Some(Action::Command { decision, .. }) => decision,
        other => panic!("{other:?}"),
    };
    let refused = CommandDecision::Critical(MISSING_TAKEOFF.into());
    assert_eq!(decided(&state, &no_takeoff, &auto), refused);
    let start = long(MavCmd::MAV_CMD_MISSION_START, [0.0; 7]);
    assert_eq!(decided(&state, &no_takeoff, &start), refused);
    let flies = CommandDecision::Execute(Request::SelectMode(FlightMode::Mission));
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
    assert_eq!(
        copter_ingest(&id(), &gcs_header(0), &set_mode, &state, &no_takeoff, 0.0),
        Some(Action::SetModeMessage(CommandDecision::Critical(
            MISSING_TAKEOFF.into()
        )))
    );
}
