//! ArduCopter's own telemetry from a [`Snapshot`] (docs/mavlink.md §5.1): the messages of its
//! stream groups that PX4 never sends (RAW_IMU, POWER_STATUS, MEMINFO, NAV_CONTROLLER_OUTPUT,
//! POSITION_TARGET_GLOBAL_INT, SIMSTATE, AHRS2, AHRS, VIBRATION), filled from what
//! the snapshot has (RC_CHANNELS is the RC receiver's, `copter_rc`); the figures it has not are constants or zeros, each said where it is built.
//! Pure.

use mavlink::dialects::ardupilotmega::{
    MavFrame, MavMessage, MavPowerStatus, PositionTargetTypemask, AHRS2_DATA, AHRS_DATA, MEMINFO_DATA,
    NAV_CONTROLLER_OUTPUT_DATA, POSITION_TARGET_GLOBAL_INT_DATA, POWER_STATUS_DATA, RAW_IMU_DATA, SIMSTATE_DATA,
    VIBRATION_DATA,
};

use crate::math::{euler_zyx, Vec3, GRAVITY_M_S2};
use crate::mav::stream_messages::{time_boot_ms, time_usec, TelemetryStream};
use crate::telemetry::Snapshot;

/// Standard gravity [m/s²]: the g of MAVLink's milli-g (RAW_IMU's accelerations).
const STANDARD_GRAVITY_M_S2: f64 = 9.80665;
/// Free memory MEMINFO reports [bytes]: a constant (nothing measures a heap), 128 KiB.
const FREE_MEMORY_BYTES: u32 = 128 * 1024;
/// Board supply POWER_STATUS reports [mV]: a constant 5 V (nothing is measured).
const BOARD_SUPPLY_MV: u16 = 5000;
/// POSITION_TARGET_TYPEMASK's upper four bits, which ArduCopter sets in POSITION_TARGET_GLOBAL_INT
/// (the spec names no flag there).
const TYPEMASK_LAST_BYTE: u16 = 0xF000;

impl TelemetryStream {
    /// ArduPilot's messages PX4 never sends: a PX4-faced link does not offer them.
    pub fn ardupilot_only(self) -> bool {
        matches!(
            self,
            TelemetryStream::RawImu
                | TelemetryStream::PowerStatus
                | TelemetryStream::Meminfo
                | TelemetryStream::NavControllerOutput
                | TelemetryStream::PositionTargetGlobal
                | TelemetryStream::RcChannels
                | TelemetryStream::Simstate
                | TelemetryStream::Ahrs2
                | TelemetryStream::Ahrs
                | TelemetryStream::Vibration
        )
    }
}

/// The message of an ArduPilot-only `stream` for snapshot `s`; `None` for the other streams and
/// when there is nothing to report (no position target, no simulator truth).
pub(in crate::mav) fn message(stream: TelemetryStream, s: &Snapshot) -> Option<MavMessage> {
    Some(match stream {
        TelemetryStream::RawImu => raw_imu(s),
        TelemetryStream::PowerStatus => power_status(),
        TelemetryStream::Meminfo => meminfo(),
        TelemetryStream::NavControllerOutput => nav_controller_output(s),
        TelemetryStream::PositionTargetGlobal => return position_target_global_int(s),
        TelemetryStream::Simstate => return simstate(s),
        TelemetryStream::Ahrs2 => ahrs2(s),
        TelemetryStream::Ahrs => ahrs(),
        TelemetryStream::Vibration => vibration(s),
        _ => return None,
    })
}

/// `v` rounded into an i16 (saturating).
fn i16_of(v: f64) -> i16 {
    v.round().clamp(f64::from(i16::MIN), f64::from(i16::MAX)) as i16
}

/// Latitude and longitude [1e-7 deg] and altitude AMSL [m] of the local NED point `pos_w` [m].
fn lat_lon_alt(s: &Snapshot, pos_w: &Vec3) -> (i32, i32, f64) {
    let (lat, lon, alt) = s.home.to_global(pos_w);
    ((lat * 1e7).round() as i32, (lon * 1e7).round() as i32, alt)
}

/// RAW_IMU as ArduPilot scales it: the accelerometer (the snapshot's specific force, body FRD)
/// [mG of standard gravity], the gyroscope (the body rates) [mrad/s], the magnetometer (the
/// reading, or without the sensor suite the fixed field of HIGHRES_IMU) [mgauss]; IMU 0, no
/// temperature (0: the spec's "not provided").
fn raw_imu(s: &Snapshot) -> MavMessage {
    let (mag_b, _, _) = crate::mav::nav_status::mag_and_baro(s);
    let mg = |a: f64| i16_of(a * 1000.0 / STANDARD_GRAVITY_M_S2);
    let milli = |v: f64| i16_of(v * 1000.0);
    MavMessage::RAW_IMU(RAW_IMU_DATA {
        time_usec: time_usec(s),
        xacc: mg(s.accel_b.x),
        yacc: mg(s.accel_b.y),
        zacc: mg(s.accel_b.z),
        xgyro: milli(s.omega_b.x),
        ygyro: milli(s.omega_b.y),
        zgyro: milli(s.omega_b.z),
        xmag: milli(mag_b.x),
        ymag: milli(mag_b.y),
        zmag: milli(mag_b.z),
        id: 0,
        temperature: 0,
    })
}

/// POWER_STATUS: constants, as nothing measures the board: a 5 V supply [mV], no servo rail
/// (0 mV), the main supply valid.
fn power_status() -> MavMessage {
    MavMessage::POWER_STATUS(POWER_STATUS_DATA {
        Vcc: BOARD_SUPPLY_MV,
        Vservo: 0,
        flags: MavPowerStatus::MAV_POWER_STATUS_BRICK_VALID,
    })
}

/// MEMINFO: a constant 128 KiB free [bytes] (`freemem` saturates at 65 535), no heap top.
fn meminfo() -> MavMessage {
    MavMessage::MEMINFO(MEMINFO_DATA {
        brkval: 0,
        freemem: FREE_MEMORY_BYTES.min(u32::from(u16::MAX)) as u16,
        freemem32: FREE_MEMORY_BYTES,
    })
}

/// NAV_CONTROLLER_OUTPUT as ArduCopter fills it: the roll, pitch and heading the attitude
/// controller aims for [deg] (without a controller running, the attitude held); towards the
/// setpoint's position, when it has one, the bearing [deg, 0..360), the horizontal distance [m]
/// and the altitude error (target above the vehicle positive) [m], else 0; no airspeed or
/// cross-track error (0).
fn nav_controller_output(s: &Snapshot) -> MavMessage {
    let eta = s.eta_desired.unwrap_or(s.eta);
    let (bearing_deg, dist_m, alt_error_m) = match s.setpoint.and_then(|sp| sp.pos_w) {
        Some(target) => {
            let d = target - s.pos_w;
            let bearing = d.y.atan2(d.x).to_degrees().rem_euclid(360.0);
            (bearing, d.xy().norm(), -d.z)
        }
        None => (0.0, 0.0, 0.0),
    };
    let yaw_deg = eta.z.sin().atan2(eta.z.cos()).to_degrees();
    MavMessage::NAV_CONTROLLER_OUTPUT(NAV_CONTROLLER_OUTPUT_DATA {
        nav_roll: eta.x.to_degrees() as f32,
        nav_pitch: eta.y.to_degrees() as f32,
        alt_error: alt_error_m as f32,
        aspd_error: 0.0,
        xtrack_error: 0.0,
        nav_bearing: i16_of(yaw_deg),
        target_bearing: i16_of(bearing_deg) % 360,
        wp_dist: dist_m.round().clamp(0.0, f64::from(u16::MAX)) as u16,
    })
}

/// POSITION_TARGET_GLOBAL_INT as ArduCopter sends it: only while the setpoint has a position,
/// that position as latitude, longitude [1e-7 deg] and altitude AMSL [m] (MAV_FRAME_GLOBAL),
/// every other field ignored (type mask: velocity, acceleration, yaw and yaw rate ignored, with
/// the upper four bits ArduCopter sets) and 0.
fn position_target_global_int(s: &Snapshot) -> Option<MavMessage> {
    let target = s.setpoint?.pos_w?;
    let (lat_int, lon_int, alt) = lat_lon_alt(s, &target);
    let ignored = PositionTargetTypemask::POSITION_TARGET_TYPEMASK_VX_IGNORE
        | PositionTargetTypemask::POSITION_TARGET_TYPEMASK_VY_IGNORE
        | PositionTargetTypemask::POSITION_TARGET_TYPEMASK_VZ_IGNORE
        | PositionTargetTypemask::POSITION_TARGET_TYPEMASK_AX_IGNORE
        | PositionTargetTypemask::POSITION_TARGET_TYPEMASK_AY_IGNORE
        | PositionTargetTypemask::POSITION_TARGET_TYPEMASK_AZ_IGNORE
        | PositionTargetTypemask::POSITION_TARGET_TYPEMASK_YAW_IGNORE
        | PositionTargetTypemask::POSITION_TARGET_TYPEMASK_YAW_RATE_IGNORE;
    Some(MavMessage::POSITION_TARGET_GLOBAL_INT(
        POSITION_TARGET_GLOBAL_INT_DATA {
            time_boot_ms: time_boot_ms(s),
            lat_int,
            lon_int,
            alt: alt as f32,
            type_mask: PositionTargetTypemask::from_bits_retain(ignored.bits() | TYPEMASK_LAST_BYTE),
            coordinate_frame: MavFrame::MAV_FRAME_GLOBAL,
            ..Default::default()
        },
    ))
}

/// SIMSTATE, the simulator's truth as ArduPilot SITL sends it: the true roll, pitch, yaw [rad],
/// the true specific force in the body FRD frame (what a perfect accelerometer reads:
/// R_wbᵀ (a_w − g e_z)) [m/s²], the true body rates [rad/s], the true latitude and longitude
/// [1e-7 deg]; none without a truth (before the first tick).
fn simstate(s: &Snapshot) -> Option<MavMessage> {
    let t = s.truth?;
    let eta = euler_zyx(&t.q_wb.to_rotation_matrix().into_inner());
    let f_b = t.q_wb.inverse() * (t.accel_w - Vec3::new(0.0, 0.0, GRAVITY_M_S2));
    let (lat, lng, _) = lat_lon_alt(s, &t.pos_w);
    Some(MavMessage::SIMSTATE(SIMSTATE_DATA {
        roll: eta.x as f32,
        pitch: eta.y as f32,
        yaw: eta.z as f32,
        xacc: f_b.x as f32,
        yacc: f_b.y as f32,
        zacc: f_b.z as f32,
        xgyro: t.omega_b.x as f32,
        ygyro: t.omega_b.y as f32,
        zgyro: t.omega_b.z as f32,
        lat,
        lng,
    }))
}

/// AHRS2 (ArduPilot's second estimator; here the one estimate): roll, pitch, yaw [rad], altitude
/// AMSL [m], latitude and longitude [1e-7 deg] of the estimated state.
fn ahrs2(s: &Snapshot) -> MavMessage {
    let (lat, lng, alt) = lat_lon_alt(s, &s.pos_w);
    MavMessage::AHRS2(AHRS2_DATA {
        roll: s.eta.x as f32,
        pitch: s.eta.y as f32,
        yaw: s.eta.z as f32,
        altitude: alt as f32,
        lat,
        lng,
    })
}

/// AHRS: ArduPilot's DCM figures (gyro drift [rad/s], accelerometer weight, renormalisation,
/// roll-pitch and yaw errors); no DCM runs here, so every one is 0.
fn ahrs() -> MavMessage {
    MavMessage::AHRS(AHRS_DATA::default())
}

/// VIBRATION: the accelerometer's vibration levels [m/s²] and clipping counts; the snapshot
/// carries no accelerometer history to measure them, so 0 (a vibration-free vehicle).
fn vibration(s: &Snapshot) -> MavMessage {
    MavMessage::VIBRATION(VIBRATION_DATA {
        time_usec: time_usec(s),
        ..Default::default()
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::commander::LandedState;
    use crate::control::FlatSetpoint;
    use crate::guidance::Home;
    use crate::math::UnitQuat;
    use crate::sitl::PlantTruth;

    fn snapshot() -> Snapshot {
        Snapshot {
            t_s: 12.345,
            pos_w: Vec3::new(10.0, -5.0, -2.5),
            vel_w: Vec3::new(0.5, 0.0, -0.25),
            eta: Vec3::new(0.1, -0.2, -1.0),
            omega_b: Vec3::new(0.01, 0.02, -0.03),
            accel_b: Vec3::new(0.0, 0.0, -9.81),
            armed: true,
            landed: LandedState::InAir,
            ..Snapshot::initial(Home::default())
        }
    }

    fn build(stream: TelemetryStream, s: &Snapshot) -> MavMessage {
        match message(stream, s) {
            Some(m) => m,
            None => panic!("no {stream:?}"),
        }
    }

    #[test]
    fn only_the_ardupilot_streams_are_built_here() {
        let s = snapshot();
        for stream in TelemetryStream::ALL {
            let built = message(stream, &s).is_some();
            let expected = stream.ardupilot_only()
                && !matches!(
                    stream,
                    TelemetryStream::PositionTargetGlobal | TelemetryStream::Simstate | TelemetryStream::RcChannels
                );
            assert_eq!(built, expected, "{stream:?}");
        }
    }

    #[test]
    fn ahrs2_is_the_estimate_placed_about_home() {
        let MavMessage::AHRS2(a) = build(TelemetryStream::Ahrs2, &snapshot()) else {
            panic!("wrong message");
        };
        assert!((a.altitude - 490.5).abs() < 1e-3, "488 m AMSL home, 2.5 m up");
        assert_eq!(a.lat, 473_978_319, "10 m north of 47.397742°");
        assert_eq!(a.lng, 85_455_276, "5 m west of 8.545594°");
        assert_eq!((a.roll, a.pitch, a.yaw), (0.1, -0.2, -1.0));
    }

    #[test]
    fn raw_imu_is_scaled_as_ardupilot_scales_it() {
        let MavMessage::RAW_IMU(r) = build(TelemetryStream::RawImu, &snapshot()) else {
            panic!("wrong message");
        };
        assert_eq!((r.xacc, r.yacc, r.zacc), (0, 0, -1000), "−9.81 m/s² is −1000 mG");
        assert_eq!((r.xgyro, r.ygyro, r.zgyro), (10, 20, -30), "mrad/s");
        assert_eq!(r.time_usec, 12_345_000);
        // The fixed field about Zürich, rotated into the body: 0.479 gauss in all.
        let norm = [r.xmag, r.ymag, r.zmag]
            .iter()
            .map(|m| f64::from(*m).powi(2))
            .sum::<f64>()
            .sqrt();
        assert!((norm - 478.8).abs() < 1.0, "{norm} mgauss");
    }

    #[test]
    fn navigation_output_and_position_target_follow_the_setpoint() {
        let s = Snapshot {
            setpoint: Some(FlatSetpoint::hold(Vec3::new(40.0, 25.0, -12.5), 0.5)),
            eta_desired: Some(Vec3::new(0.05, -0.1, 3.5)),
            ..snapshot()
        };
        let MavMessage::NAV_CONTROLLER_OUTPUT(n) = build(TelemetryStream::NavControllerOutput, &s) else {
            panic!("wrong message");
        };
        assert_eq!(n.wp_dist, 42, "30 m north, 30 m east");
        assert_eq!(n.target_bearing, 45);
        assert!((n.alt_error - 10.0).abs() < 1e-6, "target 10 m above");
        assert!((n.nav_roll - 2.8648).abs() < 1e-3);
        assert_eq!(n.nav_bearing, -159, "3.5 rad wrapped to −159°");
        let MavMessage::POSITION_TARGET_GLOBAL_INT(p) = build(TelemetryStream::PositionTargetGlobal, &s) else {
            panic!("wrong message");
        };
        assert_eq!(p.coordinate_frame, MavFrame::MAV_FRAME_GLOBAL);
        assert_eq!(p.type_mask.bits(), 0xFDF8, "position only, upper bits set");
        assert!((p.alt - 500.5).abs() < 1e-3, "AMSL");
        assert!(p.lat_int > 473_977_420 && p.lon_int > 85_455_940);
        assert!(
            message(TelemetryStream::PositionTargetGlobal, &snapshot()).is_none(),
            "no target"
        );
        let MavMessage::NAV_CONTROLLER_OUTPUT(idle) = build(TelemetryStream::NavControllerOutput, &snapshot()) else {
            panic!("wrong message");
        };
        assert_eq!((idle.wp_dist, idle.alt_error), (0, 0.0));
        assert!((idle.nav_pitch + 11.459).abs() < 1e-3, "the attitude held");
    }

    #[test]
    fn simstate_is_the_truth_not_the_estimate() {
        assert!(
            message(TelemetryStream::Simstate, &snapshot()).is_none(),
            "no truth yet"
        );
        let q = UnitQuat::from_euler_angles(0.0, 0.0, std::f64::consts::FRAC_PI_2);
        let s = Snapshot {
            truth: Some(PlantTruth {
                pos_w: Vec3::new(0.0, 100.0, -3.0),
                vel_w: Vec3::zeros(),
                q_wb: q,
                omega_b: Vec3::new(0.0, 0.0, 0.2),
                on_ground: false,
                external_force_w: Vec3::zeros(),
                external_torque_b: Vec3::zeros(),
                accel_w: Vec3::new(1.0, 0.0, 0.0),
                wind_w: Vec3::zeros(),
                drag_force_w: Vec3::zeros(),
            }),
            ..snapshot()
        };
        let MavMessage::SIMSTATE(t) = build(TelemetryStream::Simstate, &s) else {
            panic!("wrong message");
        };
        assert!((f64::from(t.yaw) - std::f64::consts::FRAC_PI_2).abs() < 1e-6);
        assert!(t.roll.abs() < 1e-6, "the truth's attitude, not the estimate's 0.1 rad");
        // Facing east, accelerating north: the specific force points to the body's left.
        assert!(t.xacc.abs() < 1e-6 && (t.yacc + 1.0).abs() < 1e-6);
        assert!((f64::from(t.zacc) + GRAVITY_M_S2).abs() < 1e-5);
        assert_eq!(t.zgyro, 0.2);
        assert_eq!(t.lat, 473_977_420);
        assert_eq!(t.lng, 85_469_226, "100 m east");
    }

    #[test]
    fn vfr_hud_heading_is_zero_to_360_and_altitude_amsl() {
        for (yaw, heading) in [(-1.0, 302), (0.0, 0), (3.1, 177), (-3.1, 182), (-1e-9, 0)] {
            let s = Snapshot {
                eta: Vec3::new(0.0, 0.0, yaw),
                thrust_fraction: 0.456,
                ..snapshot()
            };
            let Some(MavMessage::VFR_HUD(v)) = crate::mav::stream_messages::message(TelemetryStream::VfrHud, &s) else {
                panic!("wrong message");
            };
            assert_eq!(v.heading, heading, "yaw {yaw} rad");
            assert_eq!(v.throttle, 46, "%");
            assert!((v.alt - 490.5).abs() < 1e-3, "AMSL");
        }
    }

    #[test]
    fn constants_and_absent_hardware_are_reported_plainly() {
        let s = snapshot();
        assert_eq!(message(TelemetryStream::RcChannels, &s), None, "the RC receiver's");
        let MavMessage::MEMINFO(m) = build(TelemetryStream::Meminfo, &s) else {
            panic!("wrong message");
        };
        assert_eq!((m.freemem, m.freemem32), (65_535, 131_072));
        let MavMessage::POWER_STATUS(p) = build(TelemetryStream::PowerStatus, &s) else {
            panic!("wrong message");
        };
        assert_eq!(p.Vcc, 5000);
        let MavMessage::VIBRATION(v) = build(TelemetryStream::Vibration, &s) else {
            panic!("wrong message");
        };
        assert_eq!((v.vibration_z, v.clipping_0, v.time_usec), (0.0, 0, 12_345_000));
        assert!(matches!(build(TelemetryStream::Ahrs, &s), MavMessage::AHRS(_)));
    }
}
