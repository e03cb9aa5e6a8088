//! Status messages from a [`Snapshot`]: BATTERY_STATUS, SYS_STATUS (sensor, pre-arm and
//! geofence health) and STATUSTEXT (MISSION_CURRENT, which needs the stored plans, is in
//! `mission_report.rs`). Pure.

use mavlink::dialects::ardupilotmega::{
    MavMessage, MavSeverity, MavSysStatusSensor, BATTERY_STATUS_DATA, STATUSTEXT_DATA, SYS_STATUS_DATA,
};

use crate::telemetry::{BatterySnapshot, SensorState, Snapshot};

/// Pack voltage [mV].
fn millivolts(b: &BatterySnapshot) -> u16 {
    (b.cell_v * f64::from(b.cells) * 1000.0).round().clamp(0.0, 65_534.0) as u16
}

/// Remaining charge [%].
fn percent(b: &BatterySnapshot) -> i8 {
    (b.fraction * 100.0).round().clamp(0.0, 100.0) as i8
}

/// BATTERY_STATUS: cell voltages (up to ten cells, UINT16_MAX for the rest), current [cA],
/// charge drawn [mAh], energy drawn [hJ], remaining [%].
pub(super) fn battery_status(b: &BatterySnapshot) -> MavMessage {
    let mut voltages = [u16::MAX; 10];
    let cell_mv = (b.cell_v * 1000.0).round().clamp(0.0, 65_534.0) as u16;
    for v in voltages.iter_mut().take(b.cells.min(10) as usize) {
        *v = cell_mv;
    }
    MavMessage::BATTERY_STATUS(BATTERY_STATUS_DATA {
        voltages,
        current_battery: (b.current_a * 100.0).round().clamp(0.0, f64::from(i16::MAX)) as i16,
        current_consumed: b.consumed_mah.round().clamp(0.0, f64::from(i32::MAX)) as i32,
        energy_consumed: (b.energy_j / 100.0).round().clamp(0.0, f64::from(i32::MAX)) as i32,
        temperature: i16::MAX,
        battery_remaining: percent(b),
        ..Default::default()
    })
}

/// SYS_STATUS (docs/mavlink.md §4): the sensors MAVSDK's `health_all_ok()` checks (gyro,
/// accelerometer, magnetometer, barometer, GPS) as PX4's health report fills them: present,
/// enabled when present or unhealthy, healthy while the sensor delivered within the last second
/// and the navigation takes its data (the GPS present only while the filter uses its position:
/// MAVSDK's "global position ok"); the attitude estimate (AHRS); the pre-arm check healthy
/// while arming would pass (MAVSDK's "armable"); the geofence present, enabled and healthy unless
/// the vehicle is outside it, enabled unless switched off (`RP_GF_ENABLE` 0: MAVProxy then says
/// "fence disabled"). A clear geofence health bit reads as a breach (MAVProxy says "fence
/// breach" when it sees one), so the bit is cleared on a real breach only.
pub(super) fn sys_status(s: &Snapshot) -> MavMessage {
    let b = &s.battery;
    let nav = &s.nav;
    let always = |healthy: bool| SensorState { present: true, healthy };
    let checks = [
        (MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_3D_GYRO, nav.sensors.gyro),
        (MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_3D_ACCEL, nav.sensors.accel),
        (MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_3D_MAG, nav.sensors.mag),
        (
            MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_ABSOLUTE_PRESSURE,
            nav.sensors.baro,
        ),
        (MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_GPS, nav.sensors.gps),
        (MavSysStatusSensor::MAV_SYS_STATUS_AHRS, always(nav.validity.attitude)),
        (MavSysStatusSensor::MAV_SYS_STATUS_PREARM_CHECK, always(nav.armable)),
        (
            MavSysStatusSensor::MAV_SYS_STATUS_GEOFENCE,
            always(!s.geofence_breached),
        ),
    ];
    let (mut present, mut enabled, mut health) = (
        MavSysStatusSensor::empty(),
        MavSysStatusSensor::empty(),
        MavSysStatusSensor::empty(),
    );
    for (bit, state) in checks {
        if state.present {
            present |= bit;
        }
        if state.present || !state.healthy {
            enabled |= bit;
        }
        if state.healthy {
            health |= bit;
        }
    }
    if !s.geofence_enabled {
        enabled.remove(MavSysStatusSensor::MAV_SYS_STATUS_GEOFENCE);
    }
    MavMessage::SYS_STATUS(SYS_STATUS_DATA {
        onboard_control_sensors_present: present,
        onboard_control_sensors_enabled: enabled,
        onboard_control_sensors_health: health,
        voltage_battery: millivolts(b),
        current_battery: (b.current_a * 100.0).round().clamp(0.0, f64::from(i16::MAX)) as i16,
        battery_remaining: percent(b),
        ..Default::default()
    })
}

/// STATUSTEXT with `text` cut to the 50 characters the message holds.
pub fn status_text(severity: MavSeverity, text: &str) -> MavMessage {
    let mut bytes = [0u8; 50];
    let mut n = 0;
    for c in text.chars() {
        let mut buf = [0u8; 4];
        let enc = c.encode_utf8(&mut buf).as_bytes();
        if n + enc.len() > bytes.len() {
            break;
        }
        bytes[n..n + enc.len()].copy_from_slice(enc);
        n += enc.len();
    }
    MavMessage::STATUSTEXT(STATUSTEXT_DATA {
        severity,
        text: bytes.into(),
        ..Default::default()
    })
}
