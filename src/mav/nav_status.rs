//! What the navigation tells ground stations (docs/mavlink.md §4): GPS_RAW_INT from the GPS
//! reading, ESTIMATOR_STATUS from the navigation filter, HIGHRES_IMU and SCALED_PRESSURE from the
//! raw sensors. With the state sensor (no sensor suite) GPS_RAW_INT reports the estimate as a
//! perfect 3D fix and ESTIMATOR_STATUS every estimate good. Pure.

use mavlink::dialects::ardupilotmega::{
    EkfStatusFlags, EstimatorStatusFlags, GpsFixType, HighresImuUpdatedFlags, MavMessage, EKF_STATUS_REPORT_DATA,
    ESTIMATOR_STATUS_DATA, GPS_RAW_INT_DATA, HIGHRES_IMU_DATA, HIL_STATE_QUATERNION_DATA, SCALED_PRESSURE_DATA,
};

use crate::math::Vec3;
use crate::telemetry::Snapshot;

/// GPS_RAW_INT: the latest GPS reading (position as latitude, longitude and altitude AMSL about
/// home, the same altitude above the ellipsoid as PX4 SITL reports it, accuracies, speed and
/// course, fix and satellites); without a GPS, the estimate. A receiver silent for a second is
/// reported as PX4 does: no fix, accuracies, speed and course unknown (65535), satellites 255.
pub(super) fn gps_raw_int(s: &Snapshot) -> MavMessage {
    let time_usec = super::stream_messages::time_usec(s);
    if s.nav.gps.is_some_and(|g| g.silent) {
        return MavMessage::GPS_RAW_INT(GPS_RAW_INT_DATA {
            time_usec,
            fix_type: GpsFixType::GPS_FIX_TYPE_NO_GPS,
            eph: u16::MAX,
            epv: u16::MAX,
            vel: u16::MAX,
            cog: u16::MAX,
            satellites_visible: u8::MAX,
            ..Default::default()
        });
    }
    let (pos_w, vel_w, (h_acc, v_acc), speed_acc, fix, sats) = match s.nav.gps {
        Some(g) => (
            g.pos_w,
            g.vel_w,
            g.acc_m,
            g.speed_acc_m_s,
            if g.fix_3d {
                GpsFixType::GPS_FIX_TYPE_3D_FIX
            } else {
                GpsFixType::GPS_FIX_TYPE_NO_FIX
            },
            g.satellites,
        ),
        None => (s.pos_w, s.vel_w, (0.8, 1.2), 0.2, GpsFixType::GPS_FIX_TYPE_3D_FIX, 12),
    };
    let (lat, lon, alt) = s.home.to_global(&pos_w);
    let mm = |m: f64| (m * 1000.0).round().clamp(0.0, f64::from(u32::MAX)) as u32;
    MavMessage::GPS_RAW_INT(GPS_RAW_INT_DATA {
        time_usec,
        lat: (lat * 1e7).round() as i32,
        lon: (lon * 1e7).round() as i32,
        alt: (alt * 1000.0).round() as i32,
        eph: (h_acc * 100.0).round().clamp(0.0, 65_534.0) as u16,
        epv: (v_acc * 100.0).round().clamp(0.0, 65_534.0) as u16,
        vel: (vel_w.xy().norm() * 100.0).round().clamp(0.0, 65_534.0) as u16,
        cog: course_cdeg(&vel_w),
        fix_type: fix,
        satellites_visible: sats,
        alt_ellipsoid: (alt * 1000.0).round() as i32,
        h_acc: mm(h_acc),
        v_acc: mm(v_acc),
        vel_acc: mm(speed_acc),
        ..Default::default()
    })
}

/// Course over ground [cdeg], UINT16_MAX when not moving.
fn course_cdeg(vel_w: &Vec3) -> u16 {
    if vel_w.xy().norm() < 0.1 {
        return u16::MAX;
    }
    (vel_w.y.atan2(vel_w.x).to_degrees().rem_euclid(360.0) * 100.0).round() as u16 % 36000
}

/// ESTIMATOR_STATUS: the filter's validity flags, test ratios and accuracies (PX4's message);
/// with the state sensor every estimate good and every ratio 0.
pub(super) fn estimator_status(s: &Snapshot) -> MavMessage {
    let time_usec = super::stream_messages::time_usec(s);
    let Some(f) = s.nav.filter else {
        return MavMessage::ESTIMATOR_STATUS(ESTIMATOR_STATUS_DATA {
            time_usec,
            flags: EstimatorStatusFlags::from_bits_truncate(0x3FF & !0x80),
            ..Default::default()
        });
    };
    let [vel, pos_h, pos_v, mag, _height] = f.test_ratios.map(|r| r as f32);
    MavMessage::ESTIMATOR_STATUS(ESTIMATOR_STATUS_DATA {
        time_usec,
        vel_ratio: vel,
        pos_horiz_ratio: pos_h,
        pos_vert_ratio: pos_v,
        mag_ratio: mag,
        hagl_ratio: 0.0,
        tas_ratio: 0.0,
        pos_horiz_accuracy: f.pos_std_m.0 as f32,
        pos_vert_accuracy: f.pos_std_m.1 as f32,
        flags: EstimatorStatusFlags::from_bits_truncate(f.flags),
    })
}

/// The magnetometer [gauss] and barometer (pressure [hPa], temperature [°C]) of HIGHRES_IMU: the
/// readings, or without the sensor suite a fixed Earth field about Zürich rotated into the body
/// and the ISA pressure at the estimated altitude.
pub(super) fn mag_and_baro(s: &Snapshot) -> (Vec3, f64, f64) {
    let mag_b = s.nav.mag_b.unwrap_or_else(|| {
        let mag_w = Vec3::new(0.21, 0.015, 0.43);
        crate::math::UnitQuat::from_euler_angles(s.eta.x, s.eta.y, s.eta.z).inverse() * mag_w
    });
    let (pressure_hpa, temperature_c) = match s.nav.baro {
        Some((pa, c)) => (pa / 100.0, c),
        None => {
            let alt = s.home.to_global(&s.pos_w).2;
            (1013.25 * (1.0 - 2.25577e-5 * alt).powf(5.25588), 20.0)
        }
    };
    (mag_b, pressure_hpa, temperature_c)
}

/// HIGHRES_IMU: the accelerometer (specific force), the gyroscope, the magnetometer and the
/// barometer, with the fields that are new marked.
pub(super) fn highres_imu(s: &Snapshot) -> MavMessage {
    let time_usec = super::stream_messages::time_usec(s);
    let (mag_b, pressure_hpa, temperature) = mag_and_baro(s);
    let alt = s.home.to_global(&s.pos_w).2;
    MavMessage::HIGHRES_IMU(HIGHRES_IMU_DATA {
        time_usec,
        xacc: s.accel_b.x as f32,
        yacc: s.accel_b.y as f32,
        zacc: s.accel_b.z as f32,
        xgyro: s.omega_b.x as f32,
        ygyro: s.omega_b.y as f32,
        zgyro: s.omega_b.z as f32,
        xmag: mag_b.x as f32,
        ymag: mag_b.y as f32,
        zmag: mag_b.z as f32,
        abs_pressure: pressure_hpa as f32,
        pressure_alt: alt as f32,
        temperature: temperature as f32,
        fields_updated: highres_imu_updated(s),
        ..Default::default()
    })
}

/// HIGHRES_IMU's `fields_updated`, as PX4 sets it: accelerometer and gyroscope (bits 0–5) with
/// every new IMU sample, magnetometer (6–8) and barometer (9, 11, 12: pressure, pressure
/// altitude, temperature) only when they delivered since the last message; no differential
/// pressure (bit 10) without an airspeed sensor.
fn highres_imu_updated(s: &Snapshot) -> HighresImuUpdatedFlags {
    let fresh = s.nav.fresh;
    let mut bits = 0u16;
    for (on, mask) in [(fresh.imu, 0x003F), (fresh.mag, 0x01C0), (fresh.baro, 0x1A00)] {
        if on {
            bits |= mask;
        }
    }
    HighresImuUpdatedFlags::from_bits_truncate(bits)
}

/// SCALED_PRESSURE: the barometer's pressure [hPa] and temperature [cdegC]; none while it is
/// silent (PX4 sends it on each new reading).
pub(super) fn scaled_pressure(s: &Snapshot) -> Option<MavMessage> {
    if !s.nav.fresh.baro_alive {
        return None;
    }
    let (_, pressure_hpa, temperature_c) = mag_and_baro(s);
    Some(MavMessage::SCALED_PRESSURE(SCALED_PRESSURE_DATA {
        time_boot_ms: super::stream_messages::time_boot_ms(s),
        press_abs: pressure_hpa as f32,
        temperature: (temperature_c * 100.0).round() as i16,
        ..Default::default()
    }))
}

/// HIL_STATE_QUATERNION: the simulator's truth (simulation only), filled as PX4 SITL fills it
/// (position as latitude, longitude [degE7] and altitude AMSL [mm] about the start, velocity
/// [cm/s], attitude and body rates, acceleration in whole m/s² where MAVLink says mG, no
/// airspeeds, no time stamp); none without a truth.
pub(super) fn ground_truth(s: &Snapshot) -> Option<MavMessage> {
    let t = s.truth?;
    let (lat, lon, alt) = s.home.to_global(&t.pos_w);
    let cm_s = |v: f64| (v * 100.0).round().clamp(f64::from(i16::MIN), f64::from(i16::MAX)) as i16;
    let acc_b = t.q_wb.inverse() * t.accel_w;
    let whole = |v: f64| v.trunc().clamp(f64::from(i16::MIN), f64::from(i16::MAX)) as i16;
    Some(MavMessage::HIL_STATE_QUATERNION(HIL_STATE_QUATERNION_DATA {
        time_usec: 0,
        attitude_quaternion: [t.q_wb.w as f32, t.q_wb.i as f32, t.q_wb.j as f32, t.q_wb.k as f32],
        rollspeed: t.omega_b.x as f32,
        pitchspeed: t.omega_b.y as f32,
        yawspeed: t.omega_b.z as f32,
        lat: (lat * 1e7).round() as i32,
        lon: (lon * 1e7).round() as i32,
        alt: (alt * 1000.0).round() as i32,
        vx: cm_s(t.vel_w.x),
        vy: cm_s(t.vel_w.y),
        vz: cm_s(t.vel_w.z),
        ind_airspeed: 0,
        true_airspeed: 0,
        xacc: whole(acc_b.x),
        yacc: whole(acc_b.y),
        zacc: whole(acc_b.z),
    }))
}

/// EKF_STATUS_REPORT (`ardupilotmega`) as ArduPilot fills it: the flags (the same bits as
/// ESTIMATOR_STATUS's) and, for velocity, horizontal position, vertical position and compass, the
/// square root of the test ratio ν² / (gate² S), which ground stations show against 0.5
/// (warning) and 0.8 (bad); terrain and airspeed 0 (not estimated). With the state sensor every
/// flag good and every value 0.
pub(super) fn ekf_status_report(s: &Snapshot) -> MavMessage {
    let (flags, [vel, pos_h, pos_v, mag, _height]) = match s.nav.filter {
        Some(f) => (f.flags, f.test_ratios.map(|r| r.max(0.0).sqrt() as f32)),
        None => (0x3FF & !0x80, [0.0; 5]),
    };
    MavMessage::EKF_STATUS_REPORT(EKF_STATUS_REPORT_DATA {
        velocity_variance: vel,
        pos_horiz_variance: pos_h,
        pos_vert_variance: pos_v,
        compass_variance: mag,
        terrain_alt_variance: 0.0,
        flags: EkfStatusFlags::from_bits_retain(flags),
        airspeed_variance: 0.0,
    })
}
