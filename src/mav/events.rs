//! PX4's events protocol, the part a vehicle without events answers: CURRENT_EVENT_SEQUENCE
//! (411) every 3 s on each link with sequence 0 and the reset flag (PX4 sets it while its
//! buffer is empty), and REQUEST_EVENT (412) answered by one RESPONSE_EVENT_ERROR (413) with
//! reason UNAVAILABLE, as PX4 answers a range its buffer does not hold. Pure.
//!
//! Why no EVENT (410) is ever sent: an event carries only an id and arguments, which a ground
//! station can turn into text only with the vehicle's events metadata (a component-metadata file
//! generated from PX4's source). Everything this vehicle announces goes out as STATUSTEXT, which
//! QGroundControl, MAVSDK and MAVProxy all show.

use mavlink::dialects::ardupilotmega::{
    MavEventCurrentSequenceFlags, MavEventErrorReason, MavMessage, CURRENT_EVENT_SEQUENCE_DATA, REQUEST_EVENT_DATA,
    RESPONSE_EVENT_ERROR_DATA,
};

/// CURRENT_EVENT_SEQUENCE period [s] (PX4's `current_sequence_interval`).
pub const CURRENT_SEQUENCE_PERIOD_S: f64 = 3.0;

/// CURRENT_EVENT_SEQUENCE of an empty event buffer.
pub fn current_event_sequence() -> MavMessage {
    MavMessage::CURRENT_EVENT_SEQUENCE(CURRENT_EVENT_SEQUENCE_DATA {
        sequence: 0,
        flags: MavEventCurrentSequenceFlags::MAV_EVENT_CURRENT_SEQUENCE_FLAGS_RESET,
    })
}

/// The answer to `request` from the peer with MAVLink ids `(system, component)`: its first
/// sequence is unavailable, and so is every later one.
pub fn event_unavailable(request: &REQUEST_EVENT_DATA, (system, component): (u8, u8)) -> MavMessage {
    MavMessage::RESPONSE_EVENT_ERROR(RESPONSE_EVENT_ERROR_DATA {
        sequence: request.first_sequence,
        sequence_oldest_available: 0,
        target_system: system,
        target_component: component,
        reason: MavEventErrorReason::MAV_EVENT_ERROR_REASON_UNAVAILABLE,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_empty_buffer_says_reset_and_answers_every_request_with_unavailable() {
        let MavMessage::CURRENT_EVENT_SEQUENCE(c) = current_event_sequence() else {
            panic!()
        };
        assert_eq!(c.sequence, 0);
        assert_eq!(
            c.flags,
            MavEventCurrentSequenceFlags::MAV_EVENT_CURRENT_SEQUENCE_FLAGS_RESET
        );
        let request = REQUEST_EVENT_DATA {
            first_sequence: 7,
            last_sequence: 9,
            target_system: 1,
            target_component: 1,
        };
        let MavMessage::RESPONSE_EVENT_ERROR(e) = event_unavailable(&request, (255, 190)) else {
            panic!()
        };
        assert_eq!((e.sequence, e.target_system, e.target_component), (7, 255, 190));
        assert_eq!(e.reason, MavEventErrorReason::MAV_EVENT_ERROR_REASON_UNAVAILABLE);
    }
}
