//! The ground-station side of the protocol, for the bench client, the tests and the fuzz
//! target: the header a ground station sends with (255/190, docs/mavlink.md §1), COMMAND_LONG from
//! its seven parameters, and which COMMAND_ACK answers a command (docs/mavlink.md §3.1). Pure.

use mavlink::dialects::ardupilotmega::{MavCmd, MavMessage, MavResult, COMMAND_LONG_DATA};
use mavlink::MavHeader;

/// System id of a ground station (QGC and MAVSDK use 255 … 245).
pub const GCS_SYSTEM_ID: u8 = 255;
/// Component id of a ground station (MAV_COMP_ID_MISSIONPLANNER).
pub const GCS_COMPONENT_ID: u8 = 190;

/// The header of a ground-station frame with `sequence`.
pub fn gcs_header(sequence: u8) -> MavHeader {
    MavHeader {
        system_id: u32::from(GCS_SYSTEM_ID),
        component_id: GCS_COMPONENT_ID,
        sequence,
    }
}

/// COMMAND_LONG `command` with `params` (param1 … param7) to `target` (system, component),
/// confirmation 0.
pub fn command_long(target: (u8, u8), command: MavCmd, params: [f32; 7]) -> COMMAND_LONG_DATA {
    let [param1, param2, param3, param4, param5, param6, param7] = params;
    COMMAND_LONG_DATA {
        param1,
        param2,
        param3,
        param4,
        param5,
        param6,
        param7,
        command,
        target_system: target.0,
        target_component: target.1,
        confirmation: 0,
    }
}

/// The result of `message` from `sender` when it is the COMMAND_ACK of `command` sent to
/// `target_system`: it names the command and comes from the target system (any system when the
/// command was broadcast, target system 0).
pub fn ack_result(sender: &MavHeader, message: &MavMessage, command: MavCmd, target_system: u8) -> Option<MavResult> {
    match message {
        MavMessage::COMMAND_ACK(ack)
            if ack.command == command && (target_system == 0 || sender.system_id == u32::from(target_system)) =>
        {
            Some(ack.result)
        }
        _ => None,
    }
}

/// True for a HEARTBEAT from an autopilot (component 1).
pub fn is_autopilot_heartbeat(sender: &MavHeader, message: &MavMessage) -> bool {
    sender.component_id == 1 && matches!(message, MavMessage::HEARTBEAT(_))
}

#[cfg(test)]
mod tests {
    use super::*;
    use mavlink::dialects::ardupilotmega::COMMAND_ACK_DATA;

    #[test]
    fn acks_count_from_the_target_system_or_any_for_a_broadcast() {
        let cmd = command_long((1, 1), MavCmd::MAV_CMD_NAV_LAND, [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0]);
        assert_eq!((cmd.param1, cmd.param7, cmd.target_component), (1.0, 7.0, 1));
        let ack = MavMessage::COMMAND_ACK(COMMAND_ACK_DATA {
            command: MavCmd::MAV_CMD_NAV_LAND,
            result: MavResult::MAV_RESULT_DENIED,
            ..Default::default()
        });
        let from = |system_id| MavHeader {
            system_id,
            ..gcs_header(0)
        };
        let denied = Some(MavResult::MAV_RESULT_DENIED);
        assert_eq!(ack_result(&from(1), &ack, MavCmd::MAV_CMD_NAV_LAND, 1), denied);
        assert_eq!(ack_result(&from(2), &ack, MavCmd::MAV_CMD_NAV_LAND, 1), None);
        assert_eq!(ack_result(&from(2), &ack, MavCmd::MAV_CMD_NAV_LAND, 0), denied);
        assert_eq!(ack_result(&from(1), &ack, MavCmd::MAV_CMD_NAV_TAKEOFF, 1), None);
    }
}
