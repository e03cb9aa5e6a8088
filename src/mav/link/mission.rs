//! The mission protocol of the link against the vehicle's stored plans (mission, fence, rally):
//! uploads go through the link's [`MissionTransfer`](crate::mav::mission_xfer::MissionTransfer);
//! a complete upload is validated, handed to the vehicle (as the mission, the geofence or the
//! rally points), and stored and ACKed once the vehicle took it; downloads are answered from the
//! [`PlanStore`](crate::mav::plan_store::PlanStore); a clear empties both, per type.
//!
//! [`PlanService`] owns the stored plans, what MISSION_CURRENT remembers and the upload state
//! of each link, each with the vehicle's personality: ArduCopter's mission keeps home in slot 0
//! and the commander flies items 1.. (docs/ardupilot.md §6); a stored upload is announced with
//! "Flight plan received" before its MISSION_ACK.

use mavlink::dialects::ardupilotmega::{MavCmd, MavMessage, MavMissionResult, MavMissionType, MISSION_ITEM_INT_DATA};

use super::boundary::VehicleRequest;
use super::commands::Pending;
use super::effects::Effect;
use super::plan_request::{empty_plan, plan_request, MISSION};
use super::{LinkKind, CRITICAL, INFO, WARNING};
use crate::commander::MissionState;
use crate::guidance::Home;
use crate::mav::ardupilot::copter_mission::{link_seq, PLAN_RECEIVED};
use crate::mav::ardupilot::copter_plans::{PlanRefusal, FENCE_INVALID, RALLY_RECEIVED};
use crate::mav::identity::Personality;
use crate::mav::ingest::MissionStep;
use crate::mav::mission_report::MissionReport;
use crate::mav::mission_xfer::{Completed, Ids, MissionTransfer, TIMEOUT_TEXT};
use crate::mav::plan_store::{plan_name, PlanStore, PLAN_TYPES};
use crate::mav::stream_messages::status_text;
use crate::telemetry::Snapshot;

/// The vehicle's plans and the mission protocol of every link.
#[derive(Debug)]
pub(super) struct PlanService<A> {
    /// The plans as uploaded, for downloads; each replaced only when the vehicle took an upload.
    plans: PlanStore,
    /// What MISSION_CURRENT remembers (PX4's mission mode and state).
    report: MissionReport,
    /// The upload in progress on each link.
    transfers: Vec<(LinkKind, MissionTransfer<A>)>,
    /// Whose face the protocol shows (PX4's or ArduCopter's).
    personality: Personality,
}

impl<A: Copy + PartialEq> PlanService<A> {
    /// No plan, no upload, on `links`, as `personality` runs the protocol.
    pub fn new(links: &[LinkKind], personality: Personality) -> Self {
        Self {
            plans: PlanStore::new(personality),
            report: MissionReport::new(personality),
            transfers: links.iter().map(|l| (*l, MissionTransfer::new(personality))).collect(),
            personality,
        }
    }

    fn transfer(&mut self, link: LinkKind) -> Option<&mut MissionTransfer<A>> {
        self.transfers.iter_mut().find(|(l, _)| *l == link).map(|(_, t)| t)
    }

    /// Plan `mission_type` (mission, fence or rally) as last uploaded.
    pub fn items(&self, mission_type: MavMissionType) -> &[MISSION_ITEM_INT_DATA] {
        self.plans.items(mission_type)
    }

    /// The vehicle's latest state (MISSION_CURRENT follows its mission).
    pub fn handle_state(&mut self, snapshot: &Snapshot) {
        self.report.handle_state(snapshot, self.plans.ids());
        let started = matches!(
            snapshot.mission_state,
            MissionState::Active | MissionState::Paused | MissionState::Complete
        );
        self.plans
            .handle_nav_seq(started.then(|| link_seq(snapshot.mission_seq)));
    }

    /// True when the mission in `snapshot` stopped at a NAV_RETURN_TO_LAUNCH item of the stored
    /// mission (its return flown; ArduCopter flies it in AUTO).
    pub fn at_return_item(&self, snapshot: &Snapshot) -> bool {
        let seq = match self.personality {
            Personality::Px4 => snapshot.mission_seq,
            Personality::ArduPilot => link_seq(snapshot.mission_seq),
        };
        let item = self.plans.items(MISSION).get(usize::from(seq));
        snapshot.mission_state == MissionState::Complete
            && item.is_some_and(|i| i.command == MavCmd::MAV_CMD_NAV_RETURN_TO_LAUNCH)
    }

    /// The commander's mission item `seq` was reached: the MISSION_ITEM_REACHED announcing it.
    pub fn handle_reached(&mut self, seq: u16) -> MavMessage {
        self.report.handle_reached(seq)
    }

    /// MISSION_CURRENT for `snapshot` with the commander's current item `seq`.
    pub fn mission_current(&self, snapshot: &Snapshot, seq: u16) -> MavMessage {
        self.report.mission_current(snapshot, seq, self.plans.ids())
    }

    /// One mission-protocol step from `from` (MAVLink ids `ids`) on `link` at wall time
    /// `wall_s` [s], the vehicle in `state`; a complete upload is validated against its home (the
    /// local origin) and asked of the vehicle; ArduCopter's item 0 is where home is now.
    pub fn step(
        &mut self,
        wall_s: f64,
        (link, from, ids): (LinkKind, A, Ids),
        step: MissionStep,
        state: &Snapshot,
    ) -> Vec<Effect<A>> {
        let home = &state.home;
        let Some((_, transfer)) = self.transfers.iter_mut().find(|(l, _)| *l == link) else {
            return Vec::new();
        };
        let (sent, completed) = match step {
            MissionStep::Count(m) => transfer.on_count(from, ids, &m, wall_s),
            MissionStep::Item(m) => transfer.on_item(from, &m, wall_s),
            MissionStep::Clear(t) => transfer.on_clear(from, ids, t),
            MissionStep::RequestList(t) => (vec![(from, self.plans.download_count(ids, t))], None),
            MissionStep::RequestItem {
                seq,
                mission_type,
                int_form,
            } => {
                let (lat_deg, lon_deg, alt_amsl_m) = home.to_global(&state.home_w);
                let home_now = Home {
                    lat_deg,
                    lon_deg,
                    alt_amsl_m,
                };
                let item = self.plans.download_item(ids, mission_type, seq, int_form, &home_now);
                (vec![(from, item)], None)
            }
        };
        let mut out = on_link(link, sent);
        match completed {
            Some(Completed::Items(mission_type, uploaded)) => {
                match plan_request(self.personality, mission_type, uploaded.clone(), home) {
                    Ok((request, items)) => {
                        let pending = Pending::Mission {
                            link,
                            mission_type,
                            items,
                        };
                        out.push(Effect::Ask(Some(pending), VehicleRequest::Commander(request)));
                    }
                    // ArduCopter stores a mission as sent (it checks items as it flies them): the
                    // plan is kept and ACKed, the commander gets none to fly (AUTO is refused),
                    // never a flight to a point it refused (below home, say).
                    Err(PlanRefusal { error: e, .. })
                        if self.personality == Personality::ArduPilot && mission_type == MISSION =>
                    {
                        let items = uploaded;
                        let result = format!("{:?}", e.result);
                        let result = result.trim_start_matches("MAV_MISSION_");
                        let why = format!("Mission stored, not flown: item {} {result}", e.seq);
                        out.push(Effect::send(link, from, status_text(WARNING, &why)));
                        let pending = Pending::Mission {
                            link,
                            mission_type,
                            items,
                        };
                        out.push(Effect::Ask(
                            Some(pending),
                            VehicleRequest::Commander(empty_plan(mission_type)),
                        ));
                    }
                    Err(PlanRefusal { error: e, text }) => {
                        let texts = match (self.personality, text) {
                            (Personality::ArduPilot, Some(why)) => vec![why, FENCE_INVALID.to_string()],
                            (Personality::ArduPilot, None) => Vec::new(),
                            (Personality::Px4, _) => {
                                vec![format!(
                                    "{} item {} refused: {:?}",
                                    plan_name(mission_type),
                                    e.seq,
                                    e.result
                                )]
                            }
                        };
                        for why in texts {
                            out.push(Effect::send(link, from, status_text(WARNING, &why)));
                        }
                        out.extend(self.finish_upload(link, e.result, 0));
                    }
                }
            }
            Some(Completed::Cleared(cleared)) => {
                for t in PLAN_TYPES
                    .into_iter()
                    .filter(|t| cleared == *t || cleared == MavMissionType::MAV_MISSION_TYPE_ALL)
                {
                    out.push(Effect::Ask(None, VehicleRequest::Commander(empty_plan(t))));
                    self.plans.set(t, Vec::new());
                }
            }
            None => {}
        }
        out
    }

    /// The vehicle's answer to a validated upload of plan `mission_type` on `link` (`taken`
    /// false: it could not be reached): stored and ACCEPTED with the plan's id once it took the
    /// plan (ArduCopter's mission announced with [`PLAN_RECEIVED`] first), MISSION_ERROR
    /// otherwise.
    pub fn taken(
        &mut self,
        link: LinkKind,
        mission_type: MavMissionType,
        items: Vec<MISSION_ITEM_INT_DATA>,
        taken: bool,
    ) -> Vec<Effect<A>> {
        let mut out = Vec::new();
        let (result, id) = match taken {
            false => (MavMissionResult::MAV_MISSION_ERROR, 0),
            true => {
                self.plans.set(mission_type, items);
                let client = self.transfer(link).and_then(|t| t.client());
                let said = match mission_type {
                    MavMissionType::MAV_MISSION_TYPE_MISSION => Some(PLAN_RECEIVED),
                    MavMissionType::MAV_MISSION_TYPE_RALLY => Some(RALLY_RECEIVED),
                    _ => None,
                };
                if let (Personality::ArduPilot, Some(said), Some(to)) = (self.personality, said, client) {
                    out.push(Effect::send(link, to, status_text(INFO, said)));
                }
                (MavMissionResult::MAV_MISSION_ACCEPTED, self.plans.id(mission_type))
            }
        };
        out.extend(self.finish_upload(link, result, id));
        out
    }

    /// The upload's MISSION_ACK on `link` with `result` and `opaque_id`.
    fn finish_upload(&mut self, link: LinkKind, result: MavMissionResult, opaque_id: u32) -> Vec<Effect<A>> {
        let sent = self
            .transfer(link)
            .map(|t| t.finish(result, opaque_id))
            .unwrap_or_default();
        on_link(link, sent)
    }

    /// `link`'s upload at wall time `wall_s` [s]: a missing item re-requested, or the upload
    /// dropped with [`TIMEOUT_TEXT`] to its client when the client fell silent.
    pub fn tick(&mut self, wall_s: f64, link: LinkKind) -> Vec<Effect<A>> {
        let Some(transfer) = self.transfer(link) else {
            return Vec::new();
        };
        let client = transfer.client();
        let (retries, timed_out) = transfer.tick(wall_s);
        let mut out = on_link(link, retries);
        if let (true, Some(to)) = (timed_out, client) {
            out.push(Effect::send(link, to, status_text(CRITICAL, TIMEOUT_TEXT)));
        }
        out
    }
}

/// Every (destination, message) of `sent` on `link`.
fn on_link<A>(link: LinkKind, sent: Vec<(A, MavMessage)>) -> Vec<Effect<A>> {
    sent.into_iter().map(|(to, msg)| Effect::send(link, to, msg)).collect()
}

#[cfg(test)]
mod tests {
    use mavlink::dialects::ardupilotmega::{MavFrame, MISSION_COUNT_DATA};

    use super::*;
    use crate::commander::Request;
    use crate::mav::link::effects::testing::{sent, texts};
    use crate::mav::mission_xfer::PROTOCOL_TIMEOUT_S;

    const GCS: LinkKind = LinkKind::Gcs;
    const MISSION: MavMissionType = MavMissionType::MAV_MISSION_TYPE_MISSION;
    const IDS: Ids = (255, 190);

    fn count(n: u16) -> MissionStep {
        MissionStep::Count(MISSION_COUNT_DATA {
            count: n,
            target_system: 1,
            target_component: 1,
            mission_type: MISSION,
            opaque_id: 0,
        })
    }

    fn waypoint(seq: u16) -> MissionStep {
        let home = Home::default();
        MissionStep::Item(Box::new(MISSION_ITEM_INT_DATA {
            seq,
            command: MavCmd::MAV_CMD_NAV_WAYPOINT,
            frame: MavFrame::MAV_FRAME_GLOBAL,
            x: (home.lat_deg * 1e7) as i32 + 100,
            y: (home.lon_deg * 1e7) as i32,
            z: (home.alt_amsl_m + 10.0) as f32,
            target_system: 1,
            target_component: 1,
            mission_type: MISSION,
            ..Default::default()
        }))
    }

    fn ack(out: &[Effect<u16>]) -> Option<(MavMissionResult, u32)> {
        sent(out).into_iter().find_map(|(_, _, m)| match m {
            MavMessage::MISSION_ACK(a) => Some((a.mavtype, a.opaque_id)),
            _ => None,
        })
    }

    #[test]
    fn an_upload_is_asked_of_the_vehicle_and_stored_once_taken() {
        let home = Home::default();
        let mut p = PlanService::new(&[GCS], Personality::Px4);
        let out = p.step(0.0, (GCS, 5u16, IDS), count(1), &Snapshot::initial(home));
        assert!(matches!(sent(&out)[0].2, MavMessage::MISSION_REQUEST_INT(ref r) if r.seq == 0));
        let out = p.step(0.1, (GCS, 5, IDS), waypoint(0), &Snapshot::initial(home));
        let [Effect::Ask(Some(Pending::Mission { items, .. }), VehicleRequest::Commander(Request::SetMission(_)))] =
            &out[..]
        else {
            panic!("{out:?}");
        };
        assert!(p.items(MISSION).is_empty(), "stored only once the vehicle took it");
        let out = p.taken(GCS, MISSION, items.clone(), true);
        let (result, id) = ack(&out).unwrap();
        assert_eq!(result, MavMissionResult::MAV_MISSION_ACCEPTED);
        assert_eq!(p.items(MISSION).len(), 1);
        assert_ne!(id, 0, "the plan's id");
        let out = p.step(
            0.2,
            (GCS, 5, IDS),
            MissionStep::RequestList(MISSION),
            &Snapshot::initial(home),
        );
        assert!(matches!(sent(&out)[0].2, MavMessage::MISSION_COUNT(ref c) if c.count == 1));
    }

    #[test]
    fn an_unreached_vehicle_errs_a_clear_empties_and_silence_times_out() {
        let home = Home::default();
        let mut p = PlanService::new(&[GCS], Personality::Px4);
        p.step(0.0, (GCS, 5u16, IDS), count(1), &Snapshot::initial(home));
        let out = p.step(0.1, (GCS, 5, IDS), waypoint(0), &Snapshot::initial(home));
        let Some(Effect::Ask(Some(Pending::Mission { items, .. }), _)) = out.into_iter().next() else {
            panic!("asked of the vehicle");
        };
        let out = p.taken(GCS, MISSION, items, false);
        assert_eq!(ack(&out).map(|a| a.0), Some(MavMissionResult::MAV_MISSION_ERROR));
        assert!(p.items(MISSION).is_empty());

        let out = p.step(
            1.0,
            (GCS, 5, IDS),
            MissionStep::Clear(MISSION),
            &Snapshot::initial(home),
        );
        assert!(
            out.iter().any(|e| matches!(e, Effect::Ask(None, _))),
            "the vehicle's plan emptied"
        );

        p.step(2.0, (GCS, 5, IDS), count(2), &Snapshot::initial(home));
        assert!(texts(&p.tick(2.0 + PROTOCOL_TIMEOUT_S / 2.0, GCS)).is_empty());
        assert_eq!(texts(&p.tick(2.0 + PROTOCOL_TIMEOUT_S, GCS)), vec![TIMEOUT_TEXT]);
        assert!(p.tick(10.0, LinkKind::Api).is_empty(), "no such link");
    }

    #[test]
    #[allow(deprecated)] // MISSION_REQUEST: what ArduCopter asks with
    fn arducopter_flies_items_1_on_and_says_the_plan_was_received() {
        let home = Home::default();
        let mut p = PlanService::new(&[GCS], Personality::ArduPilot);
        let out = p.step(0.0, (GCS, 5u16, IDS), count(3), &Snapshot::initial(home));
        assert!(matches!(sent(&out)[0].2, MavMessage::MISSION_REQUEST(ref r) if r.seq == 0));
        p.step(0.1, (GCS, 5, IDS), waypoint(0), &Snapshot::initial(home));
        p.step(0.2, (GCS, 5, IDS), waypoint(1), &Snapshot::initial(home));
        let out = p.step(0.3, (GCS, 5, IDS), waypoint(2), &Snapshot::initial(home));
        let [Effect::Ask(Some(Pending::Mission { items, .. }), VehicleRequest::Commander(Request::SetMission(m)))] =
            &out[..]
        else {
            panic!("{out:?}");
        };
        assert_eq!((m.len(), items.len()), (2, 3), "items 1 and 2 flown, all three stored");
        let out = p.taken(GCS, MISSION, items.clone(), true);
        assert_eq!(texts(&out), vec![PLAN_RECEIVED]);
        let said = sent(&out);
        assert!(
            matches!(said[0].2, MavMessage::STATUSTEXT(_)),
            "the text before the ACK"
        );
        assert_eq!(ack(&out).map(|a| a.0), Some(MavMissionResult::MAV_MISSION_ACCEPTED));
        // A bad item is named by its uploaded seq.
        p.step(1.0, (GCS, 5, IDS), count(2), &Snapshot::initial(home));
        p.step(1.1, (GCS, 5, IDS), waypoint(0), &Snapshot::initial(home));
        let MissionStep::Item(mut far) = waypoint(1) else {
            unreachable!()
        };
        far.x = 0;
        let out = p.step(1.2, (GCS, 5, IDS), MissionStep::Item(far), &Snapshot::initial(home));
        assert_eq!(texts(&out), vec!["Mission stored, not flown: item 1 INVALID_PARAM5_X"]);
        let [_, Effect::Ask(Some(Pending::Mission { items, .. }), VehicleRequest::Commander(Request::SetMission(m)))] =
            &out[..]
        else {
            panic!("{out:?}");
        };
        assert!(m.is_empty() && items.len() == 2, "stored as sent, none flown");
        let out = p.taken(GCS, MISSION, items.clone(), true);
        assert_eq!(ack(&out).map(|a| a.0), Some(MavMissionResult::MAV_MISSION_ACCEPTED));
        // A home slot alone empties the mission.
        p.step(2.0, (GCS, 5, IDS), count(1), &Snapshot::initial(home));
        let out = p.step(2.1, (GCS, 5, IDS), waypoint(0), &Snapshot::initial(home));
        assert!(
            matches!(&out[..], [Effect::Ask(_, VehicleRequest::Commander(Request::SetMission(m)))] if m.is_empty())
        );
    }

    #[test]
    #[allow(deprecated)] // MISSION_ITEM: DroneKit's download
    fn arducopters_item_0_is_where_home_is_now() {
        let origin = Home::default();
        let mut p = PlanService::<u16>::new(&[GCS], Personality::ArduPilot);
        let mut s = Snapshot::initial(origin);
        s.home_w = crate::math::Vec3::new(111.0, 0.0, -20.0);
        let ask = MissionStep::RequestItem {
            seq: 0,
            mission_type: MISSION,
            int_form: false,
        };
        let out = p.step(0.0, (GCS, 5, IDS), ask, &s);
        let [Effect::To(_, _, MavMessage::MISSION_ITEM(item))] = &out[..] else {
            panic!("{out:?}");
        };
        assert!(
            (f64::from(item.x) - origin.lat_deg - 0.000_998).abs() < 2e-5,
            "{} moved north",
            item.x
        );
        assert!(
            (f64::from(item.z) - origin.alt_amsl_m - 20.0).abs() < 0.01,
            "{}",
            item.z
        );
    }
}
