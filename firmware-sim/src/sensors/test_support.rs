//! Helpers shared by the sensor models' unit tests.

use nalgebra::{UnitQuaternion, Vector3};

use crate::plant::TruthState;
use crate::rigid_body::RigidBodyState;

/// The vehicle at rest, level, 1 m above the origin, at time `t_s` [s].
pub(crate) fn truth_at(t_s: f64) -> TruthState {
    TruthState {
        t_s,
        body: RigidBodyState {
            pos_w: Vector3::new(0.0, 0.0, -1.0),
            vel_w: Vector3::zeros(),
            q_wb: UnitQuaternion::identity(),
            omega_b: Vector3::zeros(),
        },
        accel_w: Vector3::zeros(),
        mean_omega_b: Vector3::zeros(),
        on_ground: false,
        at_ceiling: false,
        external_force_w: Vector3::zeros(),
        external_torque_b: Vector3::zeros(),
        wind_w: Vector3::zeros(),
        drag_force_w: Vector3::zeros(),
    }
}

/// Time of plant tick `i` at 1 kHz, as the plant reports it (whole nanoseconds) [s].
pub(crate) fn tick_s(i: u64) -> f64 {
    (i * 1_000_000) as f64 * 1e-9
}

/// Sample mean and (biased) variance of `xs`.
pub(crate) fn stats(xs: &[f64]) -> (f64, f64) {
    let n = xs.len() as f64;
    let mean = xs.iter().sum::<f64>() / n;
    let var = xs.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / n;
    (mean, var)
}

/// Mean and variance over every component of `xs`.
pub(crate) fn vec_stats(xs: &[Vector3<f64>]) -> (f64, f64) {
    let flat: Vec<f64> = xs.iter().flat_map(|v| v.iter().copied()).collect();
    stats(&flat)
}
