//! Telemetry messages from a [`Snapshot`] (mavlink.md §4–§5). Pure.

use mavlink::dialects::common::{
    MavLandedState, MavMessage, MavSeverity, MavSysStatusSensor, MavVtolState, ATTITUDE_DATA, DEBUG_VECT_DATA,
    EXTENDED_SYS_STATE_DATA, GLOBAL_POSITION_INT_DATA, HOME_POSITION_DATA, LOCAL_POSITION_NED_DATA,
    MISSION_CURRENT_DATA, NAMED_VALUE_FLOAT_DATA, STATUSTEXT_DATA, SYS_STATUS_DATA,
};

use crate::commander::{FlightMode, LandedState, MissionState};
use crate::math::Vec3;
use crate::telemetry::Snapshot;

/// Streams sent unasked and their period on the GCS link [s] (PX4 "normal" mode, §5.1).
pub const GCS_STREAMS: [(Stream, f64); 10] = [
    (Stream::SysStatus, 1.0),
    (Stream::ExtendedSysState, 1.0),
    (Stream::Attitude, 1.0 / 15.0),
    (Stream::LocalPosition, 1.0),
    (Stream::GlobalPosition, 0.2),
    (Stream::HomePosition, 2.0),
    (Stream::MissionCurrent, 1.0),
    (Stream::ExternalForce, 0.1),
    (Stream::ExternalTorque, 0.1),
    (Stream::MassEstimate, 0.1),
];

/// A periodic telemetry message.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stream {
    /// SYS_STATUS (1).
    SysStatus,
    /// EXTENDED_SYS_STATE (245).
    ExtendedSysState,
    /// ATTITUDE (30).
    Attitude,
    /// LOCAL_POSITION_NED (32).
    LocalPosition,
    /// GLOBAL_POSITION_INT (33).
    GlobalPosition,
    /// HOME_POSITION (242).
    HomePosition,
    /// MISSION_CURRENT (42).
    MissionCurrent,
    /// DEBUG_VECT "EXT_F": estimated external force, world NED [N] (only while estimating).
    ExternalForce,
    /// DEBUG_VECT "EXT_T": estimated external torque, body FRD [N·m] (only while estimating).
    ExternalTorque,
    /// NAMED_VALUE_FLOAT "EXT_MASS": mass estimate [kg] (only while estimating).
    MassEstimate,
}

fn time_boot_ms(s: &Snapshot) -> u32 {
    (s.t_s * 1000.0) as u32
}

/// The message of `stream` for snapshot `s`; `None` when there is nothing to report (no estimate).
pub fn message(stream: Stream, s: &Snapshot) -> Option<MavMessage> {
    let time_usec = (s.t_s * 1e6) as u64;
    let vector = |name: &str, v: Vec3| {
        MavMessage::DEBUG_VECT(DEBUG_VECT_DATA {
            time_usec,
            x: v.x as f32,
            y: v.y as f32,
            z: v.z as f32,
            name: name.into(),
        })
    };
    Some(match stream {
        Stream::ExternalForce => vector("EXT_F", s.estimate?.force_w),
        Stream::ExternalTorque => vector("EXT_T", s.estimate?.torque_b),
        Stream::MassEstimate => MavMessage::NAMED_VALUE_FLOAT(NAMED_VALUE_FLOAT_DATA {
            time_boot_ms: time_boot_ms(s),
            value: s.estimate?.mass_kg as f32,
            name: "EXT_MASS".into(),
        }),
        Stream::SysStatus => sys_status(),
        Stream::ExtendedSysState => MavMessage::EXTENDED_SYS_STATE(EXTENDED_SYS_STATE_DATA {
            vtol_state: MavVtolState::MAV_VTOL_STATE_UNDEFINED,
            landed_state: match s.landed {
                LandedState::OnGround => MavLandedState::MAV_LANDED_STATE_ON_GROUND,
                LandedState::InAir => MavLandedState::MAV_LANDED_STATE_IN_AIR,
                LandedState::Takeoff => MavLandedState::MAV_LANDED_STATE_TAKEOFF,
                LandedState::Landing => MavLandedState::MAV_LANDED_STATE_LANDING,
            },
        }),
        Stream::Attitude => MavMessage::ATTITUDE(ATTITUDE_DATA {
            time_boot_ms: time_boot_ms(s),
            roll: s.eta.x as f32,
            pitch: s.eta.y as f32,
            yaw: s.eta.z as f32,
            rollspeed: s.omega_b.x as f32,
            pitchspeed: s.omega_b.y as f32,
            yawspeed: s.omega_b.z as f32,
        }),
        Stream::LocalPosition => MavMessage::LOCAL_POSITION_NED(LOCAL_POSITION_NED_DATA {
            time_boot_ms: time_boot_ms(s),
            x: s.pos_w.x as f32,
            y: s.pos_w.y as f32,
            z: s.pos_w.z as f32,
            vx: s.vel_w.x as f32,
            vy: s.vel_w.y as f32,
            vz: s.vel_w.z as f32,
        }),
        Stream::GlobalPosition => {
            let (lat, lon, alt) = s.home.to_global(&s.pos_w);
            let heading_cdeg = (s.eta.z.to_degrees().rem_euclid(360.0) * 100.0).round() as u16 % 36000;
            MavMessage::GLOBAL_POSITION_INT(GLOBAL_POSITION_INT_DATA {
                time_boot_ms: time_boot_ms(s),
                lat: (lat * 1e7).round() as i32,
                lon: (lon * 1e7).round() as i32,
                alt: (alt * 1000.0).round() as i32,
                relative_alt: (-s.pos_w.z * 1000.0).round() as i32,
                vx: (s.vel_w.x * 100.0).round() as i16,
                vy: (s.vel_w.y * 100.0).round() as i16,
                vz: (s.vel_w.z * 100.0).round() as i16,
                hdg: heading_cdeg,
            })
        }
        Stream::MissionCurrent => mission_current(s, s.mission_seq),
        Stream::HomePosition => {
            let h = &s.home;
            MavMessage::HOME_POSITION(HOME_POSITION_DATA {
                latitude: (h.lat_deg * 1e7).round() as i32,
                longitude: (h.lon_deg * 1e7).round() as i32,
                altitude: (h.alt_amsl_m * 1000.0).round() as i32,
                q: [1.0, 0.0, 0.0, 0.0],
                ..Default::default()
            })
        }
    })
}

/// MISSION_CURRENT for item `seq` (mavlink.md §7 "Progress"): total UINT16_MAX without a mission,
/// mission_mode 1 in AUTO.MISSION.
pub fn mission_current(s: &Snapshot, seq: u16) -> MavMessage {
    MavMessage::MISSION_CURRENT(MISSION_CURRENT_DATA {
        seq,
        total: if s.mission_total == 0 {
            u16::MAX
        } else {
            s.mission_total
        },
        mission_state: match s.mission_state {
            MissionState::NoMission => mavlink::dialects::common::MissionState::MISSION_STATE_NO_MISSION,
            MissionState::NotStarted => mavlink::dialects::common::MissionState::MISSION_STATE_NOT_STARTED,
            MissionState::Active => mavlink::dialects::common::MissionState::MISSION_STATE_ACTIVE,
            MissionState::Paused => mavlink::dialects::common::MissionState::MISSION_STATE_PAUSED,
            MissionState::Complete => mavlink::dialects::common::MissionState::MISSION_STATE_COMPLETE,
        },
        mission_mode: u8::from(s.mode == FlightMode::Mission),
        ..Default::default()
    })
}

/// SYS_STATUS with the sensors MAVSDK's `health_all_ok()` checks present, enabled and healthy,
/// and the pre-arm check healthy (the emulator is armable at once, §4).
fn sys_status() -> MavMessage {
    let sensors = MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_3D_GYRO
        | MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_3D_ACCEL
        | MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_3D_MAG
        | MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_ABSOLUTE_PRESSURE
        | MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_GPS
        | MavSysStatusSensor::MAV_SYS_STATUS_PREARM_CHECK;
    MavMessage::SYS_STATUS(SYS_STATUS_DATA {
        onboard_control_sensors_present: sensors,
        onboard_control_sensors_enabled: sensors,
        onboard_control_sensors_health: sensors,
        voltage_battery: 16_200,
        current_battery: -1,
        battery_remaining: 100,
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;
    use crate::navigation::Home;

    fn snapshot() -> Snapshot {
        Snapshot {
            t_s: 12.345,
            pos_w: Vec3::new(10.0, -5.0, -2.5),
            vel_w: Vec3::new(0.5, 0.0, -0.25),
            eta: Vec3::new(0.1, -0.2, -1.0),
            omega_b: Vec3::new(0.01, 0.02, 0.03),
            armed: true,
            mode: FlightMode::Loiter,
            landed: LandedState::InAir,
            home: Home::default(),
            mission_seq: 0,
            mission_total: 0,
            mission_state: MissionState::NoMission,
            estimate: None,
        }
    }

    #[test]
    fn positions_are_scaled_as_the_spec_says() {
        let Some(MavMessage::GLOBAL_POSITION_INT(g)) = message(Stream::GlobalPosition, &snapshot()) else {
            panic!("wrong message");
        };
        assert_eq!(g.time_boot_ms, 12_345);
        assert_eq!(g.relative_alt, 2500);
        assert_eq!(g.alt, 490_500);
        assert_eq!((g.vx, g.vz), (50, -25));
        assert_eq!(g.hdg, 30_270, "yaw −1 rad = 302.7°");
        assert!(g.lat > 473_977_420 && g.lon < 85_455_940);
        let Some(MavMessage::EXTENDED_SYS_STATE(e)) = message(Stream::ExtendedSysState, &snapshot()) else {
            panic!("wrong message");
        };
        assert_eq!(e.landed_state, MavLandedState::MAV_LANDED_STATE_IN_AIR);
    }

    #[test]
    fn status_text_is_cut_to_fifty_bytes() {
        let MavMessage::STATUSTEXT(t) = status_text(MavSeverity::MAV_SEVERITY_WARNING, &"é".repeat(40)) else {
            panic!("wrong message");
        };
        assert_eq!(t.text.to_str().map(|s| s.chars().count()).unwrap_or(0), 25);
    }
}
