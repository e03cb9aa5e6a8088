//! Tests of `param_service.rs`: PX4's protocol and ArduCopter's.
use mavlink::dialects::ardupilotmega::MavMessage;

use super::*;
use crate::mav::ardupilot::copter_link_params::LinkParams;
use crate::mav::gcs::gcs_header;
use crate::mav::link::effects::testing::{param_names, sent, table, texts};

/// What the link holds: system id 1, no link's rates (the tests of the rates are the link's).
static HELD: LinkParams = LinkParams {
    system_id: 1,
    stream_rates: Vec::new(),
};

const GCS: LinkKind = LinkKind::Gcs;

#[test]
fn a_list_sends_the_hash_first_then_one_value_per_period_and_ends() {
    let params = table();
    let mut p = ParamService::default();
    p.request_list(GCS, 5u16, 1.0);
    assert_eq!(p.next_due_s(), Some(1.0));
    let first = p.stream_lists(1.0, &params, &HELD);
    assert_eq!(param_names(&first), vec![HASH_CHECK]);
    let more = p.stream_lists(1.0 + 2.5 * PARAM_LIST_PERIOD_S, &params, &HELD);
    assert_eq!(param_names(&more).len(), 2, "one value per period of wall time");
    let rest = p.stream_lists(1e3, &params, &HELD);
    assert_eq!(param_names(&rest).len(), params.len() - 2);
    assert_eq!(p.list_count(), 0, "a sent list is done");
    assert_eq!(p.next_due_s(), None);
}

#[test]
fn the_hash_check_stops_a_list_and_forgotten_clients_lose_theirs() {
    let mut p = ParamService::default();
    p.request_list(GCS, 5u16, 0.0);
    p.request_list(GCS, 6u16, 0.0);
    assert!(p
        .set((GCS, 5, &gcs_header(0)), HASH_CHECK.into(), 1.0, (&table(), &HELD))
        .is_empty());
    assert_eq!(p.list_count(), 1);
    p.keep_clients(GCS, &[7]);
    assert_eq!(p.list_count(), 0);
}

#[test]
fn a_set_is_asked_echoed_to_the_link_and_announced_to_every_link_later() {
    let mut params = table();
    let mut p = ParamService::default();
    let out = p.set(
        (GCS, 5u16, &gcs_header(0)),
        "MIS_TAKEOFF_ALT".into(),
        5.0,
        (&params, &HELD),
    );
    let [Effect::Ask(Some(Pending::Param(set)), VehicleRequest::SetParam { name, value })] = &out[..] else {
        panic!("{out:?}");
    };
    assert_eq!((name.as_str(), *value), ("MIS_TAKEOFF_ALT", 5.0));
    let result = params.set("MIS_TAKEOFF_ALT", 5.0, 1e-3);
    let echo = p.set_done(1.0, set.clone(), Some(result), (&params, &HELD), vec![1, 2]);
    let to: Vec<u16> = sent(&echo).iter().map(|(_, to, _)| *to).collect();
    assert_eq!(to, vec![1, 2, 5], "the link's targets and the sender");
    assert!(p.announce_changed(1.001, &params, &HELD).is_empty());
    assert_eq!(p.next_due_s(), Some(1.0 + PARAM_CHANGE_DELAY_S));
    let later = p.announce_changed(1.0 + PARAM_CHANGE_DELAY_S, &params, &HELD);
    assert!(matches!(&later[..], [Effect::Everyone(MavMessage::PARAM_VALUE(_))]));
}

#[test]
fn a_refused_or_unknown_set_says_why_to_the_sender() {
    let mut params = table();
    let mut p = ParamService::default();
    let set = |name: &str| ParamSet {
        link: GCS,
        to: 5u16,
        header: gcs_header(0),
        name: name.into(),
    };
    let refused = params.set("MIS_TAKEOFF_ALT", -1e9, 1e-3);
    let out = p.set_done(0.0, set("MIS_TAKEOFF_ALT"), Some(refused), (&params, &HELD), vec![1]);
    assert_eq!(param_names(&out), vec!["MIS_TAKEOFF_ALT"], "the unchanged value");
    assert_eq!(texts(&out).len(), 1);
    let out = p.set_done(
        0.0,
        set("NOPE"),
        Some(params.set("NOPE", 1.0, 1e-3)),
        (&params, &HELD),
        vec![1],
    );
    assert!(matches!(sent(&out)[0].2, MavMessage::PARAM_ERROR(_)));
    assert_eq!(texts(&out), vec!["Unknown parameter NOPE"]);
    let out = p.set_done(0.0, set("MIS_TAKEOFF_ALT"), None, (&params, &HELD), vec![1]);
    assert_eq!(texts(&out), vec!["Vehicle busy"]);
    assert_eq!(p.next_due_s(), None, "nothing changed");
}

#[test]
fn a_read_by_name_or_index_and_an_unknown_name() {
    let params = table();
    let p = ParamService::<u16>::default();
    let header = gcs_header(0);
    let by_name = p.read((GCS, 5, &header), "MIS_TAKEOFF_ALT", None, (&params, &HELD));
    assert_eq!(param_names(&by_name), vec!["MIS_TAKEOFF_ALT"]);
    assert_eq!(
        param_names(&p.read((GCS, 5, &header), "", Some(0), (&params, &HELD))).len(),
        1
    );
    assert_eq!(
        param_names(&p.read((GCS, 5, &header), HASH_CHECK, None, (&params, &HELD))),
        vec![HASH_CHECK]
    );
    let unknown = p.read((GCS, 5, &header), "NOPE", None, (&params, &HELD));
    assert!(matches!(sent(&unknown)[0].2, MavMessage::PARAM_ERROR(_)));
}

fn ardupilot() -> ParamService<u16> {
    ParamService::new(&Identity::autopilot(1, 4).with_personality(Personality::ArduPilot))
}

fn values(out: &[Effect<u16>]) -> Vec<mavlink::dialects::ardupilotmega::PARAM_VALUE_DATA> {
    out.iter()
        .filter_map(|e| match e {
            Effect::To(_, _, MavMessage::PARAM_VALUE(v)) | Effect::Everyone(MavMessage::PARAM_VALUE(v)) => {
                Some(v.clone())
            }
            _ => None,
        })
        .collect()
}

#[test]
fn an_ardupilot_list_says_the_banner_then_every_value_under_copter_names() {
    let params = table();
    let mut p = ardupilot();
    p.request_list(GCS, 5u16, 1.0);
    let first = p.stream_lists(1.0, &params, &HELD);
    assert_eq!(texts(&first), vec!["ArduCopter V4.5.7 (rotorpilot)", "Frame: QUAD/X"]);
    assert!(param_names(&first).is_empty(), "no _HASH_CHECK");
    let rest = p.stream_lists(1e3, &params, &HELD);
    let names = param_names(&rest);
    assert_eq!(names.len(), params.len() + 1, "the table, then SYSID_THISMAV");
    assert!(names.iter().any(|n| n == "WPNAV_SPEED"));
    assert_eq!(names.last().map(String::as_str), Some("SYSID_THISMAV"));
    assert!(!names.iter().any(|n| n == "MPC_XY_CRUISE" || n == HASH_CHECK));
    let indices: Vec<usize> = values(&rest).iter().map(|v| v.param_index as usize).collect();
    assert_eq!(indices, (0..=params.len()).collect::<Vec<_>>());
    assert_eq!(p.list_count(), 0);
}

#[test]
fn an_ardupilot_read_answers_by_index_or_name_and_ignores_unknown_names() {
    let params = table();
    let p = ardupilot();
    let header = gcs_header(0);
    let by_name = values(&p.read((GCS, 5, &header), "WPNAV_SPEED", None, (&params, &HELD)));
    assert_eq!(by_name.len(), 1);
    assert_eq!((by_name[0].param_index, by_name[0].param_value), (u16::MAX, 500.0));
    let i = params.index_of("MPC_XY_CRUISE").unwrap();
    let by_index = values(&p.read((GCS, 5, &header), "", Some(i), (&params, &HELD)));
    assert_eq!(by_index[0].param_index as usize, i);
    for unknown in ["MPC_XY_CRUISE", HASH_CHECK, "NOPE"] {
        assert!(
            p.read((GCS, 5, &header), unknown, None, (&params, &HELD)).is_empty(),
            "{unknown}"
        );
    }
    assert_eq!(
        param_names(&p.read((GCS, 5, &header), "", Some(params.len()), (&params, &HELD))),
        ["SYSID_THISMAV"]
    );
    assert!(p
        .read((GCS, 5, &header), "", Some(params.len() + 1), (&params, &HELD))
        .is_empty());
}

#[test]
fn an_ardupilot_set_asks_for_the_setting_and_echoes_the_copter_value_to_everyone() {
    let mut params = table();
    let mut p = ardupilot();
    let header = gcs_header(0);
    let out = p.set((GCS, 5u16, &header), "WPNAV_SPEED".into(), 700.0, (&params, &HELD));
    let [Effect::Ask(Some(Pending::Param(set)), VehicleRequest::SetParam { name, value })] = &out[..] else {
        panic!("{out:?}");
    };
    assert_eq!((name.as_str(), *value), ("MPC_XY_CRUISE", 7.0));
    let result = params.set("MPC_XY_CRUISE", 7.0, 1e-3);
    let echo = p.set_done(1.0, set.clone(), Some(result), (&params, &HELD), vec![5]);
    let [Effect::Everyone(MavMessage::PARAM_VALUE(v))] = &echo[..] else {
        panic!("{echo:?}");
    };
    assert_eq!((v.param_value, v.param_index), (700.0, u16::MAX));
    assert_eq!(p.next_due_s(), None, "announced once, at once");
    let to_stranger = p.set_done(1.0, set.clone(), Some(Ok(0)), (&params, &HELD), vec![6]);
    assert_eq!(sent(&to_stranger).len(), 1, "the sender too when not a target");
    // Unknown names (the PX4 name of a Copter parameter, PX4's hash) are ignored.
    for unknown in ["MPC_XY_CRUISE", HASH_CHECK, "NOPE"] {
        assert!(
            p.set((GCS, 5, &header), unknown.into(), 1.0, (&params, &HELD))
                .is_empty(),
            "{unknown}"
        );
    }
    // A value the setting cannot take: the value as it is and why, in Copter's unit.
    let refused = p.set((GCS, 5, &header), "WPNAV_SPEED".into(), 5000.0, (&params, &HELD));
    assert_eq!(values(&refused)[0].param_value, 700.0);
    assert_eq!(texts(&refused), vec!["WPNAV_SPEED: 5000 outside [50, 3000]"]);
    let busy = p.set_done(1.0, set.clone(), None, (&params, &HELD), vec![5]);
    assert_eq!(texts(&busy), vec!["Vehicle busy"]);
}
