//! The mission transfer protocol (mavlink.md §7), as a state machine with the time passed in.
//!
//! Upload: MISSION_COUNT(n) → MISSION_REQUEST_INT(0) → MISSION_ITEM_INT(0) → … → the caller
//! validates the staged items and answers with [`MissionTransfer::finish`]; the stored mission
//! changes only then (atomic replace). Out-of-sequence items are dropped and re-requested; a
//! missing item is re-requested every [`RETRY_S`], at most [`MAX_RETRIES`] times, then the
//! upload is cancelled with OPERATION_CANCELLED. A second peer is DENIED while one uploads.
//! Downloads are stateless: the client asks, the machine answers from the stored items.
//!
//! Every reply carries the `mission_type` of the request it answers. Only the mission (type 0)
//! is stored: a fence (1) or rally (2) upload is refused with UNSUPPORTED, and a fence or rally
//! download is an empty plan (MISSION_COUNT 0, as PX4 answers when it holds none).
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
    /// Every item arrived; validate, then call [`MissionTransfer::finish`].
    Items(Vec<MISSION_ITEM_INT_DATA>),
    /// MISSION_COUNT(0) or MISSION_CLEAR_ALL: clear the stored mission (already ACKed).
    Cleared,
}

#[derive(Debug, Clone, PartialEq)]
enum State<P> {
    Idle,
    Receiving {
        peer: P,
        ids: Ids,
        count: u16,
        items: Vec<MISSION_ITEM_INT_DATA>,
        requested_at_s: f64,
        retries: u8,
    },
    Validating {
        peer: P,
        ids: Ids,
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

/// The plan type uploads fill.
const MISSION: MavMissionType = MavMissionType::MAV_MISSION_TYPE_MISSION;

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

fn request(ids: Ids, seq: u16) -> MavMessage {
    MavMessage::MISSION_REQUEST_INT(MISSION_REQUEST_INT_DATA {
        seq,
        target_system: ids.0,
        target_component: ids.1,
        mission_type: MISSION,
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
        if m.mission_type != MISSION {
            return (
                vec![(
                    peer,
                    mission_ack(ids, m.mission_type, MavMissionResult::MAV_MISSION_UNSUPPORTED),
                )],
                None,
            );
        }
        match self.state {
            State::Receiving { peer: busy, .. } | State::Validating { peer: busy, .. } if busy != peer => {
                return (
                    vec![(peer, mission_ack(ids, MISSION, MavMissionResult::MAV_MISSION_DENIED))],
                    None,
                );
            }
            _ => {}
        }
        if m.count == 0 {
            self.state = State::Idle;
            return (
                vec![(peer, mission_ack(ids, MISSION, MavMissionResult::MAV_MISSION_ACCEPTED))],
                Some(Completed::Cleared),
            );
        }
        self.state = State::Receiving {
            peer,
            ids,
            count: m.count,
            items: Vec::with_capacity(usize::from(m.count)),
            requested_at_s: now_s,
            retries: 0,
        };
        (vec![(peer, request(ids, 0))], None)
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
            count,
            items,
            requested_at_s,
            retries,
        } = &mut self.state
        else {
            return (Vec::new(), None);
        };
        if *from != peer || m.mission_type != MISSION {
            return (Vec::new(), None);
        }
        let next = items.len() as u16;
        if m.seq != next {
            // Out of sequence: drop it and ask again for the one we need.
            return (vec![(peer, request(*ids, next))], None);
        }
        items.push(m.clone());
        *requested_at_s = now_s;
        *retries = 0;
        if items.len() < usize::from(*count) {
            return (vec![(peer, request(*ids, next + 1))], None);
        }
        let (ids, items) = (*ids, std::mem::take(items));
        self.state = State::Validating { peer, ids };
        (Vec::new(), Some(Completed::Items(items)))
    }

    /// Answers the validated upload with `result` (the caller stores the mission when ACCEPTED).
    pub fn finish(&mut self, result: MavMissionResult) -> Vec<(P, MavMessage)> {
        match std::mem::replace(&mut self.state, State::Idle) {
            State::Validating { peer, ids } => vec![(peer, mission_ack(ids, MISSION, result))],
            other => {
                self.state = other;
                Vec::new()
            }
        }
    }

    /// MISSION_CLEAR_ALL of the mission from `peer`.
    pub fn on_clear(&mut self, peer: P, ids: Ids) -> (Vec<(P, MavMessage)>, Option<Completed>) {
        self.state = State::Idle;
        (
            vec![(peer, mission_ack(ids, MISSION, MavMissionResult::MAV_MISSION_ACCEPTED))],
            Some(Completed::Cleared),
        )
    }

    /// Re-requests a missing item or cancels a stalled upload.
    pub fn tick(&mut self, now_s: f64) -> Vec<(P, MavMessage)> {
        let State::Receiving {
            peer,
            ids,
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
            let out = vec![(
                *peer,
                mission_ack(*ids, MISSION, MavMissionResult::MAV_MISSION_OPERATION_CANCELLED),
            )];
            self.state = State::Idle;
            return out;
        }
        *retries += 1;
        *requested_at_s = now_s;
        vec![(*peer, request(*ids, items.len() as u16))]
    }

    /// True while an upload is under way.
    pub fn busy(&self) -> bool {
        !matches!(self.state, State::Idle)
    }
}

/// The items of plan `mission_type`: the stored mission for the mission, none for the others
/// (fence and rally plans are always empty here).
fn plan(mission_type: MavMissionType, stored: &[MISSION_ITEM_INT_DATA]) -> &[MISSION_ITEM_INT_DATA] {
    if mission_type == MISSION {
        stored
    } else {
        &[]
    }
}

/// MISSION_COUNT of plan `mission_type` for a download (`stored`: the stored mission).
pub fn download_count(ids: Ids, mission_type: MavMissionType, stored: &[MISSION_ITEM_INT_DATA]) -> MavMessage {
    MavMessage::MISSION_COUNT(MISSION_COUNT_DATA {
        count: plan(mission_type, stored).len() as u16,
        target_system: ids.0,
        target_component: ids.1,
        mission_type,
        opaque_id: 0,
    })
}

/// Item `seq` of plan `mission_type` addressed to `ids` (`stored`: the stored mission), or a
/// MISSION_ACK(INVALID_SEQUENCE) of that type.
pub fn download_item(ids: Ids, mission_type: MavMissionType, seq: u16, stored: &[MISSION_ITEM_INT_DATA]) -> MavMessage {
    match plan(mission_type, stored).get(usize::from(seq)) {
        Some(item) => MavMessage::MISSION_ITEM_INT(MISSION_ITEM_INT_DATA {
            target_system: ids.0,
            target_component: ids.1,
            mission_type,
            ..item.clone()
        }),
        None => mission_ack(ids, mission_type, MavMissionResult::MAV_MISSION_INVALID_SEQUENCE),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mavlink::dialects::common::MavCmd;

    const GCS: Ids = (255, 190);

    fn count(n: u16) -> MISSION_COUNT_DATA {
        MISSION_COUNT_DATA {
            count: n,
            target_system: 1,
            target_component: 1,
            mission_type: MavMissionType::MAV_MISSION_TYPE_MISSION,
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
        assert!(matches!(done, Some(Completed::Items(ref v)) if v.len() == 3));
        // Another peer is denied while the first one's upload is validated.
        let (out, _) = x.on_count(8, (250, 1), &count(1), 0.05);
        assert!(
            matches!(out[0].1, MavMessage::MISSION_ACK(ref a) if a.mavtype == MavMissionResult::MAV_MISSION_DENIED)
        );
        let out = x.finish(MavMissionResult::MAV_MISSION_ACCEPTED);
        assert!(
            matches!(out[0], (7, MavMessage::MISSION_ACK(ref a)) if a.mavtype == MavMissionResult::MAV_MISSION_ACCEPTED && a.target_system == 255)
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
    fn count_zero_clears_and_downloads_answer_from_the_store() {
        let mut x = MissionTransfer::<u8>::default();
        let (_, done) = x.on_count(7, GCS, &count(0), 0.0);
        assert_eq!(done, Some(Completed::Cleared));
        let stored = [item(0), item(1)];
        assert!(matches!(download_count(GCS, MISSION, &stored), MavMessage::MISSION_COUNT(ref c) if c.count == 2));
        assert!(
            matches!(download_item(GCS, MISSION, 1, &stored), MavMessage::MISSION_ITEM_INT(ref i) if i.seq == 1 && i.target_system == 255)
        );
        assert!(matches!(
            download_item(GCS, MISSION, 5, &stored),
            MavMessage::MISSION_ACK(_)
        ));
    }

    /// The mission_type of a mission-protocol reply and its result, count or seq.
    fn typed(msg: &MavMessage) -> Option<(MavMissionType, u32)> {
        match msg {
            MavMessage::MISSION_ACK(a) => Some((a.mission_type, a.mavtype as u32)),
            MavMessage::MISSION_COUNT(c) => Some((c.mission_type, u32::from(c.count))),
            MavMessage::MISSION_REQUEST_INT(r) => Some((r.mission_type, u32::from(r.seq))),
            MavMessage::MISSION_ITEM_INT(i) => Some((i.mission_type, u32::from(i.seq))),
            _ => None,
        }
    }

    #[test]
    fn replies_carry_the_mission_type_of_the_request() {
        let fence = MavMissionType::MAV_MISSION_TYPE_FENCE;
        let rally = MavMissionType::MAV_MISSION_TYPE_RALLY;
        let unsupported = MavMissionResult::MAV_MISSION_UNSUPPORTED as u32;
        let mut x = MissionTransfer::<u8>::default();
        // Uploads of another plan are refused as that plan: a fence, and clearing rally by count 0.
        for (mission_type, n) in [(fence, 2), (rally, 0)] {
            let (out, done) = x.on_count(
                7,
                GCS,
                &MISSION_COUNT_DATA {
                    mission_type,
                    ..count(n)
                },
                0.0,
            );
            assert_eq!(typed(&out[0].1), Some((mission_type, unsupported)), "{mission_type:?}");
            assert_eq!(done, None);
            assert!(!x.busy());
        }
        // Downloads of fence and rally: an empty plan of that type.
        let stored = [item(0), item(1)];
        assert_eq!(typed(&download_count(GCS, fence, &stored)), Some((fence, 0)));
        assert_eq!(typed(&download_count(GCS, rally, &stored)), Some((rally, 0)));
        let invalid = MavMissionResult::MAV_MISSION_INVALID_SEQUENCE as u32;
        assert_eq!(typed(&download_item(GCS, rally, 0, &stored)), Some((rally, invalid)));
        // The mission's own replies say mission.
        assert_eq!(typed(&download_count(GCS, MISSION, &stored)), Some((MISSION, 2)));
        let stray = MISSION_ITEM_INT_DATA {
            mission_type: fence,
            ..item(1)
        };
        assert_eq!(
            typed(&download_item(GCS, MISSION, 1, &[item(0), stray])),
            Some((MISSION, 1))
        );
        let (out, _) = x.on_count(7, GCS, &count(1), 0.0);
        assert_eq!(
            typed(&out[0].1),
            Some((MISSION, 0)),
            "MISSION_REQUEST_INT 0 of the mission"
        );
    }
}
