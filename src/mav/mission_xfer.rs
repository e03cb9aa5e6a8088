//! The mission transfer protocol (docs/mavlink.md §7), as a state machine with the time passed in.
//!
//! Upload: MISSION_COUNT(n) → MISSION_REQUEST_INT(0) → MISSION_ITEM_INT(0) → … → the caller
//! validates the staged items and answers with [`MissionTransfer::finish`]; the stored plan
//! changes only then (atomic replace). On a lossy link (PX4's `MavlinkMissionManager`):
//! - a missing item is re-requested every [`RETRY_S`] until [`PROTOCOL_TIMEOUT_S`] passed without
//!   a word from the client; then the upload is dropped with a critical "Operation timeout";
//! - an item from further on (the one asked for was lost) makes the vehicle ask again at once; a
//!   repeat of an item already stored (a duplicate, or an answer to a repeated request) is
//!   ignored, so that duplicates cannot multiply the traffic;
//! - MISSION_COUNT repeated before the first item (the request was lost) is asked again for; a
//!   repeat with the same count once items arrived is a duplicate and changes nothing;
//! - the last item repeated after the final MISSION_ACK (the ACK was lost) gets that ACK again.
//!
//! A second peer is DENIED while one uploads.
//! Downloads are stateless: the client asks, the link answers from the
//! [`PlanStore`](super::plan_store::PlanStore).
//!
//! Every reply carries the `mission_type` of the request it answers. The mission (type 0), the
//! fence (1) and the rally points (2) are plans of their own, uploaded and cleared alike (as PX4
//! stores them); MISSION_CLEAR_ALL of MAV_MISSION_TYPE_ALL clears all three, and an upload of
//! another type is refused with UNSUPPORTED.
//! ArduCopter's face (docs/ardupilot.md §6) asks for the items of a mission upload with
//! MISSION_REQUEST (the non-INT message, all DroneKit answers) and asks again after
//! [`COPTER_RETRY_S`]; fence and rally uploads go as PX4's.
//! Pure; `P` identifies a peer (an address in the runtime).

use mavlink::dialects::ardupilotmega::{
    MavMessage, MavMissionResult, MavMissionType, MISSION_ACK_DATA, MISSION_COUNT_DATA, MISSION_ITEM_INT_DATA,
    MISSION_REQUEST_INT_DATA,
};

use super::ardupilot::copter_mission::COPTER_RETRY_S;
use super::identity::Personality;

/// Re-request a missing item after this long [s] (PX4's `MAVLINK_MISSION_RETRY_TIMEOUT_DEFAULT`).
pub const RETRY_S: f64 = 0.25;
/// An upload is dropped after this long without a word from its client [s] (PX4's
/// `MAVLINK_MISSION_PROTOCOL_TIMEOUT_DEFAULT`).
pub const PROTOCOL_TIMEOUT_S: f64 = 5.0;
/// What the vehicle says when it drops a silent upload (PX4's text).
pub const TIMEOUT_TEXT: &str = "Operation timeout";

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
        /// Wall time of the latest request sent [s].
        requested_at_s: f64,
        /// Wall time the client was last heard [s].
        heard_at_s: f64,
    },
    Validating {
        peer: P,
        ids: Ids,
        mission_type: MavMissionType,
        last_seq: u16,
    },
}

/// The final answer of the latest upload, for a client that did not receive it.
#[derive(Debug, Clone, PartialEq)]
struct Answered<P> {
    peer: P,
    mission_type: MavMissionType,
    last_seq: u16,
    ack: MavMessage,
}

/// Upload state of one link.
#[derive(Debug, Clone, PartialEq)]
pub struct MissionTransfer<P> {
    state: State<P>,
    answered: Option<Answered<P>>,
    /// Whose face the requests show (PX4's or ArduCopter's).
    personality: Personality,
}

impl<P> Default for MissionTransfer<P> {
    /// PX4's.
    fn default() -> Self {
        Self::new(Personality::Px4)
    }
}

impl<P> MissionTransfer<P> {
    /// No upload, with `personality`'s requests.
    pub fn new(personality: Personality) -> Self {
        Self {
            state: State::Idle,
            answered: None,
            personality,
        }
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

/// The request for item `seq` of plan `mission_type` to `ids`: MISSION_REQUEST_INT as PX4 asks,
/// MISSION_REQUEST as ArduCopter asks.
#[allow(deprecated)] // MISSION_REQUEST: what ArduPilot sends and DroneKit answers
fn request(personality: Personality, ids: Ids, mission_type: MavMissionType, seq: u16) -> MavMessage {
    // ArduCopter's `MissionItemProtocol` asks for mission, fence and rally items alike.
    if personality == Personality::ArduPilot {
        return MavMessage::MISSION_REQUEST(mavlink::dialects::ardupilotmega::MISSION_REQUEST_DATA {
            seq,
            target_system: ids.0,
            target_component: ids.1,
            mission_type,
        });
    }
    MavMessage::MISSION_REQUEST_INT(MISSION_REQUEST_INT_DATA {
        seq,
        target_system: ids.0,
        target_component: ids.1,
        mission_type,
    })
}

/// How long a request for an item waits before it is sent again [s].
fn retry_s(personality: Personality) -> f64 {
    // ArduCopter's `MissionItemProtocol` asks for mission, fence and rally items alike.
    if personality == Personality::ArduPilot {
        COPTER_RETRY_S
    } else {
        RETRY_S
    }
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
        match &mut self.state {
            State::Receiving { peer: busy, .. } | State::Validating { peer: busy, .. } if *busy != peer => {
                return (ack(MavMissionResult::MAV_MISSION_DENIED), None);
            }
            State::Receiving {
                mission_type: receiving,
                count,
                items,
                heard_at_s,
                ..
            } if *receiving == mission_type && *count == m.count && !items.is_empty() => {
                // A duplicate of the count that started this upload.
                *heard_at_s = now_s;
                return (Vec::new(), None);
            }
            State::Validating { mission_type: t, .. } if *t == mission_type => return (Vec::new(), None),
            _ => {}
        }
        self.answered = None;
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
            items: Vec::new(),
            requested_at_s: now_s,
            heard_at_s: now_s,
        };
        (vec![(peer, request(self.personality, ids, mission_type, 0))], None)
    }

    /// MISSION_ITEM_INT from `peer`.
    pub fn on_item(
        &mut self,
        peer: P,
        m: &MISSION_ITEM_INT_DATA,
        now_s: f64,
    ) -> (Vec<(P, MavMessage)>, Option<Completed>) {
        if let Some(a) = &self.answered {
            if matches!(self.state, State::Idle)
                && a.peer == peer
                && a.mission_type == m.mission_type
                && a.last_seq == m.seq
            {
                // The final ACK was lost: the client sends its last item again.
                return (vec![(peer, a.ack.clone())], None);
            }
        }
        let personality = self.personality;
        let State::Receiving {
            peer: from,
            ids,
            mission_type,
            count,
            items,
            requested_at_s,
            heard_at_s,
        } = &mut self.state
        else {
            return (Vec::new(), None);
        };
        if *from != peer || m.mission_type != *mission_type {
            return (Vec::new(), None);
        }
        *heard_at_s = now_s;
        let next = items.len() as u16;
        if m.seq < next {
            // Stored already: a duplicate, or the answer to a request sent twice.
            return (Vec::new(), None);
        }
        if m.seq > next || m.seq >= *count {
            // The item asked for was lost: ask for it again now.
            *requested_at_s = now_s;
            return (vec![(peer, request(personality, *ids, *mission_type, next))], None);
        }
        items.push(m.clone());
        *requested_at_s = now_s;
        if items.len() < usize::from(*count) {
            return (vec![(peer, request(personality, *ids, *mission_type, next + 1))], None);
        }
        let (ids, mission_type, items) = (*ids, *mission_type, std::mem::take(items));
        self.state = State::Validating {
            peer,
            ids,
            mission_type,
            last_seq: next,
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
                last_seq,
            } => {
                let mut ack = mission_ack(ids, mission_type, result);
                if let MavMessage::MISSION_ACK(a) = &mut ack {
                    a.opaque_id = opaque_id;
                }
                self.answered = Some(Answered {
                    peer,
                    mission_type,
                    last_seq,
                    ack: ack.clone(),
                });
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
        self.answered = None;
        (
            vec![(
                peer,
                mission_ack(ids, mission_type, MavMissionResult::MAV_MISSION_ACCEPTED),
            )],
            Some(Completed::Cleared(mission_type)),
        )
    }

    /// Re-requests a missing item, or drops an upload whose client fell silent (the caller
    /// tells the client [`TIMEOUT_TEXT`] when this returns true).
    pub fn tick(&mut self, now_s: f64) -> (Vec<(P, MavMessage)>, bool) {
        let personality = self.personality;
        let State::Receiving {
            peer,
            ids,
            mission_type,
            items,
            requested_at_s,
            heard_at_s,
            ..
        } = &mut self.state
        else {
            return (Vec::new(), false);
        };
        if now_s - *heard_at_s >= PROTOCOL_TIMEOUT_S {
            self.state = State::Idle;
            return (Vec::new(), true);
        }
        if now_s - *requested_at_s < retry_s(personality) {
            return (Vec::new(), false);
        }
        *requested_at_s = now_s;
        (
            vec![(*peer, request(personality, *ids, *mission_type, items.len() as u16))],
            false,
        )
    }

    /// The peer of the upload in progress.
    pub fn client(&self) -> Option<P> {
        match self.state {
            State::Idle => None,
            State::Receiving { peer, .. } | State::Validating { peer, .. } => Some(peer),
        }
    }

    /// True while an upload is under way.
    pub fn busy(&self) -> bool {
        !matches!(self.state, State::Idle)
    }
}

#[cfg(test)]
#[path = "mission_xfer_tests.rs"]
mod tests;
