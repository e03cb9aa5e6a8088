use super::*;
use crate::math::GRAVITY_M_S2;
use crate::nav_filter::alignment::initial_covariance;
use crate::nav_filter::covariance::ScalarObservation;

fn still(t_s: f64) -> ImuReading {
    ImuReading {
        t_s,
        accel_b: Vec3::new(0.0, 0.0, -GRAVITY_M_S2),
        gyro_b: Vec3::zeros(),
    }
}

fn aligned(params: &NavParams) -> ErrorStateFilter {
    let mut core = ErrorStateFilter::new();
    let p = initial_covariance(params, HeightSource::Gps, &UnitQuat::identity(), 1.0);
    core.restart(Nominal::default(), p);
    core
}

#[test]
fn repeated_and_non_finite_samples_are_dropped_and_gaps_are_not_integrated() {
    let mut core = ErrorStateFilter::new();
    assert_eq!(core.accept_imu(&still(0.0)), Some(None));
    assert_eq!(core.accept_imu(&still(0.0)), None);
    let mut bad = still(0.001);
    bad.gyro_b.x = f64::NAN;
    assert_eq!(core.accept_imu(&bad), None);
    assert_eq!(core.imu_dropped, 2);
    let prev = core.accept_imu(&still(0.001)).unwrap();
    assert_eq!(prev, Some(still(0.0)));
    assert_eq!(core.t_s, 0.001);
    let interval = core.propagate(prev, &still(0.001), 0.25).unwrap();
    assert!((interval.dt_s - 0.001).abs() < 1e-15);
    assert!(
        core.propagate(None, &still(0.002), 0.25).is_none(),
        "no previous sample"
    );
    assert!(core.propagate(Some(still(0.0)), &still(0.5), 0.25).is_none(), "a gap");
    assert_eq!(core.imu_dropped, 3);
}

#[test]
fn the_covariance_is_predicted_once_the_period_has_accumulated() {
    let params = NavParams::default();
    let mut core = aligned(&params);
    let p0 = core.p;
    core.accept_imu(&still(0.0));
    let mut k = 1;
    while !core.prediction_due(params.predict_period_s) {
        let imu = still(1e-3 * f64::from(k));
        let prev = core.accept_imu(&imu).unwrap();
        assert!(core.propagate(prev, &imu, params.output_tau_s).is_some());
        k += 1;
    }
    assert_eq!(k, 11, "10 ms at 1 kHz");
    assert_eq!(core.p, p0, "nothing predicted before the flush");
    core.flush_covariance(&params, HeightSource::Gps);
    assert!(core.p[(ERR_POS, ERR_POS)] > p0[(ERR_POS, ERR_POS)]);
    let p1 = core.p;
    core.flush_covariance(&params, HeightSource::Gps);
    assert_eq!(core.p, p1, "nothing accumulated since");
}

#[test]
fn a_fused_correction_moves_the_state_and_reaches_the_output_gradually() {
    let params = NavParams::default();
    let mut core = aligned(&params);
    let group = [ScalarObservation::of_state(ERR_POS, 0.2, 0.25)];
    let (f, var) = core.fuse_gated(&group, 5.0, &params);
    assert_eq!(f.outcome, FusionOutcome::Fused);
    assert_eq!(var.x, 0.5, "S = P + r");
    assert!((core.x.pos_w.x - 0.1).abs() < 1e-12);
    assert_eq!(core.output().pos_w.x, 0.0, "the output has not moved yet");
    assert_eq!(core.estimate().pos_w.x, core.x.pos_w.x);
    assert!(
        (core.past(0.0).unwrap().pos_w.x - 0.1).abs() < 1e-12,
        "the history is corrected"
    );
    // 20 σ away: rejected, nothing changes.
    let p = core.p;
    let far = [ScalarObservation::of_state(ERR_POS, 20.0, 0.25)];
    let (f, _) = core.fuse_gated(&far, 5.0, &params);
    assert_eq!(f.outcome, FusionOutcome::Rejected);
    assert!(f.test_ratio > 1.0);
    assert_eq!(core.p, p);
}

#[test]
fn a_yaw_turn_turns_the_state_its_history_and_the_tilt_covariance() {
    let params = NavParams::default();
    let mut core = aligned(&params);
    core.p[(ERR_ATT, ERR_ATT)] = 4e-4;
    core.p[(ERR_ATT + 1, ERR_ATT + 1)] = 1e-4;
    core.turn_yaw(std::f64::consts::FRAC_PI_2, &params);
    let (_, _, yaw) = core.x.q_wb.euler_angles();
    assert!((yaw - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
    assert!(core.past(0.0).unwrap().q_wb.angle_to(&core.x.q_wb) < 1e-12);
    assert!((core.p[(ERR_ATT, ERR_ATT)] - 1e-4).abs() < 1e-15, "north and east swap");
    assert!((core.p[(ERR_ATT + 1, ERR_ATT + 1)] - 4e-4).abs() < 1e-15);
    core.yaw_covariance_from_heading(&Vec3::new(0.0, 0.0, 1.0), 0.1);
    assert!((core.p[(ERR_ATT + 2, ERR_ATT + 2)] - 0.01).abs() < 1e-15);
    assert_eq!(core.p[(ERR_ATT + 2, ERR_ATT)], 0.0);
}
