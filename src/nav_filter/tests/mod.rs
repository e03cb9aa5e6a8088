//! Scenario tests of the navigation filter against the truth generator of [`truth`]
//! (docs/navigation_filter.md §15).

mod consistency;
mod convergence;
mod faults;
mod truth;

use nalgebra::Matrix3;

use crate::math::Vec3;
use crate::nav_filter::{Fusion, GpsFusion, NavFilter, ERR_ATT, ERR_POS, ERR_VEL};
use truth::{TrueMotion, Truth, GPS_FRAME_OFFSET, IMU_DT_S};

/// Sensor faults of a run.
#[derive(Debug, Clone, Copy, Default)]
pub struct Faults {
    /// No GNSS in [start, end) [s].
    pub gps_off: Option<(f64, f64)>,
    /// GNSS position shifted by the vector in [start, end) [s].
    pub gps_jump: Option<(f64, f64, Vec3)>,
    /// Barometric altitude offset [m] from a time [s] on.
    pub baro_offset: Option<(f64, f64)>,
    /// No magnetometer in [start, end) [s].
    pub mag_off: Option<(f64, f64)>,
    /// The estimated yaw turned by an angle [rad] at a time [s] (a heading gone wrong).
    pub yaw_kick: Option<(f64, f64)>,
}

/// What the observer sees after each IMU sample.
pub struct Step<'a> {
    pub truth: TrueMotion,
    pub filter: &'a NavFilter,
    pub gps: Option<GpsFusion>,
    pub baro: Option<Fusion>,
    pub mag: Option<Fusion>,
    /// True accelerometer and gyroscope biases.
    pub biases: (Vec3, Vec3),
}

fn inside(window: Option<(f64, f64)>, t: f64) -> bool {
    window.is_some_and(|(a, b)| t >= a && t < b)
}

/// Runs the filter on the truth's readings up to `t_end_s`: IMU at 1 kHz, GNSS at 10 Hz,
/// barometer and magnetometer at 50 Hz; `observe` is called after every IMU sample.
pub fn run(truth: &mut Truth, filter: &mut NavFilter, faults: &Faults, t_end_s: f64, mut observe: impl FnMut(&Step)) {
    let n = (t_end_s / IMU_DT_S).round() as u64;
    for k in 0..=n {
        let t = k as f64 * IMU_DT_S;
        let imu = truth.imu(t);
        filter.predict(&imu);
        if let Some((_, angle)) = faults.yaw_kick.filter(|(at_s, _)| (t - at_s).abs() < 0.5 * IMU_DT_S) {
            filter.core.x.q_wb =
                crate::nav_filter::state::rotate_world(&filter.core.x.q_wb, &Vec3::new(0.0, 0.0, angle));
        }
        let mut gps = None;
        if k % 100 == 0 && !inside(faults.gps_off, t) {
            let mut reading = truth.gps(t);
            if let Some((a, b, jump)) = faults.gps_jump {
                if t >= a && t < b {
                    reading.pos_w += jump;
                }
            }
            gps = Some(filter.fuse_gps(&reading));
        }
        let mut baro = None;
        if k % 20 == 5 {
            let offset = faults.baro_offset.filter(|(t0, _)| t >= *t0).map_or(0.0, |(_, m)| m);
            let reading = truth.baro(t, offset);
            baro = Some(filter.fuse_baro(&reading));
        }
        let mut mag = None;
        if k % 20 == 10 && !inside(faults.mag_off, t) {
            let reading = truth.mag(t);
            mag = Some(filter.fuse_mag(&reading));
        }
        let biases = truth.biases();
        observe(&Step {
            truth: truth.motion.at(t),
            filter,
            gps,
            baro,
            mag,
            biases,
        });
    }
}

/// True minus estimated position (in the filter's frame), velocity and attitude (a world-frame
/// rotation vector), as the error state of docs/navigation_filter.md §1, eq. (1.3).
pub fn errors(filter: &NavFilter, truth: &TrueMotion) -> (Vec3, Vec3, Vec3) {
    let est = filter.estimate();
    let shift = filter.status().origin_w.map_or(Vec3::zeros(), |o| o - GPS_FRAME_OFFSET);
    let dp = truth.pos_w - shift - est.pos_w;
    let dv = truth.vel_w - est.vel_w;
    let dtheta = (truth.q_wb * est.q_wb.inverse()).scaled_axis();
    (dp, dv, dtheta)
}

/// Normalised estimation error squared `eᵀ P_bb⁻¹ e` of the 3×3 block at `i`
/// (docs/navigation_filter.md §15, eq. (15.1)).
pub fn nees(filter: &NavFilter, i: usize, e: &Vec3) -> f64 {
    let block: Matrix3<f64> = filter.covariance().fixed_view::<3, 3>(i, i).into_owned();
    block.try_inverse().map_or(f64::INFINITY, |inv| e.dot(&(inv * e)))
}

/// NEES of position, velocity and attitude.
pub fn nees3(filter: &NavFilter, truth: &TrueMotion) -> [f64; 3] {
    let (dp, dv, dth) = errors(filter, truth);
    [
        nees(filter, ERR_POS, &dp),
        nees(filter, ERR_VEL, &dv),
        nees(filter, ERR_ATT, &dth),
    ]
}
