//! Fence and rally plans as ArduCopter takes and stores them (docs/ardupilot.md §6.1): the
//! items it accepts, the checks its fence loader makes once the upload is complete (each a
//! MISSION_ACK ERROR with a warning naming why, `AC_PolyFence_loader::validate_fence`), and the
//! form a download returns (fence items without altitude, rally points at whole metres above
//! home). The shared parsers ([`parse_fence`](crate::mav::plan_items::parse_fence),
//! [`parse_rally`](crate::mav::plan_items::parse_rally)) then build the zones and points from
//! the stored form. Pure.
#![allow(deprecated)] // MAV_FRAME_GLOBAL_RELATIVE_ALT: what ArduPilot stores rally points in

use mavlink::dialects::ardupilotmega::{MavCmd, MavFrame, MavMissionResult, MISSION_ITEM_INT_DATA};

use crate::mav::mission_items::ItemError;

/// What ArduCopter says when a rally upload was stored, before its MISSION_ACK.
pub const RALLY_RECEIVED: &str = "Rally points received";
/// What ArduCopter says after the reason a fence upload was refused.
pub const FENCE_INVALID: &str = "Fence validation failed";

/// Why a fence or rally upload was refused: the item and MISSION_ACK result, and the warning
/// ArduCopter sends first (none for a refusal of one item's frame or command).
#[derive(Debug, Clone, PartialEq)]
pub struct PlanRefusal {
    /// The refused item and the result.
    pub error: ItemError,
    /// The warning, if ArduCopter sends one.
    pub text: Option<String>,
}

fn refuse(seq: u16, result: MavMissionResult) -> PlanRefusal {
    PlanRefusal {
        error: ItemError { seq, result },
        text: None,
    }
}

fn invalid(seq: u16, why: String) -> PlanRefusal {
    PlanRefusal {
        error: ItemError {
            seq,
            result: MavMissionResult::MAV_MISSION_ERROR,
        },
        text: Some(why),
    }
}

/// A latitude and longitude [degE7] on Earth (ArduPilot's `check_latlng`).
fn on_earth(x: i32, y: i32) -> bool {
    x.unsigned_abs() <= 900_000_000 && y.unsigned_abs() <= 1_800_000_000
}

/// The kinds of fence item ArduCopter stores.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum FenceKind {
    Vertex(bool),
    Circle,
    Return,
}

/// Checks a fence upload as ArduCopter does: each item in a global frame (terrain frames
/// included; UNSUPPORTED_FRAME otherwise) and a fence command (UNSUPPORTED otherwise); then, as
/// one plan, polygons of at least 3 vertices whose items agree on kind and count, circles of a
/// positive radius outside polygons, one return point at most and every position on Earth
/// (MAV_MISSION_ERROR with a warning).
pub fn check_fence(items: &[MISSION_ITEM_INT_DATA]) -> Result<(), PlanRefusal> {
    use MavCmd::*;
    let mut kinds = Vec::with_capacity(items.len());
    for item in items {
        let global = matches!(
            item.frame,
            MavFrame::MAV_FRAME_GLOBAL
                | MavFrame::MAV_FRAME_GLOBAL_INT
                | MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT
                | MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT_INT
                | MavFrame::MAV_FRAME_GLOBAL_TERRAIN_ALT
                | MavFrame::MAV_FRAME_GLOBAL_TERRAIN_ALT_INT
        );
        if !global {
            return Err(refuse(item.seq, MavMissionResult::MAV_MISSION_UNSUPPORTED_FRAME));
        }
        kinds.push(match item.command {
            MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION => FenceKind::Vertex(true),
            MAV_CMD_NAV_FENCE_POLYGON_VERTEX_EXCLUSION => FenceKind::Vertex(false),
            MAV_CMD_NAV_FENCE_CIRCLE_INCLUSION | MAV_CMD_NAV_FENCE_CIRCLE_EXCLUSION => FenceKind::Circle,
            MAV_CMD_NAV_FENCE_RETURN_POINT => FenceKind::Return,
            _ => return Err(refuse(item.seq, MavMissionResult::MAV_MISSION_UNSUPPORTED)),
        });
    }
    // (kind, count, vertices still expected) of the polygon being read.
    let mut polygon: Option<(bool, u32, u32)> = None;
    let mut returns = 0;
    for (item, kind) in items.iter().zip(kinds) {
        match kind {
            FenceKind::Vertex(inclusion) => {
                // ArduCopter keeps the count as a byte: param1 cut to an integer.
                let n = item.param1.clamp(0.0, 255.0) as u32;
                if n < 3 {
                    return Err(invalid(item.seq, format!("Invalid vertex count ({n})")));
                }
                let (kind, count, left) = polygon.unwrap_or((inclusion, n, n));
                if kind != inclusion {
                    return Err(invalid(item.seq, "Received incorrect vertex type".into()));
                }
                if n != count {
                    return Err(invalid(
                        item.seq,
                        format!("Unexpected vertex count want={count} got={n}"),
                    ));
                }
                polygon = (left > 1).then_some((kind, count, left - 1));
            }
            _ if polygon.is_some() => return Err(invalid(item.seq, "Received incorrect type".into())),
            FenceKind::Circle if !(item.param1.is_finite() && item.param1 > 0.0) => {
                return Err(invalid(item.seq, "Non-positive circle radius".into()));
            }
            FenceKind::Return if returns > 0 => return Err(invalid(item.seq, "Multiple return points".into())),
            FenceKind::Return => returns += 1,
            FenceKind::Circle => {}
        }
        if !on_earth(item.x, item.y) {
            return Err(invalid(item.seq, "Bad lat or lon".into()));
        }
    }
    match (polygon, items.last()) {
        (Some(_), Some(last)) => Err(invalid(last.seq, "Incorrect item count".into())),
        _ => Ok(()),
    }
}

/// A checked fence upload as ArduCopter stores and returns it: the command, the vertex count or
/// radius (p1) and the position only, in MAV_FRAME_GLOBAL at altitude 0 (a fence has no
/// height; `FENCE_ALT_MAX` limits it).
pub fn stored_fence(items: &[MISSION_ITEM_INT_DATA]) -> Vec<MISSION_ITEM_INT_DATA> {
    items
        .iter()
        .map(|item| MISSION_ITEM_INT_DATA {
            seq: item.seq,
            command: item.command,
            param1: match item.command {
                MavCmd::MAV_CMD_NAV_FENCE_RETURN_POINT => 0.0,
                _ => item.param1,
            },
            x: item.x,
            y: item.y,
            frame: MavFrame::MAV_FRAME_GLOBAL,
            mission_type: item.mission_type,
            ..Default::default()
        })
        .collect()
}

/// Checks a rally upload as ArduCopter does, item by item: MAV_CMD_NAV_RALLY_POINT
/// (UNSUPPORTED otherwise) in a frame relative to home (UNSUPPORTED_FRAME otherwise: Copter
/// keeps heights above home), on Earth (INVALID_PARAM5_X / _PARAM6_Y), its height within what
/// an int16 of metres holds (INVALID_PARAM7).
pub fn check_rally(items: &[MISSION_ITEM_INT_DATA]) -> Result<(), PlanRefusal> {
    use MavMissionResult::*;
    for item in items {
        if item.command != MavCmd::MAV_CMD_NAV_RALLY_POINT {
            return Err(refuse(item.seq, MAV_MISSION_UNSUPPORTED));
        }
        let relative = matches!(
            item.frame,
            MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT | MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT_INT
        );
        if !relative {
            return Err(refuse(item.seq, MAV_MISSION_UNSUPPORTED_FRAME));
        }
        if item.x.unsigned_abs() > 900_000_000 {
            return Err(refuse(item.seq, MAV_MISSION_INVALID_PARAM5_X));
        }
        if item.y.unsigned_abs() > 1_800_000_000 {
            return Err(refuse(item.seq, MAV_MISSION_INVALID_PARAM6_Y));
        }
        if !(item.z.is_finite() && (f32::from(i16::MIN)..=f32::from(i16::MAX)).contains(&item.z)) {
            return Err(refuse(item.seq, MAV_MISSION_INVALID_PARAM7));
        }
    }
    Ok(())
}

/// A checked rally upload as ArduCopter stores and returns it: the position, and the height
/// above home in whole metres (cut towards zero), in MAV_FRAME_GLOBAL_RELATIVE_ALT.
pub fn stored_rally(items: &[MISSION_ITEM_INT_DATA]) -> Vec<MISSION_ITEM_INT_DATA> {
    items
        .iter()
        .map(|item| MISSION_ITEM_INT_DATA {
            seq: item.seq,
            command: MavCmd::MAV_CMD_NAV_RALLY_POINT,
            x: item.x,
            y: item.y,
            z: item.z.trunc(),
            frame: MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT,
            mission_type: item.mission_type,
            ..Default::default()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use MavMissionResult::*;

    const LAT: i32 = 473_977_420;
    const LON: i32 = 85_455_940;

    fn item(seq: u16, command: MavCmd, param1: f32) -> MISSION_ITEM_INT_DATA {
        MISSION_ITEM_INT_DATA {
            seq,
            command,
            frame: MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT_INT,
            x: LAT + i32::from(seq) * 100,
            y: LON,
            z: 12.7,
            param1,
            param2: 3.0,
            ..Default::default()
        }
    }

    fn polygon(first: u16, inclusion: bool, n: u16) -> Vec<MISSION_ITEM_INT_DATA> {
        let command = if inclusion {
            MavCmd::MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION
        } else {
            MavCmd::MAV_CMD_NAV_FENCE_POLYGON_VERTEX_EXCLUSION
        };
        (first..first + n).map(|s| item(s, command, f32::from(n))).collect()
    }

    fn refused(items: &[MISSION_ITEM_INT_DATA]) -> (u16, MavMissionResult, Option<String>) {
        let e = check_fence(items).unwrap_err();
        (e.error.seq, e.error.result, e.text)
    }

    #[test]
    fn a_fence_of_polygons_circles_and_a_return_point_is_taken_and_stored_without_height() {
        let mut items = polygon(0, true, 4);
        items.extend(polygon(4, false, 3));
        items.push(item(7, MavCmd::MAV_CMD_NAV_FENCE_CIRCLE_EXCLUSION, 5.5));
        items.push(item(8, MavCmd::MAV_CMD_NAV_FENCE_RETURN_POINT, 9.0));
        items[2].frame = MavFrame::MAV_FRAME_GLOBAL_TERRAIN_ALT;
        assert_eq!(check_fence(&items), Ok(()));
        let stored = stored_fence(&items);
        assert!(stored
            .iter()
            .all(|i| i.frame == MavFrame::MAV_FRAME_GLOBAL && i.z == 0.0));
        assert_eq!((stored[0].param1, stored[0].param2), (4.0, 0.0));
        assert_eq!((stored[7].param1, stored[8].param1), (5.5, 0.0));
        assert_eq!((stored[3].x, stored[3].y), (LAT + 300, LON));
        assert_eq!(check_fence(&[]), Ok(()));
    }

    #[test]
    fn malformed_fences_are_refused_as_arducopter_refuses_them() {
        let short = polygon(0, true, 2);
        assert_eq!(
            refused(&short),
            (0, MAV_MISSION_ERROR, Some("Invalid vertex count (2)".into()))
        );
        let mut cut = polygon(0, true, 4);
        cut.pop();
        assert_eq!(
            refused(&cut),
            (2, MAV_MISSION_ERROR, Some("Incorrect item count".into()))
        );
        let mut mixed = polygon(0, true, 3);
        mixed[1].command = MavCmd::MAV_CMD_NAV_FENCE_POLYGON_VERTEX_EXCLUSION;
        assert_eq!(refused(&mixed).0, 1);
        let mut miscounted = polygon(0, true, 3);
        miscounted[2].param1 = 4.0;
        assert_eq!(
            refused(&miscounted).2.as_deref(),
            Some("Unexpected vertex count want=3 got=4")
        );
        let mut interrupted = polygon(0, true, 3);
        interrupted[1] = item(1, MavCmd::MAV_CMD_NAV_FENCE_CIRCLE_INCLUSION, 5.0);
        assert_eq!(refused(&interrupted).2.as_deref(), Some("Received incorrect type"));
        let zero = item(0, MavCmd::MAV_CMD_NAV_FENCE_CIRCLE_INCLUSION, 0.0);
        assert_eq!(refused(&[zero]).2.as_deref(), Some("Non-positive circle radius"));
        let ret = |s| item(s, MavCmd::MAV_CMD_NAV_FENCE_RETURN_POINT, 0.0);
        assert_eq!(refused(&[ret(0), ret(1)]).0, 1);
        let mut off = item(0, MavCmd::MAV_CMD_NAV_FENCE_CIRCLE_INCLUSION, 5.0);
        off.x = 910_000_000;
        assert_eq!(refused(&[off]).2.as_deref(), Some("Bad lat or lon"));
        let mut local = item(0, MavCmd::MAV_CMD_NAV_FENCE_CIRCLE_INCLUSION, 5.0);
        local.frame = MavFrame::MAV_FRAME_MISSION;
        assert_eq!(refused(&[local]), (0, MAV_MISSION_UNSUPPORTED_FRAME, None));
        let wp = item(0, MavCmd::MAV_CMD_NAV_WAYPOINT, 0.0);
        assert_eq!(refused(&[wp]), (0, MAV_MISSION_UNSUPPORTED, None));
    }

    #[test]
    fn rally_points_are_relative_whole_metres_and_nothing_else() {
        let mut a = item(0, MavCmd::MAV_CMD_NAV_RALLY_POINT, 0.0);
        a.frame = MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT;
        let b = item(1, MavCmd::MAV_CMD_NAV_RALLY_POINT, 0.0);
        assert_eq!(check_rally(&[a.clone(), b.clone()]), Ok(()));
        let stored = stored_rally(&[a.clone(), b]);
        assert_eq!(
            (stored[1].z, stored[1].frame),
            (12.0, MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT)
        );
        let bad = |m: MISSION_ITEM_INT_DATA| check_rally(&[m]).unwrap_err().error.result;
        let mut amsl = a.clone();
        amsl.frame = MavFrame::MAV_FRAME_GLOBAL_INT;
        assert_eq!(bad(amsl), MAV_MISSION_UNSUPPORTED_FRAME);
        assert_eq!(bad(item(0, MavCmd::MAV_CMD_NAV_WAYPOINT, 0.0)), MAV_MISSION_UNSUPPORTED);
        let mut high = a.clone();
        high.z = 40_000.0;
        assert_eq!(bad(high), MAV_MISSION_INVALID_PARAM7);
        let mut off = a;
        off.y = -1_800_000_001;
        assert_eq!(bad(off), MAV_MISSION_INVALID_PARAM6_Y);
    }
}
