//! What the flight controller knows of its own state: the state sensor's reading as it is, or
//! the navigation filter's estimate from the sensor suite (docs/navigation_filter.md). Pure: one
//! [`StateSource::update`] per tick with that tick's readings.

use crate::commander::NavValidity;
use crate::control::low_pass::LowPass3;
use crate::control::VehicleState;
use crate::guidance::Home;
use crate::math::Mat3;
use crate::nav_filter::{
    BaroReading, GpsReading, HeightSource, MagReading, NavFilter, NavParams, NavParamsError, NavStatus,
    PreflightFailure, SourceHealth, SourceStatus,
};
use crate::sitl::Sensors;

use super::stale_check::StaleCheck;
use crate::telemetry::{FilterSnapshot, FreshReadings, GpsSnapshot, NavSnapshot, SensorHealth, SensorState};

/// A sensor silent this long is reported unhealthy, and a silent GPS as lost (PX4's health
/// checks and GPS_RAW_INT) [s].
const SENSOR_SILENT_S: f64 = 1.0;
/// A reading this recent is new for a 50 Hz message (HIGHRES_IMU's `fields_updated`) [s].
const FRESH_S: f64 = 0.02;
/// Cut-off of the body rates the controllers read [Hz] (PX4's `IMU_GYRO_CUTOFF`, 40 Hz)
/// (docs/navigation_filter.md §17).
pub const GYRO_CUTOFF_HZ: f64 = 40.0;
/// Cut-off of the velocity the controllers read [Hz]: filtering the integrated acceleration as
/// PX4 filters the acceleration (`IMU_ACCEL_CUTOFF`, 30 Hz) (docs/navigation_filter.md §17).
pub const ACCEL_CUTOFF_HZ: f64 = 30.0;
/// Tick the output filters are designed for [s].
const TICK_S: f64 = 1e-3;

/// The latest raw readings, for telemetry.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct LatestReadings {
    imu_s: Option<f64>,
    gps: Option<GpsReading>,
    mag: Option<MagReading>,
    baro: Option<BaroReading>,
}

/// The state sensor passed through, or the navigation filter.
#[derive(Debug, Clone)]
pub struct StateSource {
    filter: NavFilter,
    /// The latest state flown on; `None` before the first tick.
    latest: Option<VehicleState>,
    /// The filter's report as of the last reading, once the sensor suite is read (`None` while
    /// the state sensor is): taken once per tick for everything that asks.
    status: Option<NavStatus>,
    readings: LatestReadings,
    /// The low-passes of the rates and the velocity the controllers fly on (filter only).
    gyro_lpf: LowPass3,
    vel_lpf: LowPass3,
    /// What has been announced of the GPS, barometer and magnetometer, and the height source.
    announced: Announced,
    /// The stale checks of the barometer (pressure, temperature) and magnetometer (field):
    /// a stuck sensor is not handed to the filter.
    baro_stale: StaleCheck<2>,
    mag_stale: StaleCheck<3>,
}

/// Where a sensor stands in the announcements.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
enum SensorNews {
    /// Not usable yet: its first data is no news.
    #[default]
    NeverUsable,
    /// Usable.
    Usable,
    /// Announced lost.
    Lost,
}

/// The announcements' memory.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct Announced {
    /// GPS, barometer, magnetometer.
    sources: [SensorNews; 3],
    /// The height source last seen.
    height: Option<HeightSource>,
}

/// A navigator with PX4's default filter settings at PX4's default home, where the plant is by
/// default.
impl Default for StateSource {
    fn default() -> Self {
        Self::at(&Home::default())
    }
}

impl StateSource {
    /// A navigator with PX4's default filter settings at `home`: the filter knows the World
    /// Magnetic Model's declination there, as PX4's looks it up at its GNSS origin
    /// (docs/navigation_filter.md §10, eq. (10.5)).
    pub fn at(home: &Home) -> Self {
        let mut filter = NavFilter::default();
        filter.set_geo_declination(crate::sitl::magnetic_declination_rad(home));
        Self::with_filter(filter)
    }

    fn with_filter(filter: NavFilter) -> Self {
        Self {
            filter,
            latest: None,
            status: None,
            readings: LatestReadings::default(),
            gyro_lpf: LowPass3::new(GYRO_CUTOFF_HZ, TICK_S),
            vel_lpf: LowPass3::new(ACCEL_CUTOFF_HZ, TICK_S),
            announced: Announced::default(),
            baro_stale: StaleCheck::default(),
            mag_stale: StaleCheck::default(),
        }
    }

    /// Announces that the sensor suite, not the state sensor, will be read: the validity is the
    /// filter's from now on (nothing is valid before its alignment).
    pub fn expect_sensor_suite(&mut self) {
        self.status = Some(self.filter.status());
    }

    /// Starts the filter aligned at the vehicle's known state `x` (a headless run that starts
    /// in the air; docs/navigation_filter.md §11), instead of aligning at rest.
    pub fn start_at(&mut self, x: &VehicleState) {
        let q_wb = crate::math::UnitQuat::from_matrix(&x.r_wb);
        self.filter.align_at(x.t_s, x.pos_w, x.vel_w, q_wb);
        self.status = Some(self.filter.status());
    }

    /// A navigator whose filter, when the sensor suite is read, has `params` (and no World
    /// Magnetic Model declination: `EKF2_MAG_DECL` is the declination).
    pub fn new(params: NavParams) -> Result<Self, NavParamsError> {
        Ok(Self::with_filter(NavFilter::new(params)?))
    }

    /// The declination the filter's magnetometer heading uses [rad]
    /// ([`NavFilter::declination_rad`]).
    pub fn declination_rad(&self) -> f64 {
        self.filter.declination_rad()
    }

    /// The filter's settings.
    pub fn params(&self) -> &NavParams {
        self.filter.params()
    }

    /// Changes the filter's settings (the estimate carries on).
    pub fn set_params(&mut self, params: NavParams) -> Result<(), NavParamsError> {
        self.filter.set_params(params)
    }

    /// The state for tick `t_s` [s] from its readings: the state sensor's when there is one,
    /// else the filter's estimate after predicting with the IMU sample and fusing whatever
    /// arrived (GPS, barometer, magnetometer), in the filter's frame; the rates
    /// and the velocity low-passed as PX4's controllers read them (docs/navigation_filter.md §17).
    pub fn update(&mut self, t_s: f64, sensors: &Sensors) -> VehicleState {
        if let Some(x) = sensors.state {
            self.latest = Some(x);
            return x;
        }
        if let Some(imu) = &sensors.imu {
            self.filter.predict(imu);
            self.readings.imu_s = Some(imu.t_s);
        }
        if let Some(gps) = &sensors.gps {
            self.filter.fuse_gps(gps);
            self.readings.gps = Some(*gps);
        }
        if let Some(baro) = &sensors.baro {
            if self.baro_stale.accept([baro.pressure_pa, baro.temperature_c]) {
                self.filter.fuse_baro(baro);
            }
            self.readings.baro = Some(*baro);
        }
        if let Some(mag) = &sensors.mag {
            let m = mag.field_b;
            if self.mag_stale.accept([m.x, m.y, m.z]) {
                self.filter.fuse_mag(mag);
            }
            self.readings.mag = Some(*mag);
        }
        self.status = Some(self.filter.status());
        let mut x = self.filter_state(t_s);
        x.omega_b = self.gyro_lpf.update(x.omega_b);
        x.vel_w = self.vel_lpf.update(x.vel_w);
        self.latest = Some(x);
        x
    }

    /// The filter's output (docs/navigation_filter.md §16) as a vehicle state at `t_s` [s],
    /// position in the filter's own frame: its origin is where the vehicle stood when the filter
    /// aligned (z = 0 there, as PX4's local frame), and the GPS readings' offset from it is
    /// [`NavFilter::origin_w`] (the receiver's error at the first fix included).
    fn filter_state(&self, t_s: f64) -> VehicleState {
        let out = self.filter.output();
        VehicleState {
            t_s,
            pos_w: out.pos_w,
            vel_w: out.vel_w,
            r_wb: Mat3::from(out.q_wb.to_rotation_matrix()),
            omega_b: out.omega_b,
        }
    }

    /// What changed in the sensors the filter uses since the last call, as announcements (a
    /// sensor lost, or back after a loss; the height source switched), each with whether it is
    /// a warning; empty with the state sensor and before the filter is aligned.
    pub fn announcements(&mut self) -> Vec<(String, bool)> {
        let Some(status) = self.status().filter(|s| s.attitude_valid) else {
            return Vec::new();
        };
        // Lost means silent for the sensor time-out (or never heard): a sample skipped or
        // rejected now and then is no news.
        let usable = |s: &SourceStatus| !matches!(s.health, SourceHealth::TimedOut | SourceHealth::NoData);
        let mut out = Vec::new();
        let sources = [
            (usable(&status.gps), "GPS lost: dead reckoning", "GPS regained"),
            (usable(&status.baro), "Barometer lost", "Barometer regained"),
            (
                usable(&status.mag),
                "Compass lost: heading from gyro and GPS",
                "Compass regained",
            ),
        ];
        for (track, (now, lost, back)) in self.announced.sources.iter_mut().zip(sources) {
            match (*track, now) {
                (SensorNews::Usable, false) => {
                    *track = SensorNews::Lost;
                    out.push((lost.to_string(), true));
                }
                (SensorNews::Lost, true) => {
                    *track = SensorNews::Usable;
                    out.push((back.to_string(), false));
                }
                (SensorNews::NeverUsable, true) => *track = SensorNews::Usable,
                _ => {}
            }
        }
        if self
            .announced
            .height
            .replace(status.active_height)
            .is_some_and(|h| h != status.active_height)
        {
            let text = match status.active_height {
                HeightSource::Gps => "Height source: GPS",
                HeightSource::Baro => "Height source: barometer",
            };
            out.push((text.to_string(), false));
        }
        out
    }

    /// Tells the filter the vehicle is armed: it may leave the height it rested at, so the GNSS
    /// height datum stops averaging (docs/navigation_filter.md §6, eq. (6.5)).
    pub fn armed(&mut self) {
        self.filter.freeze_height_datum();
    }

    /// The latest state flown on, `None` before the first tick.
    pub fn latest(&self) -> Option<VehicleState> {
        self.latest
    }

    /// The filter's report, `None` while the state sensor is read.
    pub fn status(&self) -> Option<NavStatus> {
        self.status
    }

    /// What the estimate can be flown on for.
    pub fn validity(&self) -> NavValidity {
        match self.status() {
            None => NavValidity::EXACT,
            Some(s) => NavValidity {
                attitude: s.attitude_valid && s.yaw_aligned,
                horizontal: s.horizontal_position_valid && s.velocity_valid,
                vertical: s.vertical_position_valid,
                unstable: s.preflight.map(PreflightFailure::text),
            },
        }
    }
}

impl StateSource {
    /// What the links report of the navigation at `t_s` [s]; `armable` is the commander's
    /// verdict on arming now.
    pub fn snapshot(&self, t_s: f64, armable: bool) -> NavSnapshot {
        let Some(status) = self.status() else {
            return NavSnapshot {
                armable,
                ..NavSnapshot::EXACT
            };
        };
        let validity = self.validity();
        let fused = |s: &SourceStatus| s.health == SourceHealth::Fused;
        let age = |t: Option<f64>| t.map_or(f64::INFINITY, |t| t_s - t);
        let (imu_age, gps_age) = (age(self.readings.imu_s), age(self.readings.gps.map(|g| g.t_s)));
        let (mag_age, baro_age) = (
            age(self.readings.mag.map(|m| m.t_s)),
            age(self.readings.baro.map(|b| b.t_s)),
        );
        let imu = SensorState {
            present: true,
            healthy: imu_age <= SENSOR_SILENT_S,
        };
        let e = self.filter.estimate();
        let mut flags = 0u16;
        for (bit, on) in [
            (ESTIMATOR_ATTITUDE, status.attitude_valid),
            (ESTIMATOR_VELOCITY_HORIZ, status.velocity_valid),
            (
                ESTIMATOR_VELOCITY_VERT,
                status.velocity_valid || status.vertical_position_valid,
            ),
            (ESTIMATOR_POS_HORIZ_REL, validity.horizontal),
            (
                ESTIMATOR_POS_HORIZ_ABS,
                validity.horizontal && status.origin_w.is_some(),
            ),
            (ESTIMATOR_POS_VERT_ABS, validity.vertical),
            (ESTIMATOR_POS_VERT_AGL, validity.vertical),
            (ESTIMATOR_CONST_POS_MODE, status.position_hold),
            (ESTIMATOR_PRED_POS_HORIZ_REL, validity.horizontal),
            (
                ESTIMATOR_PRED_POS_HORIZ_ABS,
                validity.horizontal && status.origin_w.is_some(),
            ),
            (ESTIMATOR_GPS_GLITCH, status.gps.health == SourceHealth::Rejected),
        ] {
            if on {
                flags |= bit;
            }
        }
        let r = status.test_ratios;
        NavSnapshot {
            validity,
            armable,
            sensors: SensorHealth {
                gyro: imu,
                accel: imu,
                mag: SensorState {
                    present: true,
                    healthy: mag_age <= SENSOR_SILENT_S && fused(&status.mag),
                },
                baro: SensorState {
                    present: true,
                    healthy: baro_age <= SENSOR_SILENT_S && fused(&status.baro),
                },
                // Present while the filter takes its position, as PX4 reports it.
                gps: SensorState {
                    present: fused(&status.gps) && validity.horizontal,
                    healthy: gps_age <= SENSOR_SILENT_S && fused(&status.gps) && validity.horizontal,
                },
            },
            fresh: FreshReadings {
                imu: imu_age <= FRESH_S,
                mag: mag_age <= FRESH_S,
                baro: baro_age <= FRESH_S,
                baro_alive: baro_age <= SENSOR_SILENT_S,
            },
            gps: self.readings.gps.map(|g| GpsSnapshot {
                pos_w: g.pos_w,
                vel_w: g.vel_w,
                acc_m: (g.h_acc_m, g.v_acc_m),
                speed_acc_m_s: g.speed_acc_m_s,
                fix_3d: g.fix_3d,
                satellites: g.satellites,
                silent: gps_age > SENSOR_SILENT_S,
            }),
            mag_b: self.readings.mag.map(|m| m.field_b),
            baro: self.readings.baro.map(|b| (b.pressure_pa, b.temperature_c)),
            suite: true,
            filter: Some(FilterSnapshot {
                flags,
                test_ratios: [
                    r.gps_velocity,
                    r.gps_horizontal,
                    r.gps_height.max(r.baro_height),
                    r.heading,
                    match status.active_height {
                        HeightSource::Baro => r.baro_height,
                        HeightSource::Gps => r.gps_height,
                    },
                ],
                pos_std_m: (e.pos_std_w.xy().norm(), e.pos_std_w.z),
                vel_std_m_s: e.vel_std_w.max(),
                heading_std_rad: e.att_std_w.z,
            }),
        }
    }
}

/// ESTIMATOR_STATUS_FLAGS (MAVLink common).
const ESTIMATOR_ATTITUDE: u16 = 1;
const ESTIMATOR_VELOCITY_HORIZ: u16 = 2;
const ESTIMATOR_VELOCITY_VERT: u16 = 4;
const ESTIMATOR_POS_HORIZ_REL: u16 = 8;
const ESTIMATOR_POS_HORIZ_ABS: u16 = 16;
const ESTIMATOR_POS_VERT_ABS: u16 = 32;
const ESTIMATOR_POS_VERT_AGL: u16 = 64;
const ESTIMATOR_CONST_POS_MODE: u16 = 128;
const ESTIMATOR_PRED_POS_HORIZ_REL: u16 = 256;
const ESTIMATOR_PRED_POS_HORIZ_ABS: u16 = 512;
const ESTIMATOR_GPS_GLITCH: u16 = 1024;
