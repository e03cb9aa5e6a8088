//! MAV_CMD_DO_REPOSITION as PX4 reads it: the target (COMMAND_LONG: p5/p6 latitude/longitude
//! [deg], p7 AMSL [m]; COMMAND_INT: the exact degE7 x/y, INT32_MAX unset, and z in the frame
//! given, docs/mavlink.md §3.2), p1 the ground speed (≤ 0: default), p4 the heading [rad] and
//! p2's mode-change bit (MAV_DO_REPOSITION_FLAGS_CHANGE_MODE), taken from p2's integer part as
//! PX4's commander takes it; NaN means unset. What the flag then does is the commander's
//! (`src/commander/goto.rs`). Pure.

use mavlink::dialects::ardupilotmega::{MavFrame, COMMAND_INT_DATA, COMMAND_LONG_DATA};

use crate::commander::{Outcome, Request};
use crate::guidance::Home;

use super::translate::{on_earth, CommandDecision};

/// MAV_DO_REPOSITION_FLAGS_CHANGE_MODE, the bit of p2 that asks for a mode change.
const CHANGE_MODE: u32 = 1;

/// `None` for NaN ("not set").
fn param(x: f32) -> Option<f32> {
    (!x.is_nan()).then_some(x)
}

/// A DO_REPOSITION sent as COMMAND_LONG, about `origin`.
pub fn decode_long(cmd: &COMMAND_LONG_DATA, origin: &Home) -> CommandDecision {
    let (lat, lon) = (param(cmd.param5), param(cmd.param6));
    let alt = param(cmd.param7);
    let (lat_deg, lon_deg) = (f64::from(lat.unwrap_or(0.0)), f64::from(lon.unwrap_or(0.0)));
    if !on_earth(lat_deg, lon_deg, f64::from(alt.unwrap_or(0.0))) {
        return CommandDecision::Refuse(Outcome::Denied(format!(
            "Reposition: {:.2}, {:.2}, {:.0} m is not a place",
            cmd.param5, cmd.param6, cmd.param7
        )));
    }
    let local = origin.to_local(lat_deg, lon_deg, f64::from(alt.unwrap_or(0.0)));
    request(cmd, lat.and(lon).map(|_| (local.x, local.y)), alt.map(|_| local.z))
}

/// A DO_REPOSITION sent as COMMAND_INT (`long`: the same as COMMAND_LONG), about `origin`:
/// z AMSL in the GLOBAL frames, above home in the GLOBAL_RELATIVE_ALT ones, other frames
/// UNSUPPORTED_MAV_FRAME.
#[allow(deprecated)]
pub fn decode_int(cmd: &COMMAND_INT_DATA, long: &COMMAND_LONG_DATA, origin: &Home) -> CommandDecision {
    let alt_amsl = |z: f32| match cmd.frame {
        MavFrame::MAV_FRAME_GLOBAL | MavFrame::MAV_FRAME_GLOBAL_INT => Some(f64::from(z)),
        MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT | MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT_INT => {
            Some(origin.alt_amsl_m + f64::from(z))
        }
        _ => None,
    };
    if alt_amsl(0.0).is_none() {
        return CommandDecision::Refuse(Outcome::Unsupported("Reposition: frame not supported".into()));
    }
    let given = cmd.x != i32::MAX && cmd.y != i32::MAX;
    let (lat, lon) = (f64::from(cmd.x) * 1e-7, f64::from(cmd.y) * 1e-7);
    if given && !on_earth(lat, lon, 0.0) {
        return CommandDecision::Refuse(Outcome::Denied(format!(
            "Reposition: {lat:.2}, {lon:.2} is not a place"
        )));
    }
    let xy = given.then(|| {
        let p = origin.to_local(lat, lon, origin.alt_amsl_m);
        (p.x, p.y)
    });
    let down = param(cmd.z).and_then(alt_amsl).map(|amsl| origin.alt_amsl_m - amsl);
    request(long, xy, down)
}

/// The request for a local target (`xy`, `down` in NED metres; `None` = keep current) with the
/// other parameters of `cmd`.
fn request(cmd: &COMMAND_LONG_DATA, xy: Option<(f64, f64)>, down: Option<f64>) -> CommandDecision {
    let flags = param(cmd.param2).filter(|p| *p >= 0.0).map_or(0, |p| p as u32);
    CommandDecision::Execute(Request::Reposition {
        north_m: xy.map(|p| p.0),
        east_m: xy.map(|p| p.1),
        down_m: down,
        yaw_rad: param(cmd.param4).map(f64::from),
        speed_m_s: param(cmd.param1).filter(|v| *v > 0.0).map(f64::from),
        change_mode: flags & CHANGE_MODE != 0,
    })
}

#[cfg(test)]
mod tests {
    use mavlink::dialects::ardupilotmega::MavCmd;

    use super::*;
    use crate::mav::gcs::gcs_header;
    use crate::mav::translate::{decode_command_int, Identity};

    const NAN: f32 = f32::NAN;

    #[test]
    #[allow(deprecated)]
    fn reposition_uses_exact_coordinates_and_the_frame_of_z() {
        let id = Identity::autopilot(1, 4);
        let home = Home::default();
        let north_5m =
            (home.lat_deg * 1e7).round() as i32 + (5.0 / 6_371_000f64).to_degrees().mul_add(1e7, 0.0).round() as i32;
        let cmd = COMMAND_INT_DATA {
            command: MavCmd::MAV_CMD_DO_REPOSITION,
            param1: -1.0,
            param2: 1.0,
            param4: NAN,
            x: north_5m,
            y: (home.lon_deg * 1e7).round() as i32,
            z: 4.0,
            frame: MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT_INT,
            target_system: 1,
            target_component: 1,
            ..Default::default()
        };
        let CommandDecision::Execute(Request::Reposition {
            north_m,
            east_m,
            down_m,
            yaw_rad,
            speed_m_s,
            change_mode,
        }) = decode_command_int(&id, &gcs_header(0), &cmd, &home)
        else {
            panic!("not a reposition");
        };
        assert!((north_m.unwrap() - 5.0).abs() < 0.02 && east_m.unwrap().abs() < 0.02);
        assert!((down_m.unwrap() + 4.0).abs() < 1e-9);
        assert_eq!((yaw_rad, speed_m_s, change_mode), (None, None, true));
        // p2's mode-change bit: the integer part of p2, NaN none; INT32_MAX x/y: no position.
        for (p2, flag) in [(0.0, false), (3.0, true), (2.0, false), (NAN, false), (1.7, true)] {
            let hold_here = COMMAND_INT_DATA {
                param2: p2,
                x: i32::MAX,
                y: i32::MAX,
                z: NAN,
                ..cmd
            };
            let CommandDecision::Execute(Request::Reposition {
                north_m,
                down_m,
                change_mode,
                ..
            }) = decode_command_int(&id, &gcs_header(0), &hold_here, &home)
            else {
                panic!("not a reposition");
            };
            assert_eq!((north_m, down_m, change_mode), (None, None, flag), "p2 {p2}");
        }
        let local = COMMAND_INT_DATA {
            frame: MavFrame::MAV_FRAME_LOCAL_NED,
            ..cmd
        };
        assert!(matches!(
            decode_command_int(&id, &gcs_header(0), &local, &home),
            CommandDecision::Refuse(Outcome::Unsupported(_))
        ));
    }
}
