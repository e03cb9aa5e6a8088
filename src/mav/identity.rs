//! Who the autopilot is on a link and how it answers: its identity and addressing rule
//! (docs/mavlink.md §1, §3.1), its HEARTBEAT, and COMMAND_ACK with the MAV_RESULT of an outcome. Pure.

use mavlink::dialects::ardupilotmega::{
    MavAutopilot, MavCmd, MavMessage, MavModeFlag, MavResult, MavState, MavType, COMMAND_ACK_DATA, HEARTBEAT_DATA,
};
use mavlink::MavHeader;

use crate::commander::{FlightMode, Outcome};

/// The autopilot a vehicle presents itself as on its links: the same commander, navigation and
/// control behind PX4's face or ArduCopter's (docs/ardupilot.md).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Personality {
    /// PX4 (MAV_AUTOPILOT_PX4): PX4's modes, streams, parameters and texts.
    #[default]
    Px4,
    /// ArduCopter (MAV_AUTOPILOT_ARDUPILOTMEGA): Copter's mode numbers, GUIDED, streams only on
    /// request, ArduPilot's parameter names and texts.
    ArduPilot,
}

impl Personality {
    /// The name `--autopilot` takes.
    pub fn name(self) -> &'static str {
        match self {
            Personality::Px4 => "px4",
            Personality::ArduPilot => "ardupilot",
        }
    }
}

impl std::str::FromStr for Personality {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_lowercase().as_str() {
            "px4" => Ok(Personality::Px4),
            "ardupilot" | "arducopter" => Ok(Personality::ArduPilot),
            other => Err(format!("unknown autopilot '{other}': px4 or ardupilot")),
        }
    }
}

impl std::fmt::Display for Personality {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Who we are on the link.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Identity {
    /// System id, 1–255.
    pub system_id: u8,
    /// Component id (1, autopilot).
    pub component_id: u8,
    /// Vehicle type from the rotor count.
    pub mav_type: MavType,
    /// The autopilot we present ourselves as.
    pub personality: Personality,
}

impl Identity {
    /// Autopilot `system_id`/1 with the vehicle type of `rotors` rotors (docs/mavlink.md §1).
    pub fn autopilot(system_id: u8, rotors: usize) -> Self {
        let mav_type = match rotors {
            4 => MavType::MAV_TYPE_QUADROTOR,
            6 => MavType::MAV_TYPE_HEXAROTOR,
            8 => MavType::MAV_TYPE_OCTOROTOR,
            10 => MavType::MAV_TYPE_DECAROTOR,
            12 => MavType::MAV_TYPE_DODECAROTOR,
            _ => MavType::MAV_TYPE_GENERIC_MULTIROTOR,
        };
        Self {
            system_id,
            component_id: 1,
            mav_type,
            personality: Personality::Px4,
        }
    }

    /// This identity presenting itself as `personality`.
    pub fn with_personality(self, personality: Personality) -> Self {
        Self { personality, ..self }
    }

    /// True when a message addressed to `target_system`/`target_component` from `sender` is ours.
    pub fn accepts(&self, sender: &MavHeader, target_system: u8, target_component: u8) -> bool {
        let from_self = sender.system_id == u32::from(self.system_id) && sender.component_id == self.component_id;
        !from_self
            && (target_system == self.system_id || target_system == 0)
            && (target_component == self.component_id || target_component == 0)
    }
}

/// MAV_RESULT of an outcome.
pub fn result_of(outcome: &Outcome) -> MavResult {
    match outcome {
        Outcome::Accepted => MavResult::MAV_RESULT_ACCEPTED,
        Outcome::TemporarilyRejected(_) => MavResult::MAV_RESULT_TEMPORARILY_REJECTED,
        Outcome::Denied(_) => MavResult::MAV_RESULT_DENIED,
        Outcome::Unsupported(_) => MavResult::MAV_RESULT_COMMAND_UNSUPPORTED_MAV_FRAME,
        Outcome::Failed(_) => MavResult::MAV_RESULT_FAILED,
    }
}

/// COMMAND_ACK for `command` addressed back to `sender` (MAVSDK matches on the target ids).
pub fn command_ack(sender: &MavHeader, command: MavCmd, result: MavResult) -> MavMessage {
    MavMessage::COMMAND_ACK(COMMAND_ACK_DATA {
        command,
        result,
        target_system: sender.system_id as u8,
        target_component: sender.component_id,
        ..Default::default()
    })
}

/// HEARTBEAT for the commander's state (docs/mavlink.md §1): PX4 autopilot, custom mode, armed bit, and
/// the base-mode flags PX4 sends for the mode: manual input for the stick modes (with stabilize
/// but in ACRO, and guided in POSCTL and its orbit), auto | guided | stabilize for the AUTO modes
/// and OFFBOARD.
pub fn heartbeat(id: &Identity, armed: bool, mode: FlightMode) -> MavMessage {
    use MavModeFlag as F;
    let mut base = F::MAV_MODE_FLAG_CUSTOM_MODE_ENABLED;
    base |= match mode {
        FlightMode::Acro => F::MAV_MODE_FLAG_MANUAL_INPUT_ENABLED,
        FlightMode::Manual | FlightMode::Stabilized | FlightMode::Altitude => {
            F::MAV_MODE_FLAG_MANUAL_INPUT_ENABLED | F::MAV_MODE_FLAG_STABILIZE_ENABLED
        }
        FlightMode::Position | FlightMode::Orbit => {
            F::MAV_MODE_FLAG_MANUAL_INPUT_ENABLED | F::MAV_MODE_FLAG_STABILIZE_ENABLED | F::MAV_MODE_FLAG_GUIDED_ENABLED
        }
        _ => F::MAV_MODE_FLAG_AUTO_ENABLED | F::MAV_MODE_FLAG_GUIDED_ENABLED | F::MAV_MODE_FLAG_STABILIZE_ENABLED,
    };
    if armed {
        base |= MavModeFlag::MAV_MODE_FLAG_SAFETY_ARMED;
    }
    MavMessage::HEARTBEAT(HEARTBEAT_DATA {
        custom_mode: mode.custom_mode(),
        mavtype: id.mav_type,
        autopilot: MavAutopilot::MAV_AUTOPILOT_PX4,
        base_mode: base,
        system_status: if armed {
            MavState::MAV_STATE_ACTIVE
        } else {
            MavState::MAV_STATE_STANDBY
        },
        mavlink_version: 3,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mav::gcs::gcs_header;

    #[test]
    fn heartbeat_and_ack_carry_what_clients_read() {
        let id = Identity::autopilot(3, 8);
        let MavMessage::HEARTBEAT(hb) = heartbeat(&id, true, FlightMode::Takeoff) else {
            panic!("not a heartbeat");
        };
        assert_eq!(hb.mavtype, MavType::MAV_TYPE_OCTOROTOR);
        assert_eq!(hb.custom_mode, 33_816_576);
        assert_eq!(hb.base_mode.bits(), 128 | 29);
        let MavMessage::HEARTBEAT(hb) = heartbeat(&id, false, FlightMode::Position) else {
            panic!("not a heartbeat");
        };
        assert_eq!(
            hb.base_mode.bits(),
            64 | 16 | 8 | 1,
            "POSCTL: manual input, stabilize, guided"
        );
        for (mode, bits) in [
            (FlightMode::Acro, 64 | 1),
            (FlightMode::Altitude, 64 | 16 | 1),
            (FlightMode::Orbit, 89),
        ] {
            let MavMessage::HEARTBEAT(hb) = heartbeat(&id, false, mode) else {
                panic!("not a heartbeat");
            };
            assert_eq!(hb.base_mode.bits(), bits, "{mode:?}");
        }
        let MavMessage::COMMAND_ACK(ack) = command_ack(
            &gcs_header(0),
            MavCmd::MAV_CMD_NAV_LAND,
            result_of(&Outcome::Denied("x".into())),
        ) else {
            panic!("not an ack");
        };
        assert_eq!((ack.target_system, ack.target_component), (255, 190));
        assert_eq!(ack.result, MavResult::MAV_RESULT_DENIED);
        assert_eq!(Identity::autopilot(1, 5).mav_type, MavType::MAV_TYPE_GENERIC_MULTIROTOR);
    }
}
