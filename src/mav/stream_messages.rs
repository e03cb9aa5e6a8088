//! Telemetry messages from a [`Snapshot`] (docs/mavlink.md §4–§5): the periodic streams. The status
//! messages (battery, SYS_STATUS, STATUSTEXT) are in `status.rs`; MISSION_CURRENT, which names the
//! stored plans, in `mission_report.rs`. Pure.

use mavlink::dialects::ardupilotmega::{
    MavFrame, MavLandedState, MavMessage, MavVtolState, PositionTargetTypemask, ATTITUDE_DATA,
    ATTITUDE_QUATERNION_DATA, ATTITUDE_TARGET_DATA, DEBUG_VECT_DATA, EXTENDED_SYS_STATE_DATA, GLOBAL_POSITION_INT_DATA,
    HOME_POSITION_DATA, LOCAL_POSITION_NED_DATA, NAMED_VALUE_FLOAT_DATA, POSITION_TARGET_LOCAL_NED_DATA,
    SYSTEM_TIME_DATA, VFR_HUD_DATA,
};

use crate::commander::LandedState;
use crate::math::{UnitQuat, Vec3};
use crate::telemetry::Snapshot;

pub use super::status::status_text;
use super::status::{battery_status, sys_status};

/// A periodic telemetry message.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TelemetryStream {
    /// ATTITUDE_QUATERNION (31).
    AttitudeQuaternion,
    /// GPS_RAW_INT (24).
    GpsRawInt,
    /// VFR_HUD (74).
    VfrHud,
    /// BATTERY_STATUS (147).
    BatteryStatus,
    /// ATTITUDE_TARGET (83): the attitude and thrust the controller aims for.
    AttitudeTarget,
    /// POSITION_TARGET_LOCAL_NED (85): the setpoint flown.
    PositionTarget,
    /// SERVO_OUTPUT_RAW (36): the motor outputs as PX4 SITL's PWM
    /// ([`motor_output_us`](super::motor_outputs::motor_output_us)).
    ServoOutputRaw,
    /// ACTUATOR_OUTPUT_STATUS (375): the same motor outputs, one per rotor, `active` the count.
    ActuatorOutputStatus,
    /// HIGHRES_IMU (105): accelerometer, gyro, magnetometer (a fixed field) and barometer.
    HighresImu,
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
    /// CURRENT_MODE (436): the mode flown, with its standard mode.
    CurrentMode,
    /// ORBIT_EXECUTION_STATUS (360): the orbit flown (only in orbit mode).
    OrbitStatus,
    /// CURRENT_EVENT_SEQUENCE (411): no events, sequence reset.
    EventSequence,
    /// ESTIMATOR_STATUS (230): the navigation filter's flags, test ratios and accuracies.
    EstimatorStatus,
    /// SCALED_PRESSURE (29): the barometer's pressure and temperature; none while it is silent.
    ScaledPressure,
    /// HIL_STATE_QUATERNION (115): the simulator's truth (simulation only), off unless asked for,
    /// as PX4 SITL streams it for MAVSDK's ground truth.
    GroundTruth,
    /// EKF_STATUS_REPORT (193, `ardupilotmega`): the same filter report as ArduPilot sends it,
    /// for ground stations that read that one.
    EkfStatusReport,
    /// SYSTEM_TIME (2): Unix time and time since boot; the link builds it from its wall clock
    /// ([`system_time`]), so [`message`] has none.
    SystemTime,
    /// RAW_IMU (27, ArduPilot's RAW_SENSORS): accelerometer, gyroscope, magnetometer as integers.
    RawImu,
    /// POWER_STATUS (125, ArduPilot's EXTENDED_STATUS): the board's supply.
    PowerStatus,
    /// MEMINFO (152, ArduPilot's EXTENDED_STATUS): free memory.
    Meminfo,
    /// NAV_CONTROLLER_OUTPUT (62, ArduPilot's EXTENDED_STATUS): the target against the state.
    NavControllerOutput,
    /// POSITION_TARGET_GLOBAL_INT (87, ArduPilot's EXTENDED_STATUS): the position target, AMSL.
    PositionTargetGlobal,
    /// RC_CHANNELS (65, ArduPilot's RC_CHANNELS): the RC receiver (none here).
    RcChannels,
    /// SIMSTATE (164, ArduPilot's EXTRA1): the simulator's truth, as ArduPilot SITL sends it.
    Simstate,
    /// AHRS2 (178, ArduPilot's EXTRA1): attitude and place of the estimate.
    Ahrs2,
    /// AHRS (163, ArduPilot's EXTRA3): ArduPilot's DCM figures (none run here: zeros).
    Ahrs,
    /// VIBRATION (241, ArduPilot's EXTRA3): accelerometer vibration and clipping.
    Vibration,
}

impl TelemetryStream {
    /// Every stream: PX4's first, then the ArduPilot-only ones
    /// ([`ardupilot_only`](TelemetryStream::ardupilot_only)).
    pub const ALL: [TelemetryStream; 37] = [
        TelemetryStream::HighresImu,
        TelemetryStream::SysStatus,
        TelemetryStream::ExtendedSysState,
        TelemetryStream::Attitude,
        TelemetryStream::AttitudeQuaternion,
        TelemetryStream::LocalPosition,
        TelemetryStream::GlobalPosition,
        TelemetryStream::GpsRawInt,
        TelemetryStream::VfrHud,
        TelemetryStream::HomePosition,
        TelemetryStream::BatteryStatus,
        TelemetryStream::AttitudeTarget,
        TelemetryStream::PositionTarget,
        TelemetryStream::ServoOutputRaw,
        TelemetryStream::ActuatorOutputStatus,
        TelemetryStream::MissionCurrent,
        TelemetryStream::ExternalForce,
        TelemetryStream::ExternalTorque,
        TelemetryStream::MassEstimate,
        TelemetryStream::CurrentMode,
        TelemetryStream::OrbitStatus,
        TelemetryStream::SystemTime,
        TelemetryStream::EventSequence,
        TelemetryStream::EstimatorStatus,
        TelemetryStream::ScaledPressure,
        TelemetryStream::GroundTruth,
        TelemetryStream::EkfStatusReport,
        TelemetryStream::RawImu,
        TelemetryStream::PowerStatus,
        TelemetryStream::Meminfo,
        TelemetryStream::NavControllerOutput,
        TelemetryStream::PositionTargetGlobal,
        TelemetryStream::RcChannels,
        TelemetryStream::Simstate,
        TelemetryStream::Ahrs2,
        TelemetryStream::Ahrs,
        TelemetryStream::Vibration,
    ];

    /// MAVLink message id.
    pub fn message_id(self) -> u32 {
        match self {
            TelemetryStream::SysStatus => 1,
            TelemetryStream::GpsRawInt => 24,
            TelemetryStream::Attitude => 30,
            TelemetryStream::AttitudeQuaternion => 31,
            TelemetryStream::LocalPosition => 32,
            TelemetryStream::GlobalPosition => 33,
            TelemetryStream::ServoOutputRaw => 36,
            TelemetryStream::ActuatorOutputStatus => 375,
            TelemetryStream::HighresImu => 105,
            TelemetryStream::MissionCurrent => 42,
            TelemetryStream::VfrHud => 74,
            TelemetryStream::AttitudeTarget => 83,
            TelemetryStream::PositionTarget => 85,
            TelemetryStream::BatteryStatus => 147,
            TelemetryStream::HomePosition => 242,
            TelemetryStream::ExtendedSysState => 245,
            TelemetryStream::ExternalForce | TelemetryStream::ExternalTorque => 250,
            TelemetryStream::MassEstimate => 251,
            TelemetryStream::CurrentMode => 436,
            TelemetryStream::OrbitStatus => 360,
            TelemetryStream::SystemTime => 2,
            TelemetryStream::EventSequence => 411,
            TelemetryStream::EstimatorStatus => 230,
            TelemetryStream::ScaledPressure => 29,
            TelemetryStream::GroundTruth => 115,
            TelemetryStream::EkfStatusReport => 193,
            TelemetryStream::RawImu => 27,
            TelemetryStream::PowerStatus => 125,
            TelemetryStream::Meminfo => 152,
            TelemetryStream::NavControllerOutput => 62,
            TelemetryStream::PositionTargetGlobal => 87,
            TelemetryStream::RcChannels => 65,
            TelemetryStream::Simstate => 164,
            TelemetryStream::Ahrs2 => 178,
            TelemetryStream::Ahrs => 163,
            TelemetryStream::Vibration => 241,
        }
    }
}

/// SYSTEM_TIME at Unix time `unix_us` [µs] (0: unknown) and the snapshot's time since boot.
pub fn system_time(unix_us: u64, s: &Snapshot) -> MavMessage {
    MavMessage::SYSTEM_TIME(SYSTEM_TIME_DATA {
        time_unix_usec: unix_us,
        time_boot_ms: time_boot_ms(s),
    })
}

/// Heading [cdeg, 0..35999].
fn heading_cdeg(s: &Snapshot) -> u16 {
    (s.eta.z.to_degrees().rem_euclid(360.0) * 100.0).round() as u16 % 36000
}

/// The snapshot's time [µs]: its tick's microsecond (rounded, as the flight log stamps it, so a
/// tick at 4.07 s stored as 4.0699… s is 4 070 000 µs, not one tick earlier).
pub(super) fn time_usec(s: &Snapshot) -> u64 {
    (s.t_s * 1e6).round().max(0.0) as u64
}

/// The snapshot's time since boot [ms]: [`time_usec`] cut to the millisecond.
pub(super) fn time_boot_ms(s: &Snapshot) -> u32 {
    (time_usec(s) / 1000) as u32
}

/// The components of `v` as MAVLink floats.
fn f32x3(v: Vec3) -> [f32; 3] {
    [v.x as f32, v.y as f32, v.z as f32]
}

/// The place `pos_w` as MAVLink integers: latitude and longitude [1e-7 deg], altitude AMSL [mm].
fn global_int(s: &Snapshot, pos_w: &Vec3) -> [i32; 3] {
    let (lat, lon, alt) = s.home.to_global(pos_w);
    [
        (lat * 1e7).round() as i32,
        (lon * 1e7).round() as i32,
        (alt * 1000.0).round() as i32,
    ]
}

/// The message of `stream` for snapshot `s`; `None` when there is nothing to report (no estimate).
pub fn message(stream: TelemetryStream, s: &Snapshot) -> Option<MavMessage> {
    let time_usec = time_usec(s);
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
        TelemetryStream::CurrentMode => super::standard_modes::current_mode(s.mode),
        TelemetryStream::OrbitStatus => return super::orbit::orbit_execution_status(s),
        // Built by the link: the wall clock, the stored plans' ids.
        TelemetryStream::SystemTime | TelemetryStream::MissionCurrent => return None,
        TelemetryStream::EkfStatusReport => super::nav_status::ekf_status_report(s),
        TelemetryStream::RawImu
        | TelemetryStream::PowerStatus
        | TelemetryStream::Meminfo
        | TelemetryStream::NavControllerOutput
        | TelemetryStream::PositionTargetGlobal
        | TelemetryStream::RcChannels
        | TelemetryStream::Simstate
        | TelemetryStream::Ahrs2
        | TelemetryStream::Ahrs
        | TelemetryStream::Vibration => return super::ardupilot::copter_messages::message(stream, s),
        TelemetryStream::EventSequence => super::events::current_event_sequence(),
        TelemetryStream::AttitudeQuaternion => {
            let q = UnitQuat::from_euler_angles(s.eta.x, s.eta.y, s.eta.z);
            MavMessage::ATTITUDE_QUATERNION(ATTITUDE_QUATERNION_DATA {
                time_boot_ms: time_boot_ms(s),
                q1: q.w as f32,
                q2: q.i as f32,
                q3: q.j as f32,
                q4: q.k as f32,
                rollspeed: s.omega_b.x as f32,
                pitchspeed: s.omega_b.y as f32,
                yawspeed: s.omega_b.z as f32,
                repr_offset_q: [0.0; 4],
            })
        }
        TelemetryStream::GpsRawInt => super::nav_status::gps_raw_int(s),
        TelemetryStream::EstimatorStatus => super::nav_status::estimator_status(s),
        TelemetryStream::ScaledPressure => return super::nav_status::scaled_pressure(s),
        TelemetryStream::GroundTruth => return super::nav_status::ground_truth(s),
        TelemetryStream::VfrHud => MavMessage::VFR_HUD(VFR_HUD_DATA {
            airspeed: s.vel_w.norm() as f32,
            groundspeed: s.vel_w.xy().norm() as f32,
            alt: s.home.to_global(&s.pos_w).2 as f32,
            climb: (-s.vel_w.z) as f32,
            heading: (heading_cdeg(s) / 100) as i16,
            throttle: (s.thrust_fraction.clamp(0.0, 1.0) * 100.0).round() as u16,
        }),
        TelemetryStream::BatteryStatus => battery_status(&s.battery),
        TelemetryStream::AttitudeTarget => {
            let eta = s.eta_desired?;
            let q = UnitQuat::from_euler_angles(eta.x, eta.y, eta.z);
            MavMessage::ATTITUDE_TARGET(ATTITUDE_TARGET_DATA {
                time_boot_ms: time_boot_ms(s),
                q: [q.w as f32, q.i as f32, q.j as f32, q.k as f32],
                thrust: s.thrust_fraction as f32,
                ..Default::default()
            })
        }
        TelemetryStream::PositionTarget => {
            let sp = s.setpoint?;
            let nan3 = |v: Option<Vec3>| v.map_or([f32::NAN; 3], f32x3);
            let ([x, y, z], [vx, vy, vz]) = (nan3(sp.pos_w), nan3(sp.vel_w));
            let [afx, afy, afz] = nan3(sp.acc_w);
            let mut mask = 0u16;
            mask |= if sp.pos_w.is_none() { 0b111 } else { 0 };
            mask |= if sp.vel_w.is_none() { 0b111 << 3 } else { 0 };
            mask |= if sp.acc_w.is_none() { 0b111 << 6 } else { 0 };
            mask |= if sp.yaw_rad.is_none() { 1 << 10 } else { 0 };
            mask |= if sp.yaw_rate_rad_s.is_none() { 1 << 11 } else { 0 };
            MavMessage::POSITION_TARGET_LOCAL_NED(POSITION_TARGET_LOCAL_NED_DATA {
                time_boot_ms: time_boot_ms(s),
                x,
                y,
                z,
                vx,
                vy,
                vz,
                afx,
                afy,
                afz,
                yaw: sp.yaw_rad.map_or(f32::NAN, |y| y as f32),
                yaw_rate: sp.yaw_rate_rad_s.map_or(f32::NAN, |y| y as f32),
                type_mask: PositionTargetTypemask::from_bits_truncate(mask),
                coordinate_frame: MavFrame::MAV_FRAME_LOCAL_NED,
            })
        }
        TelemetryStream::ServoOutputRaw => super::motor_outputs::servo_output_raw(s, time_usec),
        TelemetryStream::ActuatorOutputStatus => super::motor_outputs::actuator_output_status(s, time_usec),
        TelemetryStream::HighresImu => super::nav_status::highres_imu(s),
        TelemetryStream::ExternalForce => vector("EXT_F", s.estimate?.force_w),
        TelemetryStream::ExternalTorque => vector("EXT_T", s.estimate?.torque_b),
        TelemetryStream::MassEstimate => MavMessage::NAMED_VALUE_FLOAT(NAMED_VALUE_FLOAT_DATA {
            time_boot_ms: time_boot_ms(s),
            value: s.estimate?.mass_kg as f32,
            name: "EXT_MASS".into(),
        }),
        TelemetryStream::SysStatus => sys_status(s),
        TelemetryStream::ExtendedSysState => MavMessage::EXTENDED_SYS_STATE(EXTENDED_SYS_STATE_DATA {
            vtol_state: MavVtolState::MAV_VTOL_STATE_UNDEFINED,
            landed_state: match s.landed {
                LandedState::OnGround => MavLandedState::MAV_LANDED_STATE_ON_GROUND,
                LandedState::InAir => MavLandedState::MAV_LANDED_STATE_IN_AIR,
                LandedState::Takeoff => MavLandedState::MAV_LANDED_STATE_TAKEOFF,
                LandedState::Landing => MavLandedState::MAV_LANDED_STATE_LANDING,
            },
        }),
        TelemetryStream::Attitude => {
            let ([roll, pitch, yaw], [rollspeed, pitchspeed, yawspeed]) = (f32x3(s.eta), f32x3(s.omega_b));
            MavMessage::ATTITUDE(ATTITUDE_DATA {
                time_boot_ms: time_boot_ms(s),
                roll,
                pitch,
                yaw,
                rollspeed,
                pitchspeed,
                yawspeed,
            })
        }
        TelemetryStream::LocalPosition => {
            let ([x, y, z], [vx, vy, vz]) = (f32x3(s.pos_w), f32x3(s.vel_w));
            MavMessage::LOCAL_POSITION_NED(LOCAL_POSITION_NED_DATA {
                time_boot_ms: time_boot_ms(s),
                x,
                y,
                z,
                vx,
                vy,
                vz,
            })
        }
        TelemetryStream::GlobalPosition => {
            let [lat, lon, alt] = global_int(s, &s.pos_w);
            let heading_cdeg = heading_cdeg(s);
            MavMessage::GLOBAL_POSITION_INT(GLOBAL_POSITION_INT_DATA {
                time_boot_ms: time_boot_ms(s),
                lat,
                lon,
                alt,
                // Above home, as PX4 reports it.
                relative_alt: ((s.home_w.z - s.pos_w.z) * 1000.0).round() as i32,
                vx: (s.vel_w.x * 100.0).round() as i16,
                vy: (s.vel_w.y * 100.0).round() as i16,
                vz: (s.vel_w.z * 100.0).round() as i16,
                hdg: heading_cdeg,
            })
        }
        TelemetryStream::HomePosition => {
            let [latitude, longitude, altitude] = global_int(s, &s.home_w);
            let [x, y, z] = f32x3(s.home_w);
            MavMessage::HOME_POSITION(HOME_POSITION_DATA {
                latitude,
                longitude,
                altitude,
                x,
                y,
                z,
                q: [1.0, 0.0, 0.0, 0.0],
                ..Default::default()
            })
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::guidance::Home;
    use crate::math::Vec3;
    use mavlink::dialects::ardupilotmega::{MavSeverity, MavSysStatusSensor};

    fn snapshot() -> Snapshot {
        Snapshot {
            t_s: 12.345,
            pos_w: Vec3::new(10.0, -5.0, -2.5),
            vel_w: Vec3::new(0.5, 0.0, -0.25),
            eta: Vec3::new(0.1, -0.2, -1.0),
            omega_b: Vec3::new(0.01, 0.02, 0.03),
            accel_b: Vec3::new(0.0, 0.0, -9.81),
            armed: true,
            landed: LandedState::InAir,
            thrust_fraction: 0.5,
            rotor_count: 4,
            rotor_max_rad_s: 1100.0,
            ..Snapshot::initial(Home::default())
        }
    }

    #[test]
    fn positions_are_scaled_as_the_spec_says() {
        let Some(MavMessage::GLOBAL_POSITION_INT(g)) = message(TelemetryStream::GlobalPosition, &snapshot()) else {
            panic!("wrong message");
        };
        assert_eq!(g.time_boot_ms, 12_345);
        assert_eq!(g.relative_alt, 2500);
        assert_eq!(g.alt, 490_500);
        assert_eq!((g.vx, g.vz), (50, -25));
        assert_eq!(g.hdg, 30_270, "yaw −1 rad = 302.7°");
        assert!(g.lat > 473_977_420 && g.lon < 85_455_940);
        let Some(MavMessage::EXTENDED_SYS_STATE(e)) = message(TelemetryStream::ExtendedSysState, &snapshot()) else {
            panic!("wrong message");
        };
        assert_eq!(e.landed_state, MavLandedState::MAV_LANDED_STATE_IN_AIR);
    }

    #[test]
    fn geofence_is_healthy_until_breached_and_enabled_unless_switched_off() {
        let fence = MavSysStatusSensor::MAV_SYS_STATUS_GEOFENCE;
        let status = |s: &Snapshot| match message(TelemetryStream::SysStatus, s) {
            Some(MavMessage::SYS_STATUS(m)) => m,
            other => panic!("wrong message {other:?}"),
        };
        let inside = status(&snapshot());
        assert!(inside.onboard_control_sensors_present.contains(fence));
        assert!(inside.onboard_control_sensors_enabled.contains(fence));
        assert!(inside.onboard_control_sensors_health.contains(fence), "no false breach");
        let outside = status(&Snapshot {
            geofence_breached: true,
            ..snapshot()
        });
        assert!(outside.onboard_control_sensors_present.contains(fence));
        assert!(outside.onboard_control_sensors_enabled.contains(fence));
        assert!(!outside.onboard_control_sensors_health.contains(fence), "a breach");
        assert_eq!(
            outside.onboard_control_sensors_health | fence,
            inside.onboard_control_sensors_health,
            "only the geofence bit changes"
        );
        let off = status(&Snapshot {
            geofence_enabled: false,
            ..snapshot()
        });
        assert!(off.onboard_control_sensors_present.contains(fence));
        assert!(!off.onboard_control_sensors_enabled.contains(fence), "switched off");
        assert!(off.onboard_control_sensors_health.contains(fence));
    }

    #[test]
    fn status_text_is_cut_to_fifty_bytes() {
        let MavMessage::STATUSTEXT(t) = status_text(MavSeverity::MAV_SEVERITY_WARNING, &"é".repeat(40)) else {
            panic!("wrong message");
        };
        assert_eq!(t.text.to_str().map(|s| s.chars().count()).unwrap_or(0), 25);
    }
}
