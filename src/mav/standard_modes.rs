//! What QGroundControl asks right after AUTOPILOT_VERSION, answered as PX4 answers it:
//! PROTOCOL_VERSION (300; unanswered, QGC falls back to MAVLink 1 and skips geofence and rally),
//! and the standard modes protocol: AVAILABLE_MODES (435) for one mode or all of them, and
//! CURRENT_MODE (436), streamed and on request. The set of modes never changes here, so there is
//! never an AVAILABLE_MODES_MONITOR to send (PX4 sends one only after a change). Pure.

#[allow(deprecated)]
use mavlink::dialects::ardupilotmega::PROTOCOL_VERSION_DATA;
use mavlink::dialects::ardupilotmega::{
    MavMessage, MavModeProperty, MavStandardMode, AVAILABLE_MODES_DATA, CURRENT_MODE_DATA,
};

use crate::commander::FlightMode;

/// PROTOCOL_VERSION: MAVLink 2 (200), the oldest and newest spoken, 100 and 200; no hashes.
/// The message is deprecated in the MAVLink definitions since 2025-11, but QGroundControl still
/// asks for it and falls back to MAVLink 1 without it.
#[allow(deprecated)]
pub fn protocol_version() -> MavMessage {
    MavMessage::PROTOCOL_VERSION(PROTOCOL_VERSION_DATA {
        version: 200,
        min_version: 100,
        max_version: 200,
        spec_version_hash: [0; 8],
        library_version_hash: [0; 8],
    })
}

/// MAV_STANDARD_MODE of `mode`.
fn standard(mode: FlightMode) -> MavStandardMode {
    match mode.standard_mode() {
        Some(1) => MavStandardMode::MAV_STANDARD_MODE_POSITION_HOLD,
        Some(2) => MavStandardMode::MAV_STANDARD_MODE_ORBIT,
        Some(4) => MavStandardMode::MAV_STANDARD_MODE_ALTITUDE_HOLD,
        Some(5) => MavStandardMode::MAV_STANDARD_MODE_SAFE_RECOVERY,
        Some(6) => MavStandardMode::MAV_STANDARD_MODE_MISSION,
        Some(7) => MavStandardMode::MAV_STANDARD_MODE_LAND,
        Some(8) => MavStandardMode::MAV_STANDARD_MODE_TAKEOFF,
        _ => MavStandardMode::MAV_STANDARD_MODE_NON_STANDARD,
    }
}

/// AVAILABLE_MODES for `index` (1-based, in [`FlightMode::selectable`] order), or for every mode
/// when `index` is 0; `None` for an index beyond the last mode. As PX4 does, only a
/// non-standard mode carries its name, and every mode but position and altitude is marked
/// advanced.
pub fn available_modes(index: u8) -> Option<Vec<MavMessage>> {
    let modes = FlightMode::selectable();
    let number_modes = modes.len() as u8;
    let one = |k: usize, mode: FlightMode| {
        let standard_mode = standard(mode);
        let mode_name = if standard_mode == MavStandardMode::MAV_STANDARD_MODE_NON_STANDARD {
            mode.ui_name().into()
        } else {
            "".into()
        };
        let properties = if matches!(mode, FlightMode::Position | FlightMode::Altitude) {
            MavModeProperty::empty()
        } else {
            MavModeProperty::MAV_MODE_PROPERTY_ADVANCED
        };
        MavMessage::AVAILABLE_MODES(AVAILABLE_MODES_DATA {
            custom_mode: mode.custom_mode(),
            properties,
            number_modes,
            mode_index: k as u8 + 1,
            standard_mode,
            mode_name,
        })
    };
    match index {
        0 => Some(modes.iter().enumerate().map(|(k, m)| one(k, *m)).collect()),
        i => modes.get(usize::from(i) - 1).map(|m| vec![one(usize::from(i) - 1, *m)]),
    }
}

/// CURRENT_MODE while flying `mode`; the mode asked for is the mode flown (a failsafe here
/// changes the mode itself, it does not override an intention).
pub fn current_mode(mode: FlightMode) -> MavMessage {
    MavMessage::CURRENT_MODE(CURRENT_MODE_DATA {
        custom_mode: mode.custom_mode(),
        intended_custom_mode: mode.custom_mode(),
        standard_mode: standard(mode),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_selectable_mode_is_listed_once_in_order_with_names_only_for_non_standard_ones() {
        let all = available_modes(0).unwrap();
        assert_eq!(all.len(), 13);
        let mut seen = Vec::new();
        for (k, msg) in all.iter().enumerate() {
            let MavMessage::AVAILABLE_MODES(m) = msg else {
                panic!("{msg:?}")
            };
            assert_eq!((m.mode_index, m.number_modes), (k as u8 + 1, 13));
            let name = m.mode_name.to_str().unwrap().to_string();
            let mode = FlightMode::from_custom_mode(m.custom_mode).unwrap();
            assert_eq!(
                name.is_empty(),
                m.standard_mode != MavStandardMode::MAV_STANDARD_MODE_NON_STANDARD
            );
            seen.push((mode, name));
        }
        assert_eq!(
            seen[1],
            (FlightMode::Altitude, String::new()),
            "altitude hold is standard"
        );
        assert_eq!(seen[4], (FlightMode::Loiter, "Hold".to_string()));
        assert_eq!(seen[7], (FlightMode::Offboard, "Offboard".to_string()));
        assert_eq!(seen[8], (FlightMode::Stabilized, "Stabilized".to_string()));
        assert_eq!(available_modes(3), Some(vec![all[2].clone()]));
        assert_eq!(available_modes(14), None);
    }

    #[test]
    #[allow(deprecated)]
    fn the_current_mode_names_its_standard_mode() {
        let MavMessage::CURRENT_MODE(m) = current_mode(FlightMode::ReturnToLaunch) else {
            panic!()
        };
        assert_eq!(m.custom_mode, FlightMode::ReturnToLaunch.custom_mode());
        assert_eq!(m.standard_mode, MavStandardMode::MAV_STANDARD_MODE_SAFE_RECOVERY);
        let MavMessage::PROTOCOL_VERSION(v) = protocol_version() else {
            panic!()
        };
        assert_eq!((v.version, v.min_version, v.max_version), (200, 100, 200));
    }
}
