use super::*;
use crate::nav_filter::alignment::initial_covariance;
use crate::nav_filter::state::Nominal;
use crate::nav_filter::{ImuReading, NavFilter, NavParams};

/// Level and turning about the vertical at 0.1 rad/s (so not at rest), from `t_s` [s].
fn turning(t_s: f64) -> ImuReading {
    ImuReading {
        t_s,
        accel_b: Vec3::new(0.0, 0.0, -GRAVITY_M_S2),
        gyro_b: Vec3::new(0.0, 0.0, 0.1),
    }
}

/// A filter with a well-learned accelerometer bias, started at `q_est` with nothing aiding,
/// fed `seconds` of IMU samples at 250 Hz of a level vehicle turning slowly, and nothing else.
fn run(imu_ctrl: u8, q_est: UnitQuat, seconds: f64) -> NavFilter {
    let params = NavParams {
        imu_ctrl,
        gravity_noise_g: 0.1,
        accel_bias_init_m_s2: 0.02,
        ..NavParams::default()
    };
    let mut f = NavFilter::new(params).unwrap();
    f.align_at(0.0, Vec3::zeros(), Vec3::zeros(), q_est);
    f.aiding.last_aiding_s = None;
    let n = (seconds * 250.0) as usize;
    for i in 0..=n {
        f.predict(&turning(i as f64 / 250.0));
    }
    f
}

fn tilt(f: &NavFilter) -> f64 {
    let (roll, pitch, _) = f.estimate().q_wb.euler_angles();
    roll.hypot(pitch)
}

#[test]
fn jacobian_matches_finite_differences() {
    let q = UnitQuat::from_euler_angles(0.3, -0.2, 1.0);
    let (up, jac) = predicted_up(&q);
    assert!((up.norm() - 1.0).abs() < 1e-12);
    let eps = 1e-6;
    for axis in 0..3 {
        let mut d = Vec3::zeros();
        d[axis] = eps;
        let (up_d, _) = predicted_up(&(UnitQuat::from_scaled_axis(d) * q));
        let numeric = (up_d - up) / eps;
        assert!((numeric - jac.column(axis)).norm() < 1e-5, "axis {axis}");
    }
    // A yaw error does not change the up direction.
    assert!(jac.column(2).norm() < 1e-12);
}

#[test]
fn noise_has_a_floor() {
    assert_eq!(gravity_noise(1.0), 1.0);
    assert_eq!(gravity_noise(0.001), 0.01);
}

#[test]
fn tilt_error_is_corrected_without_gnss() {
    // 0.83° of tilt error, no position hold (the vehicle turns), only the gravity vector levels.
    let q_est = UnitQuat::from_euler_angles(0.012, -0.008, 0.0);
    let initial = tilt(&run(7, q_est, 0.0));
    let early = tilt(&run(7, q_est, 10.0));
    let late = tilt(&run(7, q_est, 40.0));
    assert!(late < 0.25 * initial && late < early, "{initial} {early} {late}");
}

#[test]
fn nothing_is_fused_while_accelerating_or_aided() {
    let mut f = NavFilter::new(NavParams::default()).unwrap();
    let q_est = UnitQuat::from_euler_angles(0.1, 0.0, 0.0);
    f.align_at(0.0, Vec3::zeros(), Vec3::zeros(), q_est);
    f.aiding.last_aiding_s = None;
    let hard = Vec3::new(0.0, 0.0, -2.5 * GRAVITY_M_S2);
    f.gravity.add(&hard, 1.0);
    let p_before = f.core.p;
    let fusion = f.fuse_gravity(&hard);
    assert_eq!(fusion.outcome, FusionOutcome::Skipped(SkipReason::Geometry));
    assert_eq!(f.estimate().q_wb, q_est);
    assert_eq!(f.core.p, p_before);
    // Near 1 g but with GNSS aiding the state a moment ago: not fused either.
    let level = Vec3::new(0.0, 0.0, -GRAVITY_M_S2);
    f.gravity.add(&level, 1.0);
    f.aiding.last_aiding_s = Some(0.0);
    assert_eq!(
        f.fuse_gravity(&level).outcome,
        FusionOutcome::Skipped(SkipReason::Inactive)
    );
    f.aiding.last_aiding_s = None;
    assert!(f.fuse_gravity(&level).accepted());
    assert!(f.estimate().q_wb.angle_to(&q_est) > 1e-7);
}

#[test]
fn the_aid_alone_skips_while_gnss_aids_and_levels_at_one_g() {
    let params = NavParams::default();
    let q = UnitQuat::from_euler_angles(0.1, 0.0, 0.0);
    let mut core = ErrorStateFilter::new();
    let x = Nominal {
        q_wb: q,
        ..Nominal::default()
    };
    core.restart(x, initial_covariance(&params, HeightSource::Gps, &q, 1.0));
    let mut aid = GravityAid::default();
    let level = Vec3::new(0.0, 0.0, -GRAVITY_M_S2);
    assert_eq!(
        aid.fuse(&level, false, &mut core, &params, HeightSource::Gps).outcome,
        FusionOutcome::Skipped(SkipReason::Invalid),
        "no magnitude yet"
    );
    aid.add(&level, 1.0);
    assert_eq!(
        aid.fuse(&level, true, &mut core, &params, HeightSource::Gps).outcome,
        FusionOutcome::Skipped(SkipReason::Inactive)
    );
    assert_eq!(core.x.q_wb, q);
    assert!(aid
        .fuse(&level, false, &mut core, &params, HeightSource::Gps)
        .accepted());
    assert!(core.x.q_wb.angle_to(&q) > 1e-7);
    let (_, _, yaw) = core.x.q_wb.euler_angles();
    assert!(yaw.abs() < 1e-12, "never the yaw: {yaw}");
}

#[test]
fn rest_needs_a_second_of_stillness() {
    let mut aid = GravityAid::default();
    let level = Vec3::new(0.0, 0.0, -GRAVITY_M_S2);
    aid.add_rest(&Vec3::zeros(), &level, 0.6);
    assert!(!aid.at_rest());
    aid.add_rest(&Vec3::zeros(), &level, 0.6);
    assert!(aid.at_rest());
    aid.add_rest(&Vec3::new(0.1, 0.0, 0.0), &level, 0.001);
    assert!(!aid.at_rest());
}
