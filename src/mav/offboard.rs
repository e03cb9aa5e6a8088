//! Offboard setpoints (mavlink.md §6): SET_POSITION_TARGET_LOCAL_NED decoded into a
//! [`FlatSetpoint`] with PX4's accepted combinations. `type_mask` bits are *ignore* bits:
//! X 1, Y 2, Z 4, VX 8, VY 16, VZ 32, AX 64, AY 128, AZ 256, FORCE 512, YAW 1024, YAW_RATE 2048.
//! Pure.

use mavlink::dialects::common::{MavFrame, SET_POSITION_TARGET_LOCAL_NED_DATA};

use crate::control::FlatSetpoint;
use crate::math::Vec3;

const IGNORE_POS: u16 = 0b111;
const IGNORE_VEL: u16 = 0b111 << 3;
const IGNORE_ACC: u16 = 0b111 << 6;
const FORCE: u16 = 1 << 9;
const IGNORE_YAW: u16 = 1 << 10;
const IGNORE_YAW_RATE: u16 = 1 << 11;

/// A decoded offboard target.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OffboardTarget {
    /// The setpoint; with `body_frame` its velocity and acceleration are in the heading frame.
    pub setpoint: FlatSetpoint,
    /// MAV_FRAME_BODY_NED: velocities and accelerations are rotated by the current heading.
    pub body_frame: bool,
}

/// Decodes `m`, or says why it is refused (PX4 multicopter combinations only). MAV_FRAME_BODY_NED
/// is deprecated in the spec, but MAVSDK's body-frame velocity uses it.
#[allow(deprecated)]
pub fn decode_local_target(m: &SET_POSITION_TARGET_LOCAL_NED_DATA) -> Result<OffboardTarget, String> {
    let mask = m.type_mask.bits();
    let body_frame = match m.coordinate_frame {
        MavFrame::MAV_FRAME_LOCAL_NED => false,
        MavFrame::MAV_FRAME_BODY_NED => true,
        other => return Err(format!("Offboard: frame {other:?} not supported")),
    };
    if mask & FORCE != 0 {
        return Err("Offboard: force setpoints not supported".into());
    }
    let group = |bits: u16, v: [f32; 3]| -> Result<Option<Vec3>, String> {
        match mask & bits {
            0 => {
                let v = Vec3::new(f64::from(v[0]), f64::from(v[1]), f64::from(v[2]));
                if v.iter().all(|x| x.is_finite()) {
                    Ok(Some(v))
                } else {
                    Err("Offboard: non-finite setpoint".into())
                }
            }
            b if b == bits => Ok(None),
            _ => Err(format!("Offboard: type_mask {mask} mixes axes")),
        }
    };
    let pos = group(IGNORE_POS, [m.x, m.y, m.z])?;
    let vel = group(IGNORE_VEL, [m.vx, m.vy, m.vz])?;
    let acc = group(IGNORE_ACC, [m.afx, m.afy, m.afz])?;
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
    Ok(OffboardTarget {
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

#[cfg(test)]
mod tests {
    use super::*;
    use mavlink::dialects::common::PositionTargetTypemask;

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
