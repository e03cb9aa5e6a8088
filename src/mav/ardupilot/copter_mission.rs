//! The mission plan as ArduCopter numbers and sends it (docs/ardupilot.md §6): slot 0 of the
//! mission is home, the flown items start at 1; uploads may arrive as MISSION_ITEM (float
//! degrees, DroneKit) and downloads answer in the form asked for. The shared protocol types
//! ([`MissionTransfer`](crate::mav::mission_xfer::MissionTransfer),
//! [`PlanStore`](crate::mav::plan_store::PlanStore),
//! [`MissionReport`](crate::mav::mission_report::MissionReport), the link's plan service) call
//! these for a vehicle presented as ArduCopter, for the mission plan only (fence and rally keep
//! no home slot). Pure.
#![allow(deprecated)] // MISSION_ITEM: what DroneKit uploads and downloads

use mavlink::dialects::ardupilotmega::{MavCmd, MavFrame, MISSION_ITEM_DATA, MISSION_ITEM_INT_DATA};

use crate::guidance::Home;

/// How long an upload waits for the item it asked for before asking again [s] (ArduPilot
/// re-sends its MISSION_REQUEST after a second without the item).
pub const COPTER_RETRY_S: f64 = 1.0;
/// What ArduCopter says when a mission upload was stored, before its MISSION_ACK.
pub const PLAN_RECEIVED: &str = "Flight plan received";
/// Why ArduCopter refuses AUTO armed on the ground when the mission does not start with a
/// take-off (said as a critical STATUSTEXT).
pub const MISSING_TAKEOFF: &str = "Auto: Missing Takeoff Cmd";
/// ArduCopter's mode number of AUTO.
pub const AUTO: u32 = 3;

/// Highest MAV_CMD id that is a navigation command (MAV_CMD_NAV_LAST): the ids above it are
/// conditions and DO commands, which a mission runs between its navigation items.
const NAV_LAST: u32 = 95;

/// The mission's item 0 as a download reports it: the vehicle's `home` as a NAV_WAYPOINT in
/// MAV_FRAME_GLOBAL (latitude and longitude in degE7, altitude AMSL [m]).
pub fn home_item(home: &Home) -> MISSION_ITEM_INT_DATA {
    MISSION_ITEM_INT_DATA {
        seq: 0,
        command: MavCmd::MAV_CMD_NAV_WAYPOINT,
        frame: MavFrame::MAV_FRAME_GLOBAL,
        x: (home.lat_deg * 1e7).round() as i32,
        y: (home.lon_deg * 1e7).round() as i32,
        z: home.alt_amsl_m as f32,
        autocontinue: 1,
        ..Default::default()
    }
}

/// A MISSION_ITEM (latitude and longitude in float degrees in x and y) in the MISSION_ITEM_INT
/// form the plan stores: x and y in degE7, rounded (a value that is no number becomes 0, one
/// out of range saturates: the item's check refuses it as far from home).
pub fn item_int(m: &MISSION_ITEM_DATA) -> MISSION_ITEM_INT_DATA {
    let e7 = |deg: f32| (f64::from(deg) * 1e7).round() as i32;
    MISSION_ITEM_INT_DATA {
        param1: m.param1,
        param2: m.param2,
        param3: m.param3,
        param4: m.param4,
        x: e7(m.x),
        y: e7(m.y),
        z: m.z,
        seq: m.seq,
        command: m.command,
        target_system: m.target_system,
        target_component: m.target_component,
        frame: m.frame,
        current: m.current,
        autocontinue: m.autocontinue,
        mission_type: m.mission_type,
    }
}

/// A stored item as a MISSION_ITEM (what answers a MISSION_REQUEST): x and y in float degrees.
pub fn item_float(m: &MISSION_ITEM_INT_DATA) -> MISSION_ITEM_DATA {
    let deg = |e7: i32| (f64::from(e7) * 1e-7) as f32;
    MISSION_ITEM_DATA {
        param1: m.param1,
        param2: m.param2,
        param3: m.param3,
        param4: m.param4,
        x: deg(m.x),
        y: deg(m.y),
        z: m.z,
        seq: m.seq,
        command: m.command,
        target_system: m.target_system,
        target_component: m.target_component,
        frame: m.frame,
        current: m.current,
        autocontinue: m.autocontinue,
        mission_type: m.mission_type,
    }
}

/// The seq the link reports for the commander's mission item `index` (item 0 is home).
pub fn link_seq(index: u16) -> u16 {
    index.saturating_add(1)
}

/// The commander's mission item a seq from a ground station names (MISSION_SET_CURRENT,
/// DO_SET_MISSION_CURRENT, MISSION_START): seq − 1, and the home slot 0 names the first item.
pub fn commander_index(seq: usize) -> usize {
    seq.saturating_sub(1)
}

/// The `current` flag of a downloaded mission item of `command` while the mission is at
/// navigation item `nav_seq` (`None` before it started), as ArduCopter sets it: its download
/// compares the item's command id with that seq (`MissionItemProtocol_Waypoints::get_item`), so
/// the flag is 1 on every item whose MAV_CMD number is the seq, not on the current item.
pub fn current_flag(command: MavCmd, nav_seq: Option<u16>) -> u8 {
    u8::from(nav_seq.is_some_and(|seq| u32::from(seq) == command as u32))
}

/// The items the commander flies from an upload as ArduCopter numbers it: items 1.. renumbered
/// from 0, each DO_JUMP's target (p1, an uploaded seq) moved along with them (a jump to the
/// home slot becomes −1, which the item's check refuses). Item 0 is stored, never flown.
pub fn flown_items(uploaded: &[MISSION_ITEM_INT_DATA]) -> Vec<MISSION_ITEM_INT_DATA> {
    uploaded
        .iter()
        .skip(1)
        .map(|item| {
            let mut flown = item.clone();
            flown.seq = item.seq.wrapping_sub(1);
            if item.command == MavCmd::MAV_CMD_DO_JUMP {
                flown.param1 = item.param1 - 1.0;
            }
            flown
        })
        .collect()
}

/// Whether AUTO may start armed on the ground with the mission `uploaded` (ArduCopter's
/// `starts_with_takeoff_cmd`): the first navigation item from seq 1 on, passing over
/// conditions, DO commands and NAV_DELAY, is a take-off (looking at 16 items at most).
pub fn starts_with_takeoff(uploaded: &[MISSION_ITEM_INT_DATA]) -> bool {
    let nav = uploaded.iter().skip(1).filter(|i| i.command as u32 <= NAV_LAST);
    for item in nav.take(16) {
        match item.command {
            MavCmd::MAV_CMD_NAV_TAKEOFF => return true,
            MavCmd::MAV_CMD_NAV_DELAY => continue,
            _ => return false,
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;

    fn item(seq: u16, command: MavCmd) -> MISSION_ITEM_INT_DATA {
        MISSION_ITEM_INT_DATA {
            seq,
            command,
            ..Default::default()
        }
    }

    #[test]
    fn home_is_a_global_waypoint_at_home() {
        let home = Home::default();
        let h = home_item(&home);
        assert_eq!(
            (h.seq, h.command, h.frame),
            (0, MavCmd::MAV_CMD_NAV_WAYPOINT, MavFrame::MAV_FRAME_GLOBAL)
        );
        assert_eq!((h.x, h.y, h.z), (473_977_420, 85_455_940, 488.0));
    }

    #[test]
    fn float_degrees_round_to_deg_e7_and_back() {
        let m = MISSION_ITEM_DATA {
            x: 47.397_743,
            y: 8.545_594,
            z: 12.5,
            seq: 3,
            command: MavCmd::MAV_CMD_NAV_WAYPOINT,
            frame: MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT,
            autocontinue: 1,
            param1: 2.0,
            ..Default::default()
        };
        let i = item_int(&m);
        assert_eq!(i.x, (f64::from(47.397_743f32) * 1e7).round() as i32);
        assert!((i.x - 473_977_430).abs() <= 20, "{}", i.x);
        assert_eq!((i.seq, i.z, i.param1, i.frame), (3, 12.5, 2.0, m.frame));
        let back = item_float(&i);
        assert_eq!((back.x, back.y, back.z, back.seq), (m.x, m.y, m.z, 3));
        let nan = item_int(&MISSION_ITEM_DATA {
            x: f32::NAN,
            ..Default::default()
        });
        assert_eq!(nan.x, 0);
    }

    #[test]
    fn the_commander_flies_items_1_on_and_seqs_shift_by_one() {
        let mut jump = item(3, MavCmd::MAV_CMD_DO_JUMP);
        jump.param1 = 2.0;
        jump.param2 = 1.0;
        let uploaded = [
            item(0, MavCmd::MAV_CMD_NAV_WAYPOINT),
            item(1, MavCmd::MAV_CMD_NAV_TAKEOFF),
            item(2, MavCmd::MAV_CMD_NAV_WAYPOINT),
            jump,
        ];
        let flown = flown_items(&uploaded);
        let seqs: Vec<(u16, MavCmd)> = flown.iter().map(|i| (i.seq, i.command)).collect();
        assert_eq!(
            seqs,
            [
                (0, MavCmd::MAV_CMD_NAV_TAKEOFF),
                (1, MavCmd::MAV_CMD_NAV_WAYPOINT),
                (2, MavCmd::MAV_CMD_DO_JUMP)
            ]
        );
        assert_eq!(
            (flown[2].param1, flown[2].param2),
            (1.0, 1.0),
            "jumps to the same waypoint"
        );
        assert!(flown_items(&uploaded[..1]).is_empty(), "home only: nothing to fly");
        assert_eq!((link_seq(0), link_seq(4)), (1, 5));
        assert_eq!((commander_index(0), commander_index(1), commander_index(5)), (0, 0, 4));
    }

    #[test]
    fn the_current_flag_compares_the_command_id_with_the_current_seq_as_copter_does() {
        assert_eq!(current_flag(MavCmd::MAV_CMD_NAV_WAYPOINT, Some(1)), 0);
        assert_eq!(current_flag(MavCmd::MAV_CMD_NAV_WAYPOINT, Some(16)), 1);
        assert_eq!(current_flag(MavCmd::MAV_CMD_NAV_TAKEOFF, Some(22)), 1);
        assert_eq!(current_flag(MavCmd::MAV_CMD_NAV_TAKEOFF, Some(16)), 0);
        assert_eq!(current_flag(MavCmd::MAV_CMD_NAV_WAYPOINT, None), 0);
    }

    #[test]
    fn auto_needs_a_takeoff_first_past_do_commands_and_delays() {
        let home = item(0, MavCmd::MAV_CMD_NAV_TAKEOFF);
        let takeoff = item(1, MavCmd::MAV_CMD_NAV_TAKEOFF);
        let wp = item(1, MavCmd::MAV_CMD_NAV_WAYPOINT);
        let speed = item(1, MavCmd::MAV_CMD_DO_CHANGE_SPEED);
        let delay = item(1, MavCmd::MAV_CMD_NAV_DELAY);
        assert!(starts_with_takeoff(&[home.clone(), takeoff.clone()]));
        assert!(starts_with_takeoff(&[
            home.clone(),
            speed.clone(),
            delay,
            takeoff.clone()
        ]));
        assert!(!starts_with_takeoff(&[home.clone(), wp.clone(), takeoff]));
        assert!(!starts_with_takeoff(&[home.clone(), speed]));
        assert!(!starts_with_takeoff(&[home]), "item 0 is never flown");
        assert!(!starts_with_takeoff(&[]));
    }
}
