//! Test helpers: random sample times and central-difference checks of a trajectory's derivatives.

use super::TrajectorySample;
use crate::math::{wrap_pi, Vec3};
use rand_chacha::rand_core::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// `n` times [s] drawn uniformly from [lo, hi) with a seeded generator.
pub(crate) fn random_times(seed: u64, lo: f64, hi: f64, n: usize) -> Vec<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..n)
        .map(|_| lo + (hi - lo) * (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64)
        .collect()
}

fn close(fd: Vec3, exact: Vec3, what: &str, t: f64) {
    let err = (fd - exact).norm();
    assert!(
        err < 1e-6 * (1.0 + exact.norm()),
        "{what} at t = {t}: fd {fd:?} vs {exact:?}"
    );
}

/// Checks pos→vel→acc→jerk and yaw→rate→acc by central differences (step 1 µs) at `times`.
pub(crate) fn assert_derivatives(f: impl Fn(f64) -> TrajectorySample, times: &[f64]) {
    let h = 1e-6;
    for &t in times {
        let (a, m, b) = (f(t - h), f(t), f(t + h));
        let d = |x: Vec3, y: Vec3| (y - x) / (2.0 * h);
        close(d(a.pos_w, b.pos_w), m.vel_w, "velocity", t);
        close(d(a.vel_w, b.vel_w), m.acc_w, "acceleration", t);
        close(d(a.acc_w, b.acc_w), m.jerk_w, "jerk", t);
        let rate = wrap_pi(b.yaw_rad - a.yaw_rad) / (2.0 * h);
        let acc = (b.yaw_rate_rad_s - a.yaw_rate_rad_s) / (2.0 * h);
        let (r, c) = (m.yaw_rate_rad_s, m.yaw_acc_rad_s2);
        assert!((rate - r).abs() < 1e-6 * (1.0 + r.abs()), "yaw rate at t = {t}");
        assert!((acc - c).abs() < 1e-6 * (1.0 + c.abs()), "yaw acc at t = {t}");
    }
}

/// Checks that position, velocity, acceleration and yaw rate are continuous at `t` [s].
pub(crate) fn assert_continuous(f: impl Fn(f64) -> TrajectorySample, t: f64) {
    let (a, b) = (f(t - 1e-9), f(t + 1e-9));
    for (x, y, what) in [
        (a.pos_w, b.pos_w, "position"),
        (a.vel_w, b.vel_w, "velocity"),
        (a.acc_w, b.acc_w, "acceleration"),
    ] {
        assert!((x - y).norm() < 1e-6, "{what} jumps at t = {t}: {x:?} → {y:?}");
    }
    assert!(wrap_pi(a.yaw_rad - b.yaw_rad).abs() < 1e-6, "yaw jumps at t = {t}");
    assert!(
        (a.yaw_rate_rad_s - b.yaw_rate_rad_s).abs() < 1e-6,
        "yaw rate jumps at t = {t}"
    );
}
