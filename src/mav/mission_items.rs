//! MISSION_ITEM_INT ↔ [`MissionItem`] (docs/mavlink.md §7): supported commands and frames, values
//! checked, each refusal with the MAV_MISSION_RESULT a client expects. Pure.

use mavlink::dialects::ardupilotmega::{MavCmd, MavFrame, MavMissionResult, MISSION_ITEM_INT_DATA};

use crate::guidance::{HereParts, Home, Mission, MissionItem};
use crate::math::Vec3;

/// Why a mission was refused: the item and the result.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ItemError {
    /// Sequence number of the bad item.
    pub seq: u16,
    /// MAV_MISSION_RESULT.
    pub result: MavMissionResult,
}

/// How a personality reads the mission items PX4 and ArduCopter read differently
/// (docs/ardupilot.md §6): a value handed to [`parse_mission`], so one parser and one mission
/// runner serve both.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MissionRules {
    /// On NAV_WAYPOINT, NAV_LOITER_TIME and NAV_LOITER_UNLIM a latitude and longitude of 0 are
    /// where the vehicle is when the item starts, and so is an altitude of 0 (ArduCopter's
    /// `loc_from_cmd`); PX4 refuses such a point as far from home (INVALID_PARAM5_X).
    pub zero_is_here: bool,
    /// NAV_WAYPOINT's acceptance radius (p2) and heading (p4) are the item's (PX4); ArduCopter
    /// ignores both (`WPNAV_RADIUS` decides when a waypoint is reached).
    pub waypoint_radius_and_yaw: bool,
    /// Hold times (NAV_WAYPOINT and NAV_LOITER_TIME p1) count whole seconds, as ArduCopter
    /// stores them; PX4 takes fractions.
    pub whole_second_holds: bool,
    /// NAV_LOITER_UNLIM is flown (ArduCopter: to the point, then held until the mission is
    /// left); PX4's face refuses it (UNSUPPORTED).
    pub loiter_unlimited: bool,
}

impl MissionRules {
    /// PX4's reading (docs/mavlink.md §7).
    pub const PX4: Self = Self {
        zero_is_here: false,
        waypoint_radius_and_yaw: true,
        whole_second_holds: false,
        loiter_unlimited: false,
    };
    /// ArduCopter's reading (`ArduCopter/mode_auto.cpp`).
    pub const COPTER: Self = Self {
        zero_is_here: true,
        waypoint_radius_and_yaw: false,
        whole_second_holds: true,
        loiter_unlimited: true,
    };
}

/// Parses uploaded items (in sequence order) into a mission about `home`, read by `rules`.
pub fn parse_mission(items: &[MISSION_ITEM_INT_DATA], home: &Home, rules: MissionRules) -> Result<Mission, ItemError> {
    let mut out = Vec::with_capacity(items.len());
    let mut here = Vec::with_capacity(items.len());
    for (i, item) in items.iter().enumerate() {
        if usize::from(item.seq) != i {
            return Err(ItemError {
                seq: item.seq,
                result: MavMissionResult::MAV_MISSION_INVALID_SEQUENCE,
            });
        }
        let refuse = |result| ItemError { seq: item.seq, result };
        let (parsed, parts) = parse_item(item, home, rules).map_err(refuse)?;
        out.push(parsed);
        here.push(parts);
    }
    // A DO_JUMP goes on at an item of this mission, never at itself.
    let count = out.len();
    for (i, item) in out.iter().enumerate() {
        if let MissionItem::Jump { target, .. } = *item {
            if target >= count || target == i {
                return Err(ItemError {
                    seq: i as u16,
                    result: MavMissionResult::MAV_MISSION_INVALID_PARAM1,
                });
            }
        }
    }
    let above_home = items.iter().map(|item| is_relative_frame(item.frame)).collect();
    Ok(Mission {
        items: out,
        above_home,
        here,
    })
}

/// True for the frames whose altitude is above home.
#[allow(deprecated)]
fn is_relative_frame(frame: MavFrame) -> bool {
    matches!(
        frame,
        MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT_INT | MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT
    )
}

/// A position of a positional frame, local NED [m]; UNSUPPORTED_FRAME for another frame,
/// INVALID_PARAM5_X for a point not finite or more than 100 km from home.
#[allow(deprecated)]
pub(crate) fn position(item: &MISSION_ITEM_INT_DATA, home: &Home) -> Result<Vec3, MavMissionResult> {
    let z = f64::from(item.z);
    let global = |relative: bool| {
        let alt = if relative { home.alt_amsl_m + z } else { z };
        home.to_local(f64::from(item.x) * 1e-7, f64::from(item.y) * 1e-7, alt)
    };
    let p = match item.frame {
        MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT_INT | MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT => global(true),
        MavFrame::MAV_FRAME_GLOBAL_INT | MavFrame::MAV_FRAME_GLOBAL => global(false),
        MavFrame::MAV_FRAME_LOCAL_NED => Vec3::new(f64::from(item.x) * 1e-4, f64::from(item.y) * 1e-4, z),
        _ => return Err(MavMissionResult::MAV_MISSION_UNSUPPORTED_FRAME),
    };
    if !p.iter().all(|v| v.is_finite()) || p.xy().norm() > 100_000.0 {
        return Err(MavMissionResult::MAV_MISSION_INVALID_PARAM5_X);
    }
    Ok(p)
}

fn non_negative(x: f32, bad: MavMissionResult) -> Result<f64, MavMissionResult> {
    if x.is_nan() {
        return Ok(0.0);
    }
    if x.is_finite() && x >= 0.0 {
        Ok(f64::from(x))
    } else {
        Err(bad)
    }
}

/// The position of a waypoint or loiter item under `rules`, and which of its parts are where the
/// vehicle will be (ArduCopter's zeros, read about home and replaced in flight).
fn located(
    item: &MISSION_ITEM_INT_DATA,
    home: &Home,
    rules: MissionRules,
) -> Result<(Vec3, HereParts), MavMissionResult> {
    let global = !matches!(item.frame, MavFrame::MAV_FRAME_LOCAL_NED);
    let here = HereParts {
        xy: rules.zero_is_here && global && item.x == 0 && item.y == 0,
        z: rules.zero_is_here && global && item.z == 0.0,
    };
    if !here.xy {
        return Ok((position(item, home)?, here));
    }
    let at_home = MISSION_ITEM_INT_DATA {
        x: (home.lat_deg * 1e7).round() as i32,
        y: (home.lon_deg * 1e7).round() as i32,
        ..item.clone()
    };
    Ok((position(&at_home, home)?, here))
}

/// A hold time p1 [s] under `rules` (whole seconds for ArduCopter, which stores an integer).
fn hold(p1: f32, rules: MissionRules) -> Result<f64, MavMissionResult> {
    let s = non_negative(p1, MavMissionResult::MAV_MISSION_INVALID_PARAM1)?;
    Ok(if rules.whole_second_holds { s.trunc() } else { s })
}

#[allow(deprecated)]
fn parse_item(
    item: &MISSION_ITEM_INT_DATA,
    home: &Home,
    rules: MissionRules,
) -> Result<(MissionItem, HereParts), MavMissionResult> {
    use MavMissionResult::*;
    let mut here = HereParts::default();
    let parsed = match item.command {
        MavCmd::MAV_CMD_NAV_TAKEOFF => {
            // Only the altitude counts: the climb is over the current position.
            let z = f64::from(item.z);
            let height_m = match item.frame {
                MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT_INT | MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT => z,
                MavFrame::MAV_FRAME_GLOBAL_INT | MavFrame::MAV_FRAME_GLOBAL => z - home.alt_amsl_m,
                MavFrame::MAV_FRAME_LOCAL_NED => -z,
                _ => return Err(MAV_MISSION_UNSUPPORTED_FRAME),
            };
            if !(height_m.is_finite() && height_m > 0.0) {
                return Err(MAV_MISSION_INVALID_PARAM7);
            }
            MissionItem::Takeoff { height_m }
        }
        MavCmd::MAV_CMD_NAV_WAYPOINT => {
            let own = rules.waypoint_radius_and_yaw;
            let accept = non_negative(item.param2, MAV_MISSION_INVALID_PARAM2)?;
            let pos_w;
            (pos_w, here) = located(item, home, rules)?;
            MissionItem::Waypoint {
                pos_w,
                hold_s: hold(item.param1, rules)?,
                accept_m: (own && accept > 0.0).then_some(accept),
                yaw_rad: (own && item.param4.is_finite()).then(|| f64::from(item.param4).to_radians()),
            }
        }
        MavCmd::MAV_CMD_NAV_LOITER_TIME => {
            let pos_w;
            (pos_w, here) = located(item, home, rules)?;
            MissionItem::LoiterTime {
                pos_w,
                seconds: Some(hold(item.param1, rules)?),
            }
        }
        MavCmd::MAV_CMD_NAV_LOITER_UNLIM if rules.loiter_unlimited => {
            let pos_w;
            (pos_w, here) = located(item, home, rules)?;
            MissionItem::LoiterTime { pos_w, seconds: None }
        }
        MavCmd::MAV_CMD_NAV_LAND => MissionItem::Land {
            pos_w: if item.x == 0 && item.y == 0 {
                None
            } else {
                Some(position(item, home)?)
            },
        },
        MavCmd::MAV_CMD_NAV_RETURN_TO_LAUNCH => MissionItem::ReturnToLaunch,
        MavCmd::MAV_CMD_DO_CHANGE_SPEED => {
            let v = item.param2;
            if !(v.is_finite() && v > 0.0 && v <= 30.0) {
                return Err(MAV_MISSION_INVALID_PARAM2);
            }
            MissionItem::ChangeSpeed {
                speed_m_s: f64::from(v),
            }
        }
        MavCmd::MAV_CMD_NAV_DELAY => {
            let s = item.param1;
            if !(s.is_finite() && s >= 0.0) {
                return Err(MAV_MISSION_INVALID_PARAM1);
            }
            MissionItem::Delay { seconds: f64::from(s) }
        }
        MavCmd::MAV_CMD_DO_JUMP => {
            let (target, repeat) = (item.param1, item.param2);
            if !(target.is_finite() && target >= 0.0 && target.fract() == 0.0 && target < 65536.0) {
                return Err(MAV_MISSION_INVALID_PARAM1);
            }
            // PX4 counts −1 (any negative) as for ever.
            if !(repeat.is_finite() && repeat.fract() == 0.0 && repeat < 65536.0) {
                return Err(MAV_MISSION_INVALID_PARAM2);
            }
            MissionItem::Jump {
                target: target as usize,
                repeat: (repeat >= 0.0).then_some(repeat as u32),
            }
        }
        _ => return Err(MAV_MISSION_UNSUPPORTED),
    };
    Ok((parsed, here))
}

#[cfg(test)]
#[allow(deprecated)] // MAVSDK uploads in MAV_FRAME_GLOBAL_RELATIVE_ALT_INT
mod tests {
    use super::*;

    fn item(seq: u16, command: MavCmd, frame: MavFrame, x: i32, y: i32, z: f32) -> MISSION_ITEM_INT_DATA {
        MISSION_ITEM_INT_DATA {
            seq,
            command,
            frame,
            x,
            y,
            z,
            param1: 0.0,
            param2: 0.0,
            param3: 0.0,
            param4: f32::NAN,
            autocontinue: 1,
            ..Default::default()
        }
    }

    #[test]
    fn a_mavsdk_style_mission_parses() {
        let home = Home::default();
        let (lat, lon) = ((home.lat_deg * 1e7) as i32, (home.lon_deg * 1e7) as i32);
        let rel = MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT_INT;
        let mut wp = item(1, MavCmd::MAV_CMD_NAV_WAYPOINT, rel, lat + 900, lon, 10.0);
        wp.param1 = 2.0;
        let items = [
            item(0, MavCmd::MAV_CMD_NAV_TAKEOFF, rel, lat, lon, 5.0),
            wp,
            item(
                2,
                MavCmd::MAV_CMD_NAV_RETURN_TO_LAUNCH,
                MavFrame::MAV_FRAME_MISSION,
                0,
                0,
                0.0,
            ),
        ];
        let m = parse_mission(&items, &home, MissionRules::PX4).unwrap();
        assert_eq!(m.len(), 3);
        assert!(matches!(m.items[0], MissionItem::Takeoff { height_m } if (height_m - 5.0).abs() < 1e-6));
        let MissionItem::Waypoint {
            pos_w,
            hold_s,
            accept_m,
            yaw_rad,
        } = m.items[1]
        else {
            panic!("not a waypoint");
        };
        // 900e-7 deg of latitude ≈ 10.0 m north.
        assert!((pos_w.x - 10.0).abs() < 0.01 && pos_w.y.abs() < 0.01 && (pos_w.z + 10.0).abs() < 1e-6);
        assert_eq!(
            (hold_s, accept_m, yaw_rad),
            (2.0, None, None),
            "no radius: NAV_ACC_RAD applies"
        );
    }

    #[test]
    fn a_do_jump_parses_and_must_go_on_at_another_item_of_the_mission() {
        let home = Home::default();
        let rel = MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT_INT;
        let jump = |seq: u16, target: f32, repeat: f32| MISSION_ITEM_INT_DATA {
            param1: target,
            param2: repeat,
            ..item(seq, MavCmd::MAV_CMD_DO_JUMP, MavFrame::MAV_FRAME_MISSION, 0, 0, 0.0)
        };
        let takeoff = item(0, MavCmd::MAV_CMD_NAV_TAKEOFF, rel, 0, 0, 5.0);
        let m = parse_mission(&[takeoff.clone(), jump(1, 0.0, 2.0)], &home, MissionRules::PX4).unwrap();
        assert_eq!(
            m.items[1],
            MissionItem::Jump {
                target: 0,
                repeat: Some(2)
            }
        );
        let forever = parse_mission(&[takeoff.clone(), jump(1, 0.0, -1.0)], &home, MissionRules::PX4).unwrap();
        assert_eq!(
            forever.items[1],
            MissionItem::Jump {
                target: 0,
                repeat: None
            }
        );
        for (target, repeat, result) in [
            (5.0, 1.0, MavMissionResult::MAV_MISSION_INVALID_PARAM1),
            (1.0, 1.0, MavMissionResult::MAV_MISSION_INVALID_PARAM1),
            (0.5, 1.0, MavMissionResult::MAV_MISSION_INVALID_PARAM1),
            (0.0, f32::NAN, MavMissionResult::MAV_MISSION_INVALID_PARAM2),
        ] {
            let e = parse_mission(&[takeoff.clone(), jump(1, target, repeat)], &home, MissionRules::PX4).unwrap_err();
            assert_eq!((e.seq, e.result), (1, result), "{target} {repeat}");
        }
    }

    #[test]
    fn bad_items_name_their_sequence_and_result() {
        let home = Home::default();
        let rel = MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT_INT;
        let bad = |items: &[MISSION_ITEM_INT_DATA]| parse_mission(items, &home, MissionRules::PX4).unwrap_err();
        let ok = item(0, MavCmd::MAV_CMD_NAV_WAYPOINT, rel, 473977420, 85455940, 5.0);
        let e = bad(&[ok.clone(), item(1, MavCmd::MAV_CMD_DO_SET_SERVO, rel, 0, 0, 0.0)]);
        assert_eq!((e.seq, e.result), (1, MavMissionResult::MAV_MISSION_UNSUPPORTED));
        let e = bad(&[item(
            0,
            MavCmd::MAV_CMD_NAV_WAYPOINT,
            MavFrame::MAV_FRAME_BODY_FRD,
            0,
            0,
            0.0,
        )]);
        assert_eq!(e.result, MavMissionResult::MAV_MISSION_UNSUPPORTED_FRAME);
        let e = bad(&[ok.clone(), ok.clone()]);
        assert_eq!(e.result, MavMissionResult::MAV_MISSION_INVALID_SEQUENCE);
        let mut neg = ok.clone();
        neg.param1 = -1.0;
        assert_eq!(bad(&[neg]).result, MavMissionResult::MAV_MISSION_INVALID_PARAM1);
        let e = bad(&[item(0, MavCmd::MAV_CMD_NAV_TAKEOFF, rel, 0, 0, -3.0)]);
        assert_eq!(e.result, MavMissionResult::MAV_MISSION_INVALID_PARAM7);
    }

    #[test]
    fn arducopter_reads_zeros_as_here_ignores_radius_and_heading_and_flies_loiter_unlim() {
        let home = Home::default();
        let rel = MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT_INT;
        let mut wp = item(0, MavCmd::MAV_CMD_NAV_WAYPOINT, rel, 0, 0, 12.0);
        (wp.param1, wp.param2, wp.param4) = (2.7, 4.0, 90.0);
        let unlim = item(
            1,
            MavCmd::MAV_CMD_NAV_LOITER_UNLIM,
            rel,
            473_977_420 + 900,
            85_455_940,
            0.0,
        );
        let copter = parse_mission(&[wp.clone(), unlim.clone()], &home, MissionRules::COPTER).unwrap();
        assert_eq!(
            copter.items[0],
            MissionItem::Waypoint {
                pos_w: Vec3::new(0.0, 0.0, -12.0),
                hold_s: 2.0,
                accept_m: None,
                yaw_rad: None,
            },
            "whole seconds, WPNAV_RADIUS, Copter's own heading"
        );
        assert_eq!(copter.here(0), HereParts { xy: true, z: false });
        assert!(
            matches!(copter.items[1], MissionItem::LoiterTime { seconds: None, pos_w } if (pos_w.x - 10.0).abs() < 0.01)
        );
        assert_eq!(
            copter.here(1),
            HereParts { xy: false, z: true },
            "altitude 0: the current one"
        );
        // PX4 refuses the zero point (far from home) and LOITER_UNLIM.
        let bad = |m: &MISSION_ITEM_INT_DATA| {
            parse_mission(std::slice::from_ref(m), &home, MissionRules::PX4)
                .unwrap_err()
                .result
        };
        assert_eq!(bad(&wp), MavMissionResult::MAV_MISSION_INVALID_PARAM5_X);
        let mut unlim0 = unlim;
        unlim0.seq = 0;
        assert_eq!(bad(&unlim0), MavMissionResult::MAV_MISSION_UNSUPPORTED);
        let mut far = wp;
        (far.x, far.y) = (473_977_420 + 900, 85_455_940);
        let px4 = parse_mission(&[far], &home, MissionRules::PX4).unwrap();
        assert!(
            matches!(px4.items[0], MissionItem::Waypoint { accept_m: Some(r), hold_s, .. } if r == 4.0 && (hold_s - 2.7).abs() < 1e-6)
        );
        assert_eq!(px4.here(0), HereParts::default());
    }
}
