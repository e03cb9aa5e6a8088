//! What the vehicle publishes every tick for the links to stream: the latest values only, plain
//! data in SI units (NED world, FRD body), independent of MAVLink.

use crate::airframe::MAX_ROTORS;
use crate::commander::{Commander, FlightMode, LandedState, MissionState, NavValidity};
use crate::control::{FlatSetpoint, VehicleState};
use crate::guidance::Home;
use crate::math::{euler_zyx, Vec3};
use crate::sitl::PlantTruth;
use crate::wrench_estimator::WrenchEstimate;

/// The battery as its gauge reads it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BatterySnapshot {
    /// Remaining fraction [0, 1].
    pub fraction: f64,
    /// Cell voltage [V].
    pub cell_v: f64,
    /// Cells in series.
    pub cells: u32,
    /// Current [A].
    pub current_a: f64,
    /// Charge drawn [mAh].
    pub consumed_mah: f64,
    /// Energy drawn [J].
    pub energy_j: f64,
}

impl BatterySnapshot {
    /// A full pack of `cells` cells at rest.
    pub fn full(cells: u32) -> Self {
        Self {
            fraction: 1.0,
            cell_v: 4.2,
            cells,
            current_a: 0.0,
            consumed_mah: 0.0,
            energy_j: 0.0,
        }
    }
}

/// What SYS_STATUS says of one sensor (PX4's health report): whether it is present and whether
/// it is healthy; it counts as enabled when present or unhealthy.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SensorState {
    /// Present (the GPS: while the navigation uses its position).
    pub present: bool,
    /// Healthy: it delivered within the last second and the navigation takes its data.
    pub healthy: bool,
}

impl SensorState {
    /// Present and healthy.
    pub const OK: Self = Self {
        present: true,
        healthy: true,
    };
}

/// The sensors SYS_STATUS reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SensorHealth {
    /// Gyroscope.
    pub gyro: SensorState,
    /// Accelerometer.
    pub accel: SensorState,
    /// Magnetometer.
    pub mag: SensorState,
    /// Barometer.
    pub baro: SensorState,
    /// GPS.
    pub gps: SensorState,
}

impl SensorHealth {
    /// Every sensor present and healthy.
    pub const ALL: Self = Self {
        gyro: SensorState::OK,
        accel: SensorState::OK,
        mag: SensorState::OK,
        baro: SensorState::OK,
        gps: SensorState::OK,
    };
}

/// Which raw readings are new since a 50 Hz message would last have been sent (HIGHRES_IMU's
/// `fields_updated`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FreshReadings {
    /// Accelerometer and gyroscope.
    pub imu: bool,
    /// Magnetometer.
    pub mag: bool,
    /// Barometer.
    pub baro: bool,
    /// The barometer delivered within the last second (SCALED_PRESSURE stops otherwise, as PX4
    /// sends it only on a new reading).
    pub baro_alive: bool,
}

impl FreshReadings {
    /// Everything new (the state sensor: computed every tick).
    pub const ALL: Self = Self {
        imu: true,
        mag: true,
        baro: true,
        baro_alive: true,
    };
}

/// The latest GPS reading (GPS_RAW_INT).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GpsSnapshot {
    /// Position, local NED [m].
    pub pos_w: Vec3,
    /// Velocity, NED [m/s].
    pub vel_w: Vec3,
    /// Horizontal and vertical accuracy [m].
    pub acc_m: (f64, f64),
    /// Speed accuracy [m/s].
    pub speed_acc_m_s: f64,
    /// A 3D fix.
    pub fix_3d: bool,
    /// Satellites used.
    pub satellites: u8,
    /// No reading for more than a second: the receiver is silent (GPS_RAW_INT then says so).
    pub silent: bool,
}

/// The navigation filter's report (ESTIMATOR_STATUS, EKF_STATUS_REPORT).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FilterSnapshot {
    /// ESTIMATOR_STATUS_FLAGS bits (the same as EKF_STATUS_FLAGS).
    pub flags: u16,
    /// Test ratios ν² / (gate² S) [-]: velocity, horizontal position, vertical position,
    /// heading, height.
    pub test_ratios: [f64; 5],
    /// Standard deviations: horizontal and vertical position [m].
    pub pos_std_m: (f64, f64),
    /// Standard deviation of the velocity (largest axis) [m/s].
    pub vel_std_m_s: f64,
    /// Standard deviation of the heading [rad].
    pub heading_std_rad: f64,
}

/// What the navigation reports for the links.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NavSnapshot {
    /// What the estimate can be flown on for.
    pub validity: NavValidity,
    /// Arming would pass every check now (SYS_STATUS pre-arm bit).
    pub armable: bool,
    /// Which sensors deliver usable data.
    pub sensors: SensorHealth,
    /// Which raw readings are new.
    pub fresh: FreshReadings,
    /// The latest GPS reading; `None` with the state sensor, or before the first one.
    pub gps: Option<GpsSnapshot>,
    /// The latest magnetometer reading, body FRD [gauss].
    pub mag_b: Option<Vec3>,
    /// The latest barometer reading: pressure [Pa], temperature [°C].
    pub baro: Option<(f64, f64)>,
    /// The sensor suite is read (`false`: the state sensor, whose raw readings are computed).
    pub suite: bool,
    /// The filter's report; `None` with the state sensor.
    pub filter: Option<FilterSnapshot>,
}

impl NavSnapshot {
    /// The state sensor's report: everything valid and healthy, no raw readings.
    pub const EXACT: Self = Self {
        validity: NavValidity::EXACT,
        armable: true,
        sensors: SensorHealth::ALL,
        fresh: FreshReadings::ALL,
        gps: None,
        mag_b: None,
        baro: None,
        suite: false,
        filter: None,
    };
}

/// Latest vehicle state for telemetry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Snapshot {
    /// Simulated time since start [s].
    pub t_s: f64,
    /// Position, world NED relative to home [m].
    pub pos_w: Vec3,
    /// Velocity, world NED [m/s].
    pub vel_w: Vec3,
    /// Roll, pitch, yaw [rad].
    pub eta: Vec3,
    /// Body rates, FRD [rad/s].
    pub omega_b: Vec3,
    /// Specific force (accelerometer), body FRD [m/s²].
    pub accel_b: Vec3,
    /// Armed.
    pub armed: bool,
    /// Flight mode.
    pub mode: FlightMode,
    /// Landed state.
    pub landed: LandedState,
    /// Geodetic position of the local NED origin (where the vehicle started).
    pub home: Home,
    /// Home (where RTL returns), local NED [m]; the origin unless DO_SET_HOME moved it.
    pub home_w: Vec3,
    /// Current mission item.
    pub mission_seq: u16,
    /// Mission item count.
    pub mission_total: u16,
    /// Mission state.
    pub mission_state: MissionState,
    /// Wrench estimate, when the estimator runs and the vehicle flies.
    pub estimate: Option<WrenchEstimate>,
    /// Setpoint flown, when the motors run.
    pub setpoint: Option<FlatSetpoint>,
    /// Desired roll, pitch, yaw of the controller [rad], when the motors run.
    pub eta_desired: Option<Vec3>,
    /// Applied collective thrust over the maximum [-].
    pub thrust_fraction: f64,
    /// True rotor speeds [rad/s]; the first `rotor_count` are used.
    pub rotor_speeds: [f64; MAX_ROTORS],
    /// The flight controller's motor outputs: the rotor speeds it commands [rad/s]; the first
    /// `rotor_count` are used.
    pub rotor_commands: [f64; MAX_ROTORS],
    /// The motors the flight controller stops (bit i: rotor i + 1): every one while the motors
    /// are off; in flight those failure injection switched off or the allocation left out.
    pub rotors_stopped: u32,
    /// Number of rotors.
    pub rotor_count: usize,
    /// Highest rotor speed [rad/s].
    pub rotor_max_rad_s: f64,
    /// Battery.
    pub battery: BatterySnapshot,
    /// Outside the geofence (`GF_MAX_HOR_DIST` / `GF_MAX_VER_DIST`) as the geofence failsafe
    /// judged at the last check.
    pub geofence_breached: bool,
    /// The geofence switched on (`RP_GF_ENABLE`, ArduCopter's `FENCE_ENABLE`): SYS_STATUS's
    /// geofence "enabled" bit.
    pub geofence_enabled: bool,
    /// The orbit flown in orbit mode: centre, world NED [m], and radius [m], positive clockwise.
    pub orbit: Option<(Vec3, f64)>,
    /// The navigation's health and raw readings.
    pub nav: NavSnapshot,
    /// The simulator's truth after the tick, never read by the flight controller: what
    /// HIL_STATE_QUATERNION carries (PX4 SITL streams it from its simulator on request, MAVSDK
    /// reads it as "ground truth"); `None` only before the first tick.
    pub truth: Option<PlantTruth>,
}

impl Snapshot {
    /// The state before the first tick: disarmed on the ground at home in AUTO.LOITER.
    pub fn initial(home: Home) -> Self {
        Self {
            t_s: 0.0,
            pos_w: Vec3::zeros(),
            vel_w: Vec3::zeros(),
            eta: Vec3::zeros(),
            omega_b: Vec3::zeros(),
            accel_b: Vec3::zeros(),
            armed: false,
            mode: FlightMode::Loiter,
            landed: LandedState::OnGround,
            home,
            home_w: Vec3::zeros(),
            mission_seq: 0,
            mission_total: 0,
            mission_state: MissionState::NoMission,
            estimate: None,
            setpoint: None,
            eta_desired: None,
            thrust_fraction: 0.0,
            rotor_speeds: [0.0; MAX_ROTORS],
            rotor_commands: [0.0; MAX_ROTORS],
            rotors_stopped: u32::MAX,
            rotor_count: 0,
            rotor_max_rad_s: 1.0,
            battery: BatterySnapshot::full(3),
            geofence_breached: false,
            geofence_enabled: true,
            orbit: None,
            nav: NavSnapshot::EXACT,
            truth: None,
        }
    }

    /// This snapshot with the state's time, position, velocity, attitude and body rates.
    pub fn with_state(self, x: &VehicleState) -> Self {
        Self {
            t_s: x.t_s,
            pos_w: x.pos_w,
            vel_w: x.vel_w,
            eta: euler_zyx(&x.r_wb),
            omega_b: x.omega_b,
            ..self
        }
    }

    /// This snapshot with the commander's part (armed state, mode, landed state, home, mission
    /// progress, geofence, orbit) taken from `commander`.
    pub fn with_commander(self, commander: &Commander) -> Self {
        let (seq, total, state) = commander.mission_progress();
        Self {
            armed: commander.armed(),
            mode: commander.mode(),
            landed: commander.landed_state(),
            home_w: commander.home_w(),
            geofence_breached: commander.geofence_breached(),
            geofence_enabled: commander.params.failsafe.geofence_enabled,
            orbit: commander.orbit_status(),
            mission_seq: seq as u16,
            mission_total: total as u16,
            mission_state: state,
            ..self
        }
    }
}
