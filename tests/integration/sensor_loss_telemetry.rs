//! What a ground station is told when a simulated sensor goes silent and comes back (issue: after
//! MAV_CMD_INJECT_FAILURE GPS OFF, GPS_RAW_INT went on repeating its last fix and SYS_STATUS kept
//! the GPS healthy). Every message that reports a sensor is built from the vehicle's snapshot as
//! the links send it: GPS_RAW_INT, SYS_STATUS's present / enabled / health bits, HIGHRES_IMU's
//! `fields_updated`, SCALED_PRESSURE, ESTIMATOR_STATUS's flags.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::runtime_vehicle::{vehicle, DT_S};
use mavlink::dialects::ardupilotmega::{GpsFixType, HighresImuUpdatedFlags, MavMessage, MavSysStatusSensor};
use rotorpilot::lockstep::ScheduledSensorFailure;
use rotorpilot::mav::stream_messages::{message, TelemetryStream};
use rotorpilot::runtime::vehicle::Vehicle;
use rotorpilot::sitl::SensorModel;
use rotorpilot::telemetry::Snapshot;

/// quad_x on the default sensors, seed 2, ready to arm on the ground.
fn ready() -> Vehicle {
    let mut v = vehicle("quad_x", SensorModel::Suite, 2, &[]);
    run(&mut v, 10.0);
    v
}

fn run(v: &mut Vehicle, seconds: f64) -> Snapshot {
    let mut last = None;
    for _ in 0..(seconds / DT_S) as usize {
        last = Some(v.step().snapshot);
    }
    last.unwrap()
}

fn set(v: &mut Vehicle, unit: &str, kind: &str) {
    let at = v.time_s();
    v.schedule_sensor_failure(format!("{unit}:{kind}@{at}").parse::<ScheduledSensorFailure>().unwrap());
}

/// SYS_STATUS's (present, enabled, healthy) for `bit`.
fn sys_status(s: &Snapshot, bit: MavSysStatusSensor) -> (bool, bool, bool) {
    let Some(MavMessage::SYS_STATUS(m)) = message(TelemetryStream::SysStatus, s) else {
        panic!("no SYS_STATUS")
    };
    (
        m.onboard_control_sensors_present.contains(bit),
        m.onboard_control_sensors_enabled.contains(bit),
        m.onboard_control_sensors_health.contains(bit),
    )
}

fn highres_updated(s: &Snapshot) -> HighresImuUpdatedFlags {
    let Some(MavMessage::HIGHRES_IMU(m)) = message(TelemetryStream::HighresImu, s) else {
        panic!("no HIGHRES_IMU")
    };
    m.fields_updated
}

const MAG_BITS: u16 = 0x01C0;
const BARO_BITS: u16 = 0x1A00;

#[test]
fn a_silent_gps_is_reported_lost_and_back() {
    let mut v = ready();
    let s = run(&mut v, 0.1);
    let Some(MavMessage::GPS_RAW_INT(g)) = message(TelemetryStream::GpsRawInt, &s) else {
        panic!()
    };
    assert_eq!(
        (g.fix_type, g.satellites_visible),
        (GpsFixType::GPS_FIX_TYPE_3D_FIX, 10)
    );
    assert!(
        g.alt_ellipsoid != 0 && g.alt_ellipsoid == g.alt,
        "alt_ellipsoid {} alt {}",
        g.alt_ellipsoid,
        g.alt
    );
    assert_eq!(
        sys_status(&s, MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_GPS),
        (true, true, true)
    );
    set(&mut v, "gps", "off");
    let s = run(&mut v, 1.5);
    let Some(MavMessage::GPS_RAW_INT(g)) = message(TelemetryStream::GpsRawInt, &s) else {
        panic!()
    };
    assert_eq!(g.fix_type, GpsFixType::GPS_FIX_TYPE_NO_GPS);
    assert_eq!(
        (g.satellites_visible, g.eph, g.epv, g.lat, g.lon),
        (255, u16::MAX, u16::MAX, 0, 0)
    );
    let (_, enabled, healthy) = sys_status(&s, MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_GPS);
    assert!(enabled && !healthy, "GPS health cleared, still enabled");
    set(&mut v, "gps", "ok");
    let s = run(&mut v, 3.0);
    let Some(MavMessage::GPS_RAW_INT(g)) = message(TelemetryStream::GpsRawInt, &s) else {
        panic!()
    };
    assert_eq!(g.fix_type, GpsFixType::GPS_FIX_TYPE_3D_FIX);
    assert_eq!(
        sys_status(&s, MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_GPS),
        (true, true, true)
    );
}

#[test]
fn a_silent_barometer_stops_scaled_pressure_and_clears_its_bits() {
    let mut v = ready();
    let s = run(&mut v, 0.1);
    assert!(
        matches!(message(TelemetryStream::ScaledPressure, &s), Some(MavMessage::SCALED_PRESSURE(p)) if p.press_abs > 900.0)
    );
    let baro = MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_ABSOLUTE_PRESSURE;
    assert_eq!(sys_status(&s, baro), (true, true, true));
    set(&mut v, "baro", "off");
    let s = run(&mut v, 1.5);
    assert_eq!(message(TelemetryStream::ScaledPressure, &s), None);
    assert_eq!(sys_status(&s, baro), (true, true, false));
    assert_eq!(highres_updated(&s).bits() & BARO_BITS, 0);
    set(&mut v, "baro", "ok");
    let s = run(&mut v, 2.0);
    assert!(message(TelemetryStream::ScaledPressure, &s).is_some());
    assert_eq!(sys_status(&s, baro), (true, true, true));
}

#[test]
fn a_silent_magnetometer_and_imu_clear_their_bits_and_come_back() {
    let mut v = ready();
    let mag = MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_3D_MAG;
    set(&mut v, "mag", "off");
    let s = run(&mut v, 1.5);
    assert_eq!(sys_status(&s, mag), (true, true, false));
    let mut seen_mag_bits = false;
    for _ in 0..100 {
        seen_mag_bits |= highres_updated(&v.step().snapshot).bits() & MAG_BITS != 0;
    }
    assert!(!seen_mag_bits, "no magnetometer field updated while it is off");
    set(&mut v, "mag", "ok");
    let s = run(&mut v, 2.0);
    assert_eq!(sys_status(&s, mag), (true, true, true));
    let mut updates = 0;
    for _ in 0..100 {
        updates += usize::from(highres_updated(&v.step().snapshot).bits() & MAG_BITS == MAG_BITS);
    }
    assert!(
        updates >= 4,
        "50 Hz magnetometer back in HIGHRES_IMU: {updates} of 100 ticks"
    );

    let gyro = MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_3D_GYRO;
    set(&mut v, "gyro", "off");
    let s = run(&mut v, 1.5);
    assert_eq!(sys_status(&s, gyro), (true, true, false));
    assert_eq!(highres_updated(&s).bits() & 0x3F, 0);
    set(&mut v, "gyro", "ok");
    let s = run(&mut v, 0.5);
    assert_eq!(sys_status(&s, gyro), (true, true, true));
    assert_eq!(highres_updated(&s).bits() & 0x3F, 0x3F);
}
