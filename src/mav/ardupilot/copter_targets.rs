//! GUIDED's targets as ArduCopter reads them (docs/ardupilot.md §3), before PX4's offboard
//! decoding flies them: the frames Copter takes (LOCAL_NED; LOCAL_OFFSET_NED, BODY_NED and
//! BODY_OFFSET_NED as offsets from the vehicle, the body frames turned by its heading, with a
//! heading relative to its own), the force bit ignored while the acceleration is (DroneKit's
//! masks set it), and a target Copter cannot fly answered by stopping where the vehicle is
//! (Copter re-enters GUIDED's hold) rather than by a refusal. Pure.

use mavlink::dialects::ardupilotmega::{
    MavFrame, PositionTargetTypemask, SET_ATTITUDE_TARGET_DATA, SET_POSITION_TARGET_GLOBAL_INT_DATA,
    SET_POSITION_TARGET_LOCAL_NED_DATA,
};

use crate::commander::{Lean, Request};
use crate::control::{AttitudeTarget, FlatSetpoint};
use crate::math::wrap_pi;
use crate::mav::ingest::Action;
use crate::mav::offboard::{decode_attitude_target, decode_global_target, decode_local_target, DecodedOffboard};
use crate::telemetry::Snapshot;

/// The type-mask bits of the position, the acceleration, the force flag and the yaw.
const IGNORE_POS: u16 = 0b111;
const IGNORE_ACC: u16 = 0b111 << 6;
const FORCE: u16 = 1 << 9;
const IGNORE_YAW: u16 = 1 << 10;

/// GUIDED's hold where the vehicle is: a target of position alone (it persists), at its heading.
fn stop(state: &Snapshot) -> Action {
    Action::Request(Request::offboard(FlatSetpoint {
        pos_w: Some(state.pos_w),
        yaw_rad: Some(state.eta.z),
        ..Default::default()
    }))
}

/// The request a decoded target is, or the stop Copter makes of one it cannot fly.
fn fly(decoded: Result<DecodedOffboard, String>, state: &Snapshot) -> Action {
    match decoded {
        Ok(target) => Action::Request(Request::OffboardSetpoint {
            setpoint: target.setpoint,
            body_frame: target.body_frame,
        }),
        Err(_) => stop(state),
    }
}

/// The mask without the force flag when the acceleration is ignored (Copter reads the flag only
/// with an acceleration); `None` for a force target, which Copter cannot fly.
fn copter_mask(mask: u16) -> Option<u16> {
    match (mask & FORCE != 0, mask & IGNORE_ACC == IGNORE_ACC) {
        (true, true) => Some(mask & !FORCE),
        (true, false) => None,
        (false, _) => Some(mask),
    }
}

/// SET_POSITION_TARGET_LOCAL_NED in GUIDED, in `state`: turned into a LOCAL_NED target (offsets
/// added to the vehicle's position; body frames turned by its heading ψ: x_n = x cos ψ − y sin ψ,
/// y_e = x sin ψ + y cos ψ, for positions, velocities and accelerations; their heading ψ + yaw),
/// then decoded as PX4's offboard decodes it.
#[allow(deprecated)] // MAV_FRAME_BODY_NED: the frame DroneKit's and MAVSDK's body targets use
pub fn copter_local_target(m: &SET_POSITION_TARGET_LOCAL_NED_DATA, state: &Snapshot) -> Action {
    let (offset, body) = match m.coordinate_frame {
        MavFrame::MAV_FRAME_LOCAL_NED => (false, false),
        MavFrame::MAV_FRAME_LOCAL_OFFSET_NED => (true, false),
        MavFrame::MAV_FRAME_BODY_NED | MavFrame::MAV_FRAME_BODY_OFFSET_NED => (true, true),
        _ => return stop(state),
    };
    let Some(mask) = copter_mask(m.type_mask.bits()) else {
        return stop(state);
    };
    let yaw = state.eta.z;
    let (s, c) = if body { yaw.sin_cos() } else { (0.0, 1.0) };
    let turn = |x: f32, y: f32| {
        let (x, y) = (f64::from(x), f64::from(y));
        ((c * x - s * y) as f32, (s * x + c * y) as f32)
    };
    let mut t = m.clone();
    t.coordinate_frame = MavFrame::MAV_FRAME_LOCAL_NED;
    t.type_mask = PositionTargetTypemask::from_bits_retain(mask);
    (t.x, t.y) = turn(m.x, m.y);
    (t.vx, t.vy) = turn(m.vx, m.vy);
    (t.afx, t.afy) = turn(m.afx, m.afy);
    if offset && mask & IGNORE_POS == 0 {
        t.x += state.pos_w.x as f32;
        t.y += state.pos_w.y as f32;
        t.z += state.pos_w.z as f32;
    }
    if body && mask & IGNORE_YAW == 0 {
        t.yaw = wrap_pi(yaw + f64::from(m.yaw)) as f32;
    }
    fly(decode_local_target(&t), state)
}

/// SET_POSITION_TARGET_GLOBAL_INT in GUIDED, in `state`: the force flag read as Copter reads it,
/// then decoded as PX4's offboard decodes it; what Copter cannot fly stops the vehicle.
pub fn copter_global_target(m: &SET_POSITION_TARGET_GLOBAL_INT_DATA, state: &Snapshot) -> Action {
    let Some(mask) = copter_mask(m.type_mask.bits()) else {
        return stop(state);
    };
    let t = SET_POSITION_TARGET_GLOBAL_INT_DATA {
        type_mask: PositionTargetTypemask::from_bits_retain(mask),
        ..m.clone()
    };
    fly(decode_global_target(&t, &state.home), state)
}

/// SET_ATTITUDE_TARGET in GUIDED, in `state`, as Copter reads it: an attitude with its thrust
/// read as a climb rate (0.5 holds the height, 1 climbs at `WPNAV_SPEED_UP`, 0 descends at
/// `WPNAV_SPEED_DN`: climb = 2 (thrust − 0.5)), flown as a lean ([`Request::GuidedLean`]); rates
/// alone as PX4's offboard flies them; one Copter cannot fly (a partial rate mask, a quaternion
/// that is no rotation, no thrust) stops the vehicle where it is, silently, as Copter does.
pub fn copter_attitude_target(m: &SET_ATTITUDE_TARGET_DATA, state: &Snapshot) -> Action {
    match decode_attitude_target(m) {
        Ok(AttitudeTarget {
            q_wb: Some(q),
            thrust_fraction,
            ..
        }) => {
            let (roll_rad, pitch_rad, yaw_rad) = q.euler_angles();
            Action::Request(Request::GuidedLean(Lean {
                roll_rad,
                pitch_rad,
                yaw_rad,
                climb: 2.0 * (thrust_fraction - 0.5),
            }))
        }
        Ok(rates) => Action::Request(Request::OffboardAttitude(rates)),
        Err(_) => stop(state),
    }
}

#[cfg(test)]
#[allow(deprecated)] // the body frames DroneKit sends
mod tests {
    use super::*;
    use crate::guidance::Home;
    use crate::math::Vec3;

    fn state() -> Snapshot {
        let mut s = Snapshot::initial(Home::default());
        s.pos_w = Vec3::new(10.0, 5.0, -20.0);
        s.eta.z = std::f64::consts::FRAC_PI_2; // facing east
        s
    }

    fn setpoint(action: Action) -> FlatSetpoint {
        match action {
            Action::Request(Request::OffboardSetpoint {
                setpoint,
                body_frame: false,
            }) => setpoint,
            other => panic!("{other:?}"),
        }
    }

    fn local(frame: MavFrame, mask: u16, xyz: [f32; 3], v: [f32; 3]) -> SET_POSITION_TARGET_LOCAL_NED_DATA {
        SET_POSITION_TARGET_LOCAL_NED_DATA {
            coordinate_frame: frame,
            type_mask: PositionTargetTypemask::from_bits_retain(mask),
            x: xyz[0],
            y: xyz[1],
            z: xyz[2],
            vx: v[0],
            vy: v[1],
            vz: v[2],
            target_system: 1,
            ..Default::default()
        }
    }

    #[test]
    fn dronekits_position_mask_with_the_force_bit_flies_and_offsets_add_the_vehicle() {
        // DroneKit's goto_position_target_local_ned: 0b0000111111111000, force bit set.
        let sp = setpoint(copter_local_target(
            &local(MavFrame::MAV_FRAME_LOCAL_NED, 0x0FF8, [3.0, 4.0, -10.0], [0.0; 3]),
            &state(),
        ));
        assert_eq!(sp.pos_w, Some(Vec3::new(3.0, 4.0, -10.0)));
        let sp = setpoint(copter_local_target(
            &local(MavFrame::MAV_FRAME_LOCAL_OFFSET_NED, 0x0FF8, [1.0, 0.0, -2.0], [0.0; 3]),
            &state(),
        ));
        let p = sp.pos_w.unwrap_or_default();
        assert!((p - Vec3::new(11.0, 5.0, -22.0)).norm() < 1e-5, "{p:?}");
    }

    #[test]
    fn body_frames_turn_by_the_heading() {
        // 2 m ahead of a vehicle facing east is 2 m east of it; 1 m/s forward is 1 m/s east.
        let sp = setpoint(copter_local_target(
            &local(MavFrame::MAV_FRAME_BODY_OFFSET_NED, 0x0FF8, [2.0, 0.0, 0.0], [0.0; 3]),
            &state(),
        ));
        let p = sp.pos_w.unwrap_or_default();
        assert!((p - Vec3::new(10.0, 7.0, -20.0)).norm() < 1e-5, "{p:?}");
        let sp = setpoint(copter_local_target(
            &local(MavFrame::MAV_FRAME_BODY_NED, 0x0FC7, [0.0; 3], [1.0, 0.0, 0.0]),
            &state(),
        ));
        let v = sp.vel_w.unwrap_or_default();
        assert!((v - Vec3::new(0.0, 1.0, 0.0)).norm() < 1e-6, "{v:?}");
    }

    #[test]
    fn an_attitude_target_copter_cannot_fly_stops_the_vehicle_silently() {
        // DroneKit's set_attitude_target sends type_mask 0b100: only the yaw rate ignored.
        let partial = SET_ATTITUDE_TARGET_DATA {
            type_mask: mavlink::dialects::ardupilotmega::AttitudeTargetTypemask::from_bits_retain(0b100),
            q: [1.0, 0.0, 0.0, 0.0],
            thrust: 0.5,
            target_system: 1,
            ..Default::default()
        };
        let sp = setpoint(copter_attitude_target(&partial, &state()));
        assert_eq!(sp.pos_w, Some(state().pos_w));
    }

    #[test]
    fn an_attitude_target_is_a_lean_whose_thrust_is_a_climb_rate() {
        let pitch_forward = crate::math::UnitQuat::from_euler_angles(0.0, -0.1, 1.0);
        let q = pitch_forward.coords;
        let m = SET_ATTITUDE_TARGET_DATA {
            type_mask: mavlink::dialects::ardupilotmega::AttitudeTargetTypemask::from_bits_retain(0b111),
            q: [q.w as f32, q.x as f32, q.y as f32, q.z as f32],
            thrust: 0.7,
            target_system: 1,
            ..Default::default()
        };
        let Action::Request(Request::GuidedLean(lean)) = copter_attitude_target(&m, &state()) else {
            panic!("not a lean");
        };
        assert!(
            (lean.pitch_rad + 0.1).abs() < 1e-6 && (lean.yaw_rad - 1.0).abs() < 1e-6,
            "{lean:?}"
        );
        assert!((lean.climb - 0.4).abs() < 1e-6, "thrust 0.7 is 40 % of the climb speed");
    }

    #[test]
    fn what_copter_cannot_fly_stops_the_vehicle_where_it_is() {
        let s = state();
        for bad in [
            local(MavFrame::MAV_FRAME_GLOBAL, 0x0FF8, [1.0; 3], [0.0; 3]),
            local(MavFrame::MAV_FRAME_LOCAL_NED, 0x0E38, [0.0; 3], [0.0; 3]),
        ] {
            let sp = setpoint(copter_local_target(&bad, &s));
            assert_eq!((sp.pos_w, sp.vel_w), (Some(s.pos_w), None));
        }
    }
}
