//! The mission transfer protocol (docs/mavlink.md §7), as a state machine with the time passed in.
//!
//! Upload: MISSION_COUNT(n) → MISSION_REQUEST_INT(0) → MISSION_ITEM_INT(0) → … → the caller
//! validates the staged items and answers with [`MissionTransfer::finish`]; the stored plan
//! changes only then (atomic replace). Out-of-sequence items are dropped and re-requested; a
//! missing item is re-requested every [`RETRY_S`], at most [`MAX_RETRIES`] times, then the
//! upload is cancelled with OPERATION_CANCELLED. A second peer is DENIED while one uploads.
//! Downloads are stateless: the client asks, the link answers from the
//! [`PlanStore`](super::plan_store::PlanStore).
//!
//! Every reply carries the `mission_type` of the request it answers. The mission (type 0), the
//! fence (1) and the rally points (2) are plans of their own, uploaded and cleared alike (as PX4
//! stores them); MISSION_CLEAR_ALL of MAV_MISSION_TYPE_ALL clears all three, and an upload of
//! another type is refused with UNSUPPORTED.
//! Pure; `P` identifies a peer (an address in the runtime).

use mavlink::dialects::common::{
    MavMessage, MavMissionResult, MavMissionType, MISSION_ACK_DATA, MISSION_COUNT_DATA, MISSION_ITEM_INT_DATA,
    MISSION_REQUEST_INT_DATA,
};

/// Re-request a missing item after this long [s].
pub const RETRY_S: f64 = 0.25;
/// Re-requests before the upload is cancelled.
pub const MAX_RETRIES: u8 = 5;

/// A peer's MAVLink ids (for the target fields of replies).
pub type Ids = (u8, u8);

/// What an upload produced.
#[derive(Debug, Clone, PartialEq)]
pub enum Completed {
    /// Every item of plan `mission_type` arrived; validate, then call [`MissionTransfer::finish`].
    Items(MavMissionType, Vec<MISSION_ITEM_INT_DATA>),
    /// MISSION_COUNT(0) or MISSION_CLEAR_ALL: clear the stored plan of this type (all three for
    /// MAV_MISSION_TYPE_ALL); already ACKed.
    Cleared(MavMissionType),
}

#[derive(Debug, Clone, PartialEq)]
enum State<P> {
    Idle,
    Receiving {
        peer: P,
        ids: Ids,
        mission_type: MavMissionType,
        count: u16,
        items: Vec<MISSION_ITEM_INT_DATA>,
        requested_at_s: f64,
        retries: u8,
    },
    Validating {
        peer: P,
        ids: Ids,
        mission_type: MavMissionType,
    },
}

/// Upload state of one link.
#[derive(Debug, Clone, PartialEq)]
pub struct MissionTransfer<P> {
    state: State<P>,
}

impl<P> Default for MissionTransfer<P> {
    fn default() -> Self {
        Self { state: State::Idle }
    }
}

/// A plan type an upload can fill: mission, fence or rally.
pub fn uploadable(mission_type: MavMissionType) -> bool {
    matches!(
        mission_type,
        MavMissionType::MAV_MISSION_TYPE_MISSION
            | MavMissionType::MAV_MISSION_TYPE_FENCE
            | MavMissionType::MAV_MISSION_TYPE_RALLY
    )
}

/// MISSION_ACK to `ids` answering a request about plan `mission_type`.
pub fn mission_ack(ids: Ids, mission_type: MavMissionType, result: MavMissionResult) -> MavMessage {
    MavMessage::MISSION_ACK(MISSION_ACK_DATA {
        target_system: ids.0,
        target_component: ids.1,
        mavtype: result,
        mission_type,
        opaque_id: 0,
    })
}

fn request(ids: Ids, mission_type: MavMissionType, seq: u16) -> MavMessage {
    MavMessage::MISSION_REQUEST_INT(MISSION_REQUEST_INT_DATA {
        seq,
        target_system: ids.0,
        target_component: ids.1,
        mission_type,
    })
}

impl<P: Copy + PartialEq> MissionTransfer<P> {
    /// MISSION_COUNT from `peer`.
    pub fn on_count(
        &mut self,
        peer: P,
        ids: Ids,
        m: &MISSION_COUNT_DATA,
        now_s: f64,
    ) -> (Vec<(P, MavMessage)>, Option<Completed>) {
        let mission_type = m.mission_type;
        let ack = |result| vec![(peer, mission_ack(ids, mission_type, result))];
        if !uploadable(mission_type) {
            return (ack(MavMissionResult::MAV_MISSION_UNSUPPORTED), None);
        }
        match self.state {
            State::Receiving { peer: busy, .. } | State::Validating { peer: busy, .. } if busy != peer => {
                return (ack(MavMissionResult::MAV_MISSION_DENIED), None);
            }
            _ => {}
        }
        if m.count == 0 {
            self.state = State::Idle;
            return (
                ack(MavMissionResult::MAV_MISSION_ACCEPTED),
                Some(Completed::Cleared(mission_type)),
            );
        }
        self.state = State::Receiving {
            peer,
            ids,
            mission_type,
            count: m.count,
            items: Vec::with_capacity(usize::from(m.count)),
            requested_at_s: now_s,
            retries: 0,
        };
        (vec![(peer, request(ids, mission_type, 0))], None)
    }

    /// MISSION_ITEM_INT from `peer`.
    pub fn on_item(
        &mut self,
        peer: P,
        m: &MISSION_ITEM_INT_DATA,
        now_s: f64,
    ) -> (Vec<(P, MavMessage)>, Option<Completed>) {
        let State::Receiving {
            peer: from,
            ids,
            mission_type,
            count,
            items,
            requested_at_s,
            retries,
        } = &mut self.state
        else {
            return (Vec::new(), None);
        };
        if *from != peer || m.mission_type != *mission_type {
            return (Vec::new(), None);
        }
        let next = items.len() as u16;
        if m.seq != next {
            // Out of sequence: drop it and ask again for the one we need.
            return (vec![(peer, request(*ids, *mission_type, next))], None);
        }
        items.push(m.clone());
        *requested_at_s = now_s;
        *retries = 0;
        if items.len() < usize::from(*count) {
            return (vec![(peer, request(*ids, *mission_type, next + 1))], None);
        }
        let (ids, mission_type, items) = (*ids, *mission_type, std::mem::take(items));
        self.state = State::Validating {
            peer,
            ids,
            mission_type,
        };
        (Vec::new(), Some(Completed::Items(mission_type, items)))
    }

    /// Answers the validated upload with `result` and `opaque_id` (the caller stores the plan
    /// when ACCEPTED and names its id, as PX4 does; 0 otherwise).
    pub fn finish(&mut self, result: MavMissionResult, opaque_id: u32) -> Vec<(P, MavMessage)> {
        match std::mem::replace(&mut self.state, State::Idle) {
            State::Validating {
                peer,
                ids,
                mission_type,
            } => {
                let mut ack = mission_ack(ids, mission_type, result);
                if let MavMessage::MISSION_ACK(a) = &mut ack {
                    a.opaque_id = opaque_id;
                }
                vec![(peer, ack)]
            }
            other => {
                self.state = other;
                Vec::new()
            }
        }
    }

    /// MISSION_CLEAR_ALL of plan `mission_type` (mission, fence, rally or all) from `peer`.
    pub fn on_clear(
        &mut self,
        peer: P,
        ids: Ids,
        mission_type: MavMissionType,
    ) -> (Vec<(P, MavMessage)>, Option<Completed>) {
        self.state = State::Idle;
        (
            vec![(
                peer,
                mission_ack(ids, mission_type, MavMissionResult::MAV_MISSION_ACCEPTED),
            )],
            Some(Completed::Cleared(mission_type)),
        )
    }

    /// Re-requests a missing item or cancels a stalled upload.
    pub fn tick(&mut self, now_s: f64) -> Vec<(P, MavMessage)> {
        let State::Receiving {
            peer,
            ids,
            mission_type,
            items,
            requested_at_s,
            retries,
            ..
        } = &mut self.state
        else {
            return Vec::new();
        };
        if now_s - *requested_at_s < RETRY_S {
            return Vec::new();
        }
        if *retries >= MAX_RETRIES {
            let cancelled = MavMissionResult::MAV_MISSION_OPERATION_CANCELLED;
            let out = vec![(*peer, mission_ack(*ids, *mission_type, cancelled))];
            self.state = State::Idle;
            return out;
        }
        *retries += 1;
        *requested_at_s = now_s;
        vec![(*peer, request(*ids, *mission_type, items.len() as u16))]
    }

    /// True while an upload is under way.
    pub fn busy(&self) -> bool {
        !matches!(self.state, State::Idle)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mavlink::dialects::common::MavCmd;

    const GCS: Ids = (255, 190);
    const MISSION: MavMissionType = MavMissionType::MAV_MISSION_TYPE_MISSION;

    fn count(n: u16) -> MISSION_COUNT_DATA {
        MISSION_COUNT_DATA {
            count: n,
            target_system: 1,
            target_component: 1,
            mission_type: MISSION,
            opaque_id: 0,
        }
    }

    fn item(seq: u16) -> MISSION_ITEM_INT_DATA {
        MISSION_ITEM_INT_DATA {
            seq,
            command: MavCmd::MAV_CMD_NAV_WAYPOINT,
            ..Default::default()
        }
    }

    fn requested(out: &[(u8, MavMessage)]) -> Option<u16> {
        match out.first() {
            Some((_, MavMessage::MISSION_REQUEST_INT(r))) => Some(r.seq),
            _ => None,
        }
    }

    #[test]
    fn upload_requests_each_item_and_completes() {
        let mut x = MissionTransfer::<u8>::default();
        let (out, _) = x.on_count(7, GCS, &count(3), 0.0);
        assert_eq!(requested(&out), Some(0));
        assert_eq!(requested(&x.on_item(7, &item(0), 0.01).0), Some(1));
        // Out of sequence: re-request 1.
        assert_eq!(requested(&x.on_item(7, &item(2), 0.02).0), Some(1));
        assert_eq!(requested(&x.on_item(7, &item(1), 0.03).0), Some(2));
        let (out, done) = x.on_item(7, &item(2), 0.04);
        assert!(out.is_empty());
        assert!(matches!(done, Some(Completed::Items(MISSION, ref v)) if v.len() == 3));
        // Another peer is denied while the first one's upload is validated.
        let (out, _) = x.on_count(8, (250, 1), &count(1), 0.05);
        assert!(
            matches!(out[0].1, MavMessage::MISSION_ACK(ref a) if a.mavtype == MavMissionResult::MAV_MISSION_DENIED)
        );
        let out = x.finish(MavMissionResult::MAV_MISSION_ACCEPTED, 0xC0FF_EE00);
        assert!(
            matches!(out[0], (7, MavMessage::MISSION_ACK(ref a)) if a.mavtype == MavMissionResult::MAV_MISSION_ACCEPTED && a.target_system == 255 && a.opaque_id == 0xC0FF_EE00)
        );
        assert!(!x.busy());
    }

    #[test]
    fn stalled_upload_is_retried_then_cancelled() {
        let mut x = MissionTransfer::<u8>::default();
        x.on_count(7, GCS, &count(2), 0.0);
        assert!(x.tick(0.1).is_empty());
        for k in 1..=MAX_RETRIES {
            assert_eq!(requested(&x.tick(0.26 * f64::from(k))), Some(0));
        }
        let out = x.tick(10.0);
        assert!(
            matches!(out[0].1, MavMessage::MISSION_ACK(ref a) if a.mavtype == MavMissionResult::MAV_MISSION_OPERATION_CANCELLED)
        );
        assert!(!x.busy());
    }

    #[test]
    fn count_zero_and_clear_all_clear_the_plan_of_their_type() {
        let mut x = MissionTransfer::<u8>::default();
        let (_, done) = x.on_count(7, GCS, &count(0), 0.0);
        assert_eq!(done, Some(Completed::Cleared(MISSION)));
        let all = MavMissionType::MAV_MISSION_TYPE_ALL;
        let (out, done) = x.on_clear(7, GCS, all);
        assert_eq!(done, Some(Completed::Cleared(all)));
        assert!(matches!(out[0].1, MavMessage::MISSION_ACK(ref a) if a.mission_type == all));
    }

    /// The mission_type of a mission-protocol reply and its result or seq.
    fn typed(msg: &MavMessage) -> Option<(MavMissionType, u32)> {
        match msg {
            MavMessage::MISSION_ACK(a) => Some((a.mission_type, a.mavtype as u32)),
            MavMessage::MISSION_REQUEST_INT(r) => Some((r.mission_type, u32::from(r.seq))),
            _ => None,
        }
    }

    #[test]
    fn fence_and_rally_uploads_run_as_their_own_type() {
        let fence = MavMissionType::MAV_MISSION_TYPE_FENCE;
        let rally = MavMissionType::MAV_MISSION_TYPE_RALLY;
        let typed_count = |mission_type, n| MISSION_COUNT_DATA {
            mission_type,
            ..count(n)
        };
        let mut x = MissionTransfer::<u8>::default();
        let (out, _) = x.on_count(7, GCS, &typed_count(fence, 2), 0.0);
        assert_eq!(typed(&out[0].1), Some((fence, 0)), "MISSION_REQUEST_INT 0 of the fence");
        // A mission item does not fill a fence upload; a fence item does.
        assert!(x.on_item(7, &item(0), 0.01).0.is_empty());
        let fence_item = |seq| MISSION_ITEM_INT_DATA {
            mission_type: fence,
            ..item(seq)
        };
        assert_eq!(typed(&x.on_item(7, &fence_item(0), 0.02).0[0].1), Some((fence, 1)));
        let (_, done) = x.on_item(7, &fence_item(1), 0.03);
        assert!(matches!(done, Some(Completed::Items(t, ref v)) if t == fence && v.len() == 2));
        let accepted = MavMissionResult::MAV_MISSION_ACCEPTED as u32;
        assert_eq!(
            typed(&x.finish(MavMissionResult::MAV_MISSION_ACCEPTED, 1)[0].1),
            Some((fence, accepted))
        );
        // Clearing rally by count 0 is a rally clear.
        let (out, done) = x.on_count(7, GCS, &typed_count(rally, 0), 0.0);
        assert_eq!(typed(&out[0].1), Some((rally, accepted)));
        assert_eq!(done, Some(Completed::Cleared(rally)));
        // A stalled rally upload is cancelled as rally.
        x.on_count(7, GCS, &typed_count(rally, 1), 0.0);
        for k in 1..=MAX_RETRIES {
            assert_eq!(typed(&x.tick(0.26 * f64::from(k))[0].1), Some((rally, 0)));
        }
        let cancelled = MavMissionResult::MAV_MISSION_OPERATION_CANCELLED as u32;
        assert_eq!(typed(&x.tick(10.0)[0].1), Some((rally, cancelled)));
        // Another type (ALL) cannot be uploaded.
        let all = MavMissionType::MAV_MISSION_TYPE_ALL;
        let (out, done) = x.on_count(7, GCS, &typed_count(all, 3), 0.0);
        let unsupported = MavMissionResult::MAV_MISSION_UNSUPPORTED as u32;
        assert_eq!((typed(&out[0].1), done), (Some((all, unsupported)), None));
        assert!(!x.busy());
    }
}
