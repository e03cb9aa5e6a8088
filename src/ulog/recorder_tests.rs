//! The recorder's schedule, subscriptions and definitions, read back by counting messages.

use super::*;
use crate::control::VehicleState;
use crate::math::Vec3;

fn setup(profile: Profile) -> RecorderSetup {
    RecorderSetup {
        profile,
        rotors: 4,
        omega_max_rad_s: 1000.0,
        thrust_max_n: 40.0,
        torque_max_b: Vec3::new(2.0, 2.0, 1.0),
        believed_mass_kg: 1.5,
        true_mass_kg: 1.7,
        dt_s: 1e-3,
    }
}

fn info() -> LogInfo {
    LogInfo::new("quad_x", ControllerKind::Geometric, None)
}

/// (type, message id for data and subscriptions) of every message after the file header.
fn messages(bytes: &[u8]) -> Vec<(u8, Option<u16>)> {
    let mut out = Vec::new();
    let mut at = 16;
    while at + 3 <= bytes.len() {
        let len = u16::from_le_bytes([bytes[at], bytes[at + 1]]) as usize;
        let kind = bytes[at + 2];
        let payload = &bytes[at + 3..at + 3 + len];
        let id = match kind {
            b'D' => Some(u16::from_le_bytes([payload[0], payload[1]])),
            b'A' => Some(u16::from_le_bytes([payload[1], payload[2]])),
            _ => None,
        };
        out.push((kind, id));
        at += 3 + len;
    }
    assert_eq!(at, bytes.len(), "whole messages only");
    out
}

/// Records `ticks` ticks of a vehicle at rest with the motors off (a bare flight core).
fn record(profile: Profile, ticks: u64) -> Vec<u8> {
    let mut r = Recorder::new(setup(profile));
    let mut out = Vec::new();
    r.begin(
        &mut out,
        0,
        &info(),
        &[("MPC_XY_VEL_MAX".into(), ParamValue::Float(12.0))],
    );
    for k in 0..ticks {
        let t_s = k as f64 * 1e-3;
        let state = VehicleState::at_rest(t_s, Vec3::zeros());
        let mut view = TickView::resting(&state);
        view.truth.external_force_w = Vec3::new(if k < 500 { 0.0 } else { 0.5 }, 0.0, 0.0);
        r.record(&mut out, &view);
    }
    out
}

fn count(msgs: &[(u8, Option<u16>)], kind: u8, topic: Topic) -> usize {
    msgs.iter().filter(|m| **m == (kind, Some(topic.msg_id()))).count()
}

#[test]
fn definitions_hold_every_format_the_info_and_the_parameters() {
    let msgs = messages(&record(Profile::Default, 0));
    assert_eq!(msgs[0].0, b'B', "flag bits first");
    assert_eq!(msgs.iter().filter(|m| m.0 == b'F').count(), Topic::ALL.len());
    assert!(msgs.iter().filter(|m| m.0 == b'I').count() >= 6);
    assert_eq!(msgs.iter().filter(|m| m.0 == b'P').count(), 1);
}

#[test]
fn the_full_profile_records_the_state_every_tick_and_the_rest_at_its_rate() {
    let msgs = messages(&record(Profile::Full, 1000));
    assert_eq!(count(&msgs, b'D', Topic::VehicleAttitude), 1000);
    assert_eq!(count(&msgs, b'D', Topic::VehicleLocalPosition), 1000);
    assert_eq!(count(&msgs, b'D', Topic::SensorCombined), 100);
    assert_eq!(
        count(&msgs, b'D', Topic::VehicleAttitudeGroundtruth),
        100,
        "the truth at 100 Hz"
    );
    assert_eq!(
        count(&msgs, b'A', Topic::VehicleAttitude),
        1,
        "one subscription per topic"
    );
    // Nothing to log without a step or a snapshot.
    assert_eq!(count(&msgs, b'A', Topic::AllocationStatus), 0);
    assert_eq!(count(&msgs, b'A', Topic::VehicleStatus), 0);
}

#[test]
fn the_default_profile_follows_px4_rates_and_logs_changes_at_once() {
    let msgs = messages(&record(Profile::Default, 1000));
    assert_eq!(
        count(&msgs, b'D', Topic::VehicleAttitudeSetpoint),
        0,
        "nothing without a step"
    );
    assert_eq!(count(&msgs, b'D', Topic::VehicleAttitude), 50, "every 20 ms");
    assert_eq!(count(&msgs, b'D', Topic::VehicleLocalPositionSetpoint), 0);
    assert_eq!(count(&msgs, b'D', Topic::VehicleAngularVelocity), 50, "every 20 ms");
    // The true wrench: at the start (due), then when it changes at 0.5 s.
    assert_eq!(count(&msgs, b'D', Topic::ExternalWrenchTruth), 2);
}

#[test]
fn a_sync_message_marks_every_second() {
    let msgs = messages(&record(Profile::Default, 2500));
    assert_eq!(msgs.iter().filter(|m| m.0 == b'S').count(), 2);
}
