//! MISSION_ITEM_INT of the fence and rally plans → [`Geofence`] / [`RallyPoints`], each refusal
//! with the MAV_MISSION_RESULT PX4 gives (`MavlinkMissionManager::parse_mavlink_mission_item` and
//! the fence check of `handle_mission_item_both`). Pure.
//!
//! Fence: MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION / _EXCLUSION (5001 / 5002), one item per
//! vertex, param1 the polygon's vertex count (rounded; fewer than 3 → ERROR, as PX4; a run that
//! does not hold that many vertices of one kind → INVALID_PARAM1); _CIRCLE_INCLUSION /
//! _EXCLUSION (5003 / 5004), param1 the radius (not negative, else INVALID_PARAM1);
//! MAV_CMD_NAV_FENCE_RETURN_POINT (5000) is kept in the plan and, as in PX4, not used. Rally:
//! MAV_CMD_NAV_RALLY_POINT (5100). Both plans take the global frames only (GLOBAL,
//! GLOBAL_RELATIVE_ALT and their _INT forms; MISSION → UNSUPPORTED, others UNSUPPORTED_FRAME);
//! another command is UNSUPPORTED.

use mavlink::dialects::ardupilotmega::{MavCmd, MavFrame, MavMissionResult, MISSION_ITEM_INT_DATA};

use super::mission_items::ItemError;
use crate::guidance::geofence::{Shape, Zone};
use crate::guidance::{Geofence, Home, RallyPoints};
use crate::math::Vec3;

/// The item's position in local NED [m] when its frame is a global one. Unlike a mission item, a
/// zone may lie anywhere on Earth (PX4 takes MAVSDK's placeholder circle at 0°, 0°): only a
/// latitude beyond ±90° or a longitude beyond ±180° is INVALID_PARAM5_X / _PARAM6_Y; a zone that
/// does not hold home is left out when the fence is checked.
#[allow(deprecated)]
fn global_position(item: &MISSION_ITEM_INT_DATA, home: &Home) -> Result<Vec3, MavMissionResult> {
    let alt_amsl_m = match item.frame {
        MavFrame::MAV_FRAME_GLOBAL | MavFrame::MAV_FRAME_GLOBAL_INT => f64::from(item.z),
        MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT | MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT_INT => {
            home.alt_amsl_m + f64::from(item.z)
        }
        MavFrame::MAV_FRAME_MISSION => return Err(MavMissionResult::MAV_MISSION_UNSUPPORTED),
        _ => return Err(MavMissionResult::MAV_MISSION_UNSUPPORTED_FRAME),
    };
    let (lat, lon) = (f64::from(item.x) * 1e-7, f64::from(item.y) * 1e-7);
    if lat.abs() > 90.0 {
        return Err(MavMissionResult::MAV_MISSION_INVALID_PARAM5_X);
    }
    if lon.abs() > 180.0 {
        return Err(MavMissionResult::MAV_MISSION_INVALID_PARAM6_Y);
    }
    if !alt_amsl_m.is_finite() {
        return Err(MavMissionResult::MAV_MISSION_INVALID_PARAM7);
    }
    Ok(home.to_local(lat, lon, alt_amsl_m))
}

/// Items must come in sequence order.
fn check_sequence(items: &[MISSION_ITEM_INT_DATA]) -> Result<(), ItemError> {
    match items.iter().enumerate().find(|(i, item)| usize::from(item.seq) != *i) {
        Some((_, item)) => Err(ItemError {
            seq: item.seq,
            result: MavMissionResult::MAV_MISSION_INVALID_SEQUENCE,
        }),
        None => Ok(()),
    }
}

/// PX4's vertex count of a polygon item: param1 rounded.
fn vertex_count(item: &MISSION_ITEM_INT_DATA) -> Option<usize> {
    let n = item.param1;
    (n.is_finite() && n >= 0.0).then_some((n + 0.5) as usize)
}

/// Parses an uploaded fence plan (items in sequence order) into zones about `home`.
pub fn parse_fence(items: &[MISSION_ITEM_INT_DATA], home: &Home) -> Result<Geofence, ItemError> {
    use MavMissionResult::*;
    check_sequence(items)?;
    let mut zones = Vec::new();
    let mut i = 0;
    while i < items.len() {
        let item = &items[i];
        let refuse = |result| ItemError { seq: item.seq, result };
        let p = global_position(item, home).map_err(refuse)?;
        match item.command {
            MavCmd::MAV_CMD_NAV_FENCE_RETURN_POINT => i += 1,
            MavCmd::MAV_CMD_NAV_FENCE_CIRCLE_INCLUSION | MavCmd::MAV_CMD_NAV_FENCE_CIRCLE_EXCLUSION => {
                // PX4 takes a zero radius (MAVSDK's placeholder circle); a negative one is refused.
                let radius_m = f64::from(item.param1);
                if !(radius_m.is_finite() && radius_m >= 0.0) {
                    return Err(refuse(MAV_MISSION_INVALID_PARAM1));
                }
                zones.push(Zone {
                    inclusion: item.command == MavCmd::MAV_CMD_NAV_FENCE_CIRCLE_INCLUSION,
                    shape: Shape::Circle {
                        center: [p.x, p.y],
                        radius_m,
                    },
                });
                i += 1;
            }
            MavCmd::MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION | MavCmd::MAV_CMD_NAV_FENCE_POLYGON_VERTEX_EXCLUSION => {
                let n = vertex_count(item).ok_or(refuse(MAV_MISSION_INVALID_PARAM1))?;
                if n < 3 {
                    return Err(refuse(MAV_MISSION_ERROR));
                }
                let mut vertices = Vec::with_capacity(n);
                for k in i..i + n {
                    let Some(v) = items.get(k) else {
                        return Err(refuse(MAV_MISSION_INVALID_PARAM1));
                    };
                    if v.command != item.command || vertex_count(v) != Some(n) {
                        return Err(ItemError {
                            seq: v.seq,
                            result: MAV_MISSION_INVALID_PARAM1,
                        });
                    }
                    let q = global_position(v, home).map_err(|result| ItemError { seq: v.seq, result })?;
                    vertices.push([q.x, q.y]);
                }
                zones.push(Zone {
                    inclusion: item.command == MavCmd::MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION,
                    shape: Shape::Polygon(vertices),
                });
                i += n;
            }
            _ => return Err(refuse(MAV_MISSION_UNSUPPORTED)),
        }
    }
    Ok(Geofence { zones })
}

/// Parses an uploaded rally plan (items in sequence order) into points about `home`.
pub fn parse_rally(items: &[MISSION_ITEM_INT_DATA], home: &Home) -> Result<RallyPoints, ItemError> {
    check_sequence(items)?;
    let mut points_w = Vec::with_capacity(items.len());
    for item in items {
        let refuse = |result| ItemError { seq: item.seq, result };
        let p = global_position(item, home).map_err(refuse)?;
        if item.command != MavCmd::MAV_CMD_NAV_RALLY_POINT {
            return Err(refuse(MavMissionResult::MAV_MISSION_UNSUPPORTED));
        }
        points_w.push(p);
    }
    Ok(RallyPoints {
        points_w,
        ..Default::default()
    })
}

#[cfg(test)]
#[allow(deprecated)]
mod tests {
    use super::*;
    use MavMissionResult::*;

    /// An item `seq` of `command` at (`dlat`, `dlon`) [1e-7°] from home, in QGC's frame
    /// (MAV_FRAME_GLOBAL, z 0) with `param1`.
    fn item(seq: u16, command: MavCmd, dlat: i32, dlon: i32, param1: f32) -> MISSION_ITEM_INT_DATA {
        let home = Home::default();
        MISSION_ITEM_INT_DATA {
            seq,
            command,
            frame: MavFrame::MAV_FRAME_GLOBAL,
            x: (home.lat_deg * 1e7) as i32 + dlat,
            y: (home.lon_deg * 1e7) as i32 + dlon,
            param1,
            ..Default::default()
        }
    }

    fn polygon(first: u16, command: MavCmd, n: u16) -> Vec<MISSION_ITEM_INT_DATA> {
        let corners = [(-900, -1300), (900, -1300), (900, 1300), (-900, 1300), (0, 2000)];
        (0..n)
            .map(|k| {
                let (a, b) = corners[usize::from(k) % corners.len()];
                item(first + k, command, a, b, f32::from(n))
            })
            .collect()
    }

    #[test]
    fn a_qgc_fence_with_a_polygon_a_circle_and_a_return_point_parses() {
        let home = Home::default();
        let mut items = polygon(0, MavCmd::MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION, 4);
        items.push(item(4, MavCmd::MAV_CMD_NAV_FENCE_CIRCLE_EXCLUSION, 450, 0, 3.0));
        let mut ret = item(5, MavCmd::MAV_CMD_NAV_FENCE_RETURN_POINT, 0, 0, 0.0);
        ret.frame = MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT;
        items.push(ret);
        let fence = parse_fence(&items, &home).unwrap();
        assert_eq!(fence.zones.len(), 2);
        assert!(fence.zones[0].inclusion && !fence.zones[1].inclusion);
        // 900e-7° north ≈ 10 m, 1300e-7° east ≈ 9.8 m.
        let Shape::Polygon(v) = &fence.zones[0].shape else {
            panic!("not a polygon")
        };
        assert!(
            (v[2][0] - 10.0).abs() < 0.01 && (v[2][1] - 9.79).abs() < 0.01,
            "{:?}",
            v[2]
        );
        assert!(fence.contains(&Vec3::new(0.0, 0.0, -3.0)));
        assert!(!fence.contains(&Vec3::new(5.0, 0.0, -3.0)), "in the keep-out circle");
        assert!(!fence.contains(&Vec3::new(0.0, 12.0, -3.0)), "outside the polygon");
        assert!(parse_fence(&[], &home).unwrap().is_empty());
    }

    #[test]
    fn bad_fence_items_are_refused_as_px4_refuses_them() {
        let home = Home::default();
        let bad = |items: &[MISSION_ITEM_INT_DATA]| parse_fence(items, &home).map(|_| ()).unwrap_err();
        let incl = MavCmd::MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION;
        let e = bad(&polygon(0, incl, 2));
        assert_eq!((e.seq, e.result), (0, MAV_MISSION_ERROR), "fewer than 3 vertices");
        let mut short = polygon(0, incl, 4);
        short.pop();
        assert_eq!(
            bad(&short).result,
            MAV_MISSION_INVALID_PARAM1,
            "the plan ends mid-polygon"
        );
        let mut mixed = polygon(0, incl, 3);
        mixed[2].command = MavCmd::MAV_CMD_NAV_FENCE_POLYGON_VERTEX_EXCLUSION;
        assert_eq!((bad(&mixed).seq, bad(&mixed).result), (2, MAV_MISSION_INVALID_PARAM1));
        let mut miscounted = polygon(0, incl, 3);
        miscounted[1].param1 = 4.0;
        assert_eq!(bad(&miscounted).seq, 1);
        let circle = |r| item(0, MavCmd::MAV_CMD_NAV_FENCE_CIRCLE_INCLUSION, 0, 0, r);
        assert_eq!(bad(&[circle(-1.0)]).result, MAV_MISSION_INVALID_PARAM1);
        assert_eq!(bad(&[circle(f32::NAN)]).result, MAV_MISSION_INVALID_PARAM1);
        // MAVSDK's placeholder circle (0°, 0°, radius 0) is taken, as PX4 takes it.
        let mut placeholder = circle(0.0);
        (placeholder.x, placeholder.y) = (0, 0);
        assert!(parse_fence(&[placeholder], &home).is_ok());
        let mut off_earth = circle(5.0);
        off_earth.x = 910_000_000;
        assert_eq!(bad(&[off_earth]).result, MAV_MISSION_INVALID_PARAM5_X);
        let mut local = circle(5.0);
        local.frame = MavFrame::MAV_FRAME_LOCAL_NED;
        assert_eq!(bad(&[local]).result, MAV_MISSION_UNSUPPORTED_FRAME);
        let mut no_position = circle(5.0);
        no_position.frame = MavFrame::MAV_FRAME_MISSION;
        assert_eq!(bad(&[no_position]).result, MAV_MISSION_UNSUPPORTED);
        let e = bad(&[circle(5.0), item(1, MavCmd::MAV_CMD_NAV_WAYPOINT, 0, 0, 0.0)]);
        assert_eq!((e.seq, e.result), (1, MAV_MISSION_UNSUPPORTED));
        assert_eq!(bad(&[circle(5.0), circle(5.0)]).result, MAV_MISSION_INVALID_SEQUENCE);
    }

    #[test]
    fn rally_points_parse_in_both_altitude_frames_and_nothing_else() {
        let home = Home::default();
        let mut a = item(0, MavCmd::MAV_CMD_NAV_RALLY_POINT, 4500, 0, 0.0);
        a.frame = MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT_INT;
        a.z = 15.0;
        let mut b = item(1, MavCmd::MAV_CMD_NAV_RALLY_POINT, 0, -2000, 0.0);
        b.z = 500.0;
        let rally = parse_rally(&[a.clone(), b], &home).unwrap();
        assert!(
            (rally.points_w[0] - Vec3::new(50.04, 0.0, -15.0)).norm() < 0.01,
            "{:?}",
            rally.points_w[0]
        );
        assert!(
            (rally.points_w[1].z + 12.0).abs() < 1e-3,
            "500 m AMSL is 12 m above home"
        );
        let e = parse_rally(&[item(0, MavCmd::MAV_CMD_NAV_WAYPOINT, 0, 0, 0.0)], &home).unwrap_err();
        assert_eq!(e.result, MAV_MISSION_UNSUPPORTED);
        a.frame = MavFrame::MAV_FRAME_BODY_FRD;
        assert_eq!(
            parse_rally(&[a], &home).unwrap_err().result,
            MAV_MISSION_UNSUPPORTED_FRAME
        );
    }
}
