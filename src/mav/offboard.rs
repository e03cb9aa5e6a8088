//! Offboard setpoints (docs/mavlink.md §6): SET_POSITION_TARGET_LOCAL_NED decoded into a
//! [`FlatSetpoint`] with PX4's accepted combinations. `type_mask` bits are *ignore* bits:
//! X 1, Y 2, Z 4, VX 8, VY 16, VZ 32, AX 64, AY 128, AZ 256, FORCE 512, YAW 1024, YAW_RATE 2048.
//! Pure.

use mavlink::dialects::ardupilotmega::{
    MavFrame, SET_ATTITUDE_TARGET_DATA, SET_POSITION_TARGET_GLOBAL_INT_DATA, SET_POSITION_TARGET_LOCAL_NED_DATA,
};

use crate::control::{AttitudeTarget, FlatSetpoint};
use crate::guidance::Home;
use crate::math::{UnitQuat, Vec3};

const IGNORE_POS: u16 = 0b111;
const IGNORE_VEL: u16 = 0b111 << 3;
const IGNORE_ACC: u16 = 0b111 << 6;
const FORCE: u16 = 1 << 9;
const IGNORE_YAW: u16 = 1 << 10;
const IGNORE_YAW_RATE: u16 = 1 << 11;

/// A decoded offboard target.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DecodedOffboard {
    /// The setpoint; with `body_frame` its velocity and acceleration are in the heading frame.
    pub setpoint: FlatSetpoint,
    /// MAV_FRAME_BODY_NED: velocities and accelerations are rotated by the current heading.
    pub body_frame: bool,
}

/// Largest offboard position component from home [m]: farther is not a setpoint but a mistake.
pub const MAX_POSITION_M: f64 = 10_000.0;
/// Largest offboard velocity component [m/s].
pub const MAX_SPEED_M_S: f64 = 100.0;
/// Largest offboard acceleration component [m/s²].
pub const MAX_ACCEL_M_S2: f64 = 100.0;

/// Decodes `m`, or says why it is refused (PX4 multicopter combinations only). MAV_FRAME_BODY_NED
/// is deprecated in the spec, but MAVSDK's body-frame velocity uses it.
#[allow(deprecated)]
pub fn decode_local_target(m: &SET_POSITION_TARGET_LOCAL_NED_DATA) -> Result<DecodedOffboard, String> {
    let mask = m.type_mask.bits();
    let body_frame = match m.coordinate_frame {
        MavFrame::MAV_FRAME_LOCAL_NED => false,
        MavFrame::MAV_FRAME_BODY_NED => true,
        other => return Err(format!("Offboard: frame {other:?} not supported")),
    };
    if mask & FORCE != 0 {
        return Err("Offboard: force setpoints not supported".into());
    }
    let group = |bits: u16, v: [f32; 3], (what, limit): (&str, f64)| -> Result<Option<Vec3>, String> {
        match mask & bits {
            0 => {
                let v = Vec3::new(f64::from(v[0]), f64::from(v[1]), f64::from(v[2]));
                if !v.iter().all(|x| x.is_finite()) {
                    Err("Offboard: non-finite setpoint".into())
                } else if v.amax() > limit {
                    Err(format!("Offboard: {what} {:.0} beyond {limit}", v.amax()))
                } else {
                    Ok(Some(v))
                }
            }
            b if b == bits => Ok(None),
            _ => Err(format!("Offboard: type_mask {mask} mixes axes")),
        }
    };
    let pos = group(IGNORE_POS, [m.x, m.y, m.z], ("position [m]", MAX_POSITION_M))?;
    let vel = group(IGNORE_VEL, [m.vx, m.vy, m.vz], ("velocity [m/s]", MAX_SPEED_M_S))?;
    let acc = group(
        IGNORE_ACC,
        [m.afx, m.afy, m.afz],
        ("acceleration [m/s²]", MAX_ACCEL_M_S2),
    )?;
    if pos.is_none() && vel.is_none() && acc.is_none() {
        return Err("Offboard: no position, velocity or acceleration".into());
    }
    if pos.is_some() && body_frame {
        return Err("Offboard: body-frame positions not supported".into());
    }
    let scalar = |ignored: bool, x: f32| -> Result<Option<f64>, String> {
        match (ignored, x.is_finite()) {
            (true, _) => Ok(None),
            (false, true) => Ok(Some(f64::from(x))),
            (false, false) => Err("Offboard: non-finite yaw".into()),
        }
    };
    Ok(DecodedOffboard {
        setpoint: FlatSetpoint {
            pos_w: pos,
            vel_w: vel,
            acc_w: acc,
            yaw_rad: scalar(mask & IGNORE_YAW != 0, m.yaw)?,
            yaw_rate_rad_s: scalar(mask & IGNORE_YAW_RATE != 0, m.yaw_rate)?,
            yaw_acc_rad_s2: None,
        },
        body_frame,
    })
}

/// SET_POSITION_TARGET_GLOBAL_INT: latitude/longitude [degE7] and altitude (AMSL in
/// GLOBAL_INT, above home in GLOBAL_RELATIVE_ALT_INT) about `origin`, then as the local target.
#[allow(deprecated)]
pub fn decode_global_target(m: &SET_POSITION_TARGET_GLOBAL_INT_DATA, origin: &Home) -> Result<DecodedOffboard, String> {
    let alt_amsl = match m.coordinate_frame {
        MavFrame::MAV_FRAME_GLOBAL_INT | MavFrame::MAV_FRAME_GLOBAL => f64::from(m.alt),
        MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT_INT | MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT => {
            origin.alt_amsl_m + f64::from(m.alt)
        }
        other => return Err(format!("Offboard: frame {other:?} not supported")),
    };
    let p = origin.to_local(f64::from(m.lat_int) * 1e-7, f64::from(m.lon_int) * 1e-7, alt_amsl);
    decode_local_target(&SET_POSITION_TARGET_LOCAL_NED_DATA {
        time_boot_ms: m.time_boot_ms,
        x: p.x as f32,
        y: p.y as f32,
        z: p.z as f32,
        vx: m.vx,
        vy: m.vy,
        vz: m.vz,
        afx: m.afx,
        afy: m.afy,
        afz: m.afz,
        yaw: m.yaw,
        yaw_rate: m.yaw_rate,
        type_mask: m.type_mask,
        target_system: m.target_system,
        target_component: m.target_component,
        coordinate_frame: MavFrame::MAV_FRAME_LOCAL_NED,
    })
}

/// SET_ATTITUDE_TARGET ignore bits: body rates 1, 2, 4; thrust-body 32; throttle 64; attitude 128.
const IGNORE_RATES: u8 = 0b111;
const IGNORE_THRUST_BODY: u8 = 32;
const IGNORE_THROTTLE: u8 = 64;
const IGNORE_ATTITUDE: u8 = 128;

/// Decodes SET_ATTITUDE_TARGET (docs/mavlink.md §6): attitude + thrust (MAVSDK mask 7), rates +
/// thrust (128), or all three; `q` is w-first, body → world (NED → FRD), thrust normalised 0..1.
pub fn decode_attitude_target(m: &SET_ATTITUDE_TARGET_DATA) -> Result<AttitudeTarget, String> {
    let mask = m.type_mask.bits();
    if mask & IGNORE_THRUST_BODY == 0 && m.thrust_body.iter().any(|t| *t != 0.0) {
        return Err("Attitude target: thrust_body not supported".into());
    }
    if mask & IGNORE_THROTTLE != 0 {
        return Err("Attitude target: a thrust is required".into());
    }
    if !(m.thrust.is_finite() && (0.0..=1.0).contains(&m.thrust)) {
        return Err(format!("Attitude target: thrust {} outside [0, 1]", m.thrust));
    }
    let q_wb = if mask & IGNORE_ATTITUDE == 0 {
        let q = nalgebra::Quaternion::new(
            f64::from(m.q[0]),
            f64::from(m.q[1]),
            f64::from(m.q[2]),
            f64::from(m.q[3]),
        );
        if !(q.coords.iter().all(|c| c.is_finite()) && (q.norm() - 1.0).abs() < 1e-3) {
            return Err("Attitude target: q is not a unit quaternion".into());
        }
        Some(UnitQuat::from_quaternion(q))
    } else {
        None
    };
    let omega_b = match mask & IGNORE_RATES {
        IGNORE_RATES => None,
        0 => {
            let w = Vec3::new(
                f64::from(m.body_roll_rate),
                f64::from(m.body_pitch_rate),
                f64::from(m.body_yaw_rate),
            );
            if !w.iter().all(|c| c.is_finite()) {
                return Err("Attitude target: non-finite rates".into());
            }
            Some(w)
        }
        _ => return Err(format!("Attitude target: type_mask {mask} mixes rate axes")),
    };
    if q_wb.is_none() && omega_b.is_none() {
        return Err("Attitude target: neither attitude nor rates".into());
    }
    Ok(AttitudeTarget {
        q_wb,
        omega_b,
        thrust_fraction: f64::from(m.thrust),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use mavlink::dialects::ardupilotmega::PositionTargetTypemask;

    fn target(mask: u16, frame: MavFrame) -> SET_POSITION_TARGET_LOCAL_NED_DATA {
        SET_POSITION_TARGET_LOCAL_NED_DATA {
            x: 1.0,
            y: 2.0,
            z: -3.0,
            vx: 0.5,
            vy: 0.0,
            vz: -0.5,
            yaw: 0.3,
            yaw_rate: 0.1,
            type_mask: PositionTargetTypemask::from_bits_truncate(mask),
            coordinate_frame: frame,
            ..Default::default()
        }
    }

    #[test]
    #[allow(deprecated)]
    fn mavsdk_masks_decode() {
        let local = MavFrame::MAV_FRAME_LOCAL_NED;
        let p = decode_local_target(&target(2552, local)).unwrap().setpoint;
        assert_eq!(
            (p.pos_w, p.vel_w, p.yaw_rad),
            (Some(Vec3::new(1.0, 2.0, -3.0)), None, Some(0.3f32 as f64))
        );
        assert_eq!(p.yaw_rate_rad_s, None);
        let v = decode_local_target(&target(2503, local)).unwrap().setpoint;
        assert_eq!((v.pos_w, v.vel_w.map(|v| v.x)), (None, Some(0.5)));
        let pv = decode_local_target(&target(2496, local)).unwrap().setpoint;
        assert!(pv.pos_w.is_some() && pv.vel_w.is_some() && pv.acc_w.is_none());
        assert!(decode_local_target(&target(2048, local))
            .unwrap()
            .setpoint
            .acc_w
            .is_some());
        let a = decode_local_target(&target(3135, local)).unwrap().setpoint;
        assert!(a.acc_w.is_some() && a.pos_w.is_none() && a.yaw_rad.is_none());
        let body = decode_local_target(&target(1479, MavFrame::MAV_FRAME_BODY_NED)).unwrap();
        assert!(body.body_frame && body.setpoint.yaw_rate_rad_s.is_some() && body.setpoint.yaw_rad.is_none());
    }

    #[test]
    #[allow(deprecated)]
    fn global_targets_convert_about_the_origin() {
        let home = Home::default();
        let m = SET_POSITION_TARGET_GLOBAL_INT_DATA {
            lat_int: (home.lat_deg * 1e7).round() as i32 + 90,
            lon_int: (home.lon_deg * 1e7).round() as i32,
            alt: 3.0,
            type_mask: PositionTargetTypemask::from_bits_truncate(2552),
            coordinate_frame: MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT_INT,
            ..Default::default()
        };
        let p = decode_global_target(&m, &home).unwrap().setpoint.pos_w.unwrap();
        assert!(
            (p.x - 1.0).abs() < 0.01 && p.y.abs() < 0.01 && (p.z + 3.0).abs() < 1e-5,
            "{p}"
        );
        let bad = SET_POSITION_TARGET_GLOBAL_INT_DATA {
            coordinate_frame: MavFrame::MAV_FRAME_GLOBAL_TERRAIN_ALT_INT,
            ..m
        };
        assert!(decode_global_target(&bad, &home).is_err());
    }

    #[test]
    fn attitude_targets_decode_with_mavsdk_masks() {
        use mavlink::dialects::ardupilotmega::AttitudeTargetTypemask;
        let m = |mask: u8, q: [f32; 4], thrust: f32| SET_ATTITUDE_TARGET_DATA {
            q,
            body_roll_rate: 0.1,
            body_pitch_rate: 0.0,
            body_yaw_rate: -0.2,
            thrust,
            type_mask: AttitudeTargetTypemask::from_bits_truncate(mask),
            ..Default::default()
        };
        let att = decode_attitude_target(&m(7, [1.0, 0.0, 0.0, 0.0], 0.5)).unwrap();
        assert!(att.q_wb.is_some() && att.omega_b.is_none() && att.thrust_fraction == 0.5);
        let rates = decode_attitude_target(&m(128, [0.0; 4], 0.6)).unwrap();
        assert!(rates.q_wb.is_none() && rates.omega_b.map(|w| w.z) == Some(-0.2f32 as f64));
        assert!(
            decode_attitude_target(&m(7, [0.5, 0.0, 0.0, 0.0], 0.5)).is_err(),
            "not unit"
        );
        assert!(
            decode_attitude_target(&m(7, [1.0, 0.0, 0.0, 0.0], 1.5)).is_err(),
            "thrust > 1"
        );
        assert!(
            decode_attitude_target(&m(7 | 64, [1.0, 0.0, 0.0, 0.0], 0.5)).is_err(),
            "no thrust"
        );
        assert!(
            decode_attitude_target(&m(128 | 7, [1.0, 0.0, 0.0, 0.0], 0.5)).is_err(),
            "nothing"
        );
    }

    #[test]
    fn bad_targets_are_refused() {
        let local = MavFrame::MAV_FRAME_LOCAL_NED;
        assert!(
            decode_local_target(&target(0b1111_1111_1111, local)).is_err(),
            "nothing set"
        );
        assert!(
            decode_local_target(&target(2553 & !2, local)).is_err(),
            "x ignored, y not"
        );
        assert!(decode_local_target(&target(2552 | 512, local)).is_err(), "force");
        assert!(decode_local_target(&target(2552, MavFrame::MAV_FRAME_GLOBAL)).is_err());
        let mut nan = target(2552, local);
        nan.x = f32::NAN;
        assert!(decode_local_target(&nan).is_err());
    }
}
