//! Faulty and missing sensors: gates, fall-backs, time-outs, dead reckoning
//! (docs/navigation_filter.md §6, §9, §10, §12, §13).

use super::truth::{Motion, SimulatedErrors, Truth};
use super::{errors, run, Faults};
use crate::math::Vec3;
use crate::nav_filter::{
    FusionOutcome, GpsReading, HeightSource, NavFilter, NavParams, SkipReason, SourceHealth, DEAD_RECKONING_AFTER_S,
};

fn setup(motion: Motion, params: impl FnOnce(NavParams) -> NavParams, seed: u64) -> (Truth, NavFilter) {
    let e = SimulatedErrors::realistic();
    (
        Truth::new(motion, e, seed),
        NavFilter::new(params(e.matched_params())).unwrap(),
    )
}

#[test]
fn a_50_m_gps_jump_is_rejected_and_reported() {
    let (mut truth, mut filter) = setup(Motion::curves(), |p| p, 11);
    let faults = Faults {
        gps_jump: Some((60.0, 63.0, Vec3::new(50.0, 0.0, 0.0))),
        ..Faults::default()
    };
    let (mut rejected, mut velocity_fused, mut worst_pos, mut refused_after) = (0, 0, 0.0_f64, 0);
    let mut reported = false;
    run(&mut truth, &mut filter, &faults, 70.0, |s| {
        let t = s.truth.t_s;
        if (59.0..70.0).contains(&t) {
            worst_pos = worst_pos.max(errors(s.filter, &s.truth).0.norm());
        }
        let Some(g) = s.gps else { return };
        if (60.0..63.0).contains(&t) {
            rejected += usize::from(g.horizontal.outcome == FusionOutcome::Rejected && g.horizontal.test_ratio > 1.0);
            velocity_fused += usize::from(g.velocity.outcome == FusionOutcome::Fused);
            let st = s.filter.status();
            reported |= st.gps.health == SourceHealth::Rejected && st.test_ratios.gps_horizontal > 1.0;
        }
        if t >= 64.0 && g.horizontal.outcome != FusionOutcome::Fused {
            refused_after += 1;
        }
    });
    assert_eq!(rejected, 30, "every fix of the 3 s jump is rejected");
    assert_eq!(velocity_fused, 30, "the velocity is still fused");
    assert!(reported);
    assert!(filter.status().gps.rejected >= 30);
    assert!(worst_pos < 1.0, "{worst_pos}");
    assert_eq!(refused_after, 0, "fused again after the jump");
    assert!(filter.status().horizontal_position_valid);
}

#[test]
fn an_offset_baro_is_rejected_height_falls_back_to_gps_and_the_baro_stays_at_fault() {
    let (mut truth, mut filter) = setup(
        Motion::curves(),
        |p| NavParams {
            height_ref: HeightSource::Baro,
            ..p
        },
        12,
    );
    let faults = Faults {
        baro_offset: Some((60.0, 40.0)),
        ..Faults::default()
    };
    let (mut rejected, mut worst_height, mut gps_active_at, mut checked, mut at_fault) = (0, 0.0_f64, None, 0, 0);
    run(&mut truth, &mut filter, &faults, 100.0, |s| {
        let t = s.truth.t_s;
        let st = s.filter.status();
        if t >= 30.0 {
            worst_height = worst_height.max(errors(s.filter, &s.truth).0.z.abs());
        }
        if (60.0..64.9).contains(&t) {
            rejected += usize::from(s.baro.is_some_and(|b| b.outcome == FusionOutcome::Rejected));
            assert_eq!(st.active_height, HeightSource::Baro);
        }
        if gps_active_at.is_none() && st.active_height == HeightSource::Gps {
            gps_active_at = Some(t);
        }
        if (66.0..69.0).contains(&t) {
            assert_eq!(st.active_height, HeightSource::Gps, "t = {t}");
            assert!(st.vertical_position_valid);
            checked += 1;
        }
        if t >= 70.0 {
            if let Some(b) = s.baro {
                assert_eq!(b.outcome, FusionOutcome::Skipped(SkipReason::Fault), "t = {t}");
                at_fault += 1;
            }
        }
    });
    assert!(at_fault > 1000, "{at_fault}");
    assert!(rejected > 200, "{rejected}");
    let switched = gps_active_at.unwrap();
    assert!((65.0..65.2).contains(&switched), "{switched}");
    assert!(checked > 0);
    assert!(worst_height < 1.0, "{worst_height}");
    // The barometer kept delivering while it failed its gate: it is at fault (PX4's
    // `baro_fault`) and never fused again, nor does it return as the reference.
    let st = filter.status();
    assert_eq!(st.resets.height_source_changes, 1, "{:?}", st.resets);
    assert_eq!(st.active_height, HeightSource::Gps);
    assert!(st.vertical_position_valid);
}

#[test]
fn without_the_magnetometer_yaw_is_held_and_the_mag_times_out() {
    let (mut truth, mut filter) = setup(Motion::hover(1.0), |p| p, 13);
    let faults = Faults {
        mag_off: Some((40.0, 1e9)),
        ..Faults::default()
    };
    let (mut std_before, mut worst_yaw) = (0.0, 0.0_f64);
    run(&mut truth, &mut filter, &faults, 100.0, |s| {
        if (s.truth.t_s - 40.0).abs() < 1e-9 {
            std_before = s.filter.estimate().att_std_w.z;
        }
        if s.truth.t_s >= 40.0 {
            worst_yaw = worst_yaw.max(errors(s.filter, &s.truth).2.z.abs());
        }
    });
    let st = filter.status();
    assert_eq!(st.mag.health, SourceHealth::TimedOut);
    assert!((st.mag.time_since_fused_s.unwrap() - 60.0).abs() < 0.1);
    assert!(st.attitude_valid && st.horizontal_position_valid && st.vertical_position_valid);
    // In a hover the yaw is tied to the unobservable tilt (the field is steep), so it is known to
    // a few degrees only; without the magnetometer it drifts with the gyro bias, within its σ.
    let yaw_std = filter.estimate().att_std_w.z;
    assert!(
        worst_yaw < 3.0 * yaw_std && worst_yaw.to_degrees() < 6.0,
        "{worst_yaw} vs σ {yaw_std}"
    );
    assert!(
        yaw_std > 1.2 * std_before,
        "the yaw uncertainty grows: {std_before} -> {yaw_std}"
    );
}

/// Moving, the GNSS velocity gives the heading (docs/navigation_filter.md §18): without the
/// magnetometer, a right yaw is left to the gyroscope, and a yaw turned 45° off (as a disturbed
/// magnetometer may leave it) is reset to the yaw estimator's heading at the next GNSS fix.
#[test]
fn without_the_magnetometer_a_wrong_yaw_is_reset_to_the_heading_from_gps_velocity() {
    let (mut truth, mut filter) = setup(Motion::curves(), |p| p, 13);
    let kick_s = 90.05;
    let faults = Faults {
        mag_off: Some((40.0, 1e9)),
        yaw_kick: Some((kick_s, 45f64.to_radians())),
        ..Faults::default()
    };
    let (mut resets_before_kick, mut worst_before, mut worst_after) = (None, 0.0_f64, 0.0_f64);
    let mut recovered_at = None;
    run(&mut truth, &mut filter, &faults, 180.0, |s| {
        let t = s.truth.t_s;
        let yaw_err = errors(s.filter, &s.truth).2.z.abs();
        let resets = s.filter.status().resets.yaw;
        if (40.0..kick_s).contains(&t) {
            worst_before = worst_before.max(yaw_err);
            resets_before_kick.get_or_insert(resets);
            assert_eq!(Some(resets), resets_before_kick, "no reset of a right yaw at {t:.2} s");
        } else if t > kick_s && recovered_at.is_none() && Some(resets) > resets_before_kick {
            recovered_at = Some(t);
        } else if recovered_at.is_some() {
            worst_after = worst_after.max(yaw_err);
        }
    });
    assert!(
        worst_before.to_degrees() < 5.0,
        "gyro-held: {:.2}°",
        worst_before.to_degrees()
    );
    let recovered_at = recovered_at.expect("the yaw was reset to the heading from GPS velocity");
    assert!(
        recovered_at - kick_s < 0.2,
        "reset {:.2} s after the kick",
        recovered_at - kick_s
    );
    assert!(
        worst_after.to_degrees() < 5.0,
        "held after: {:.2}°",
        worst_after.to_degrees()
    );
}

#[test]
fn without_gps_horizontal_position_turns_invalid_after_noaid_timeout() {
    // Gravity-vector fusion off (EKF2_IMU_CTRL 3): the position hold levels the filter in flight.
    let (mut truth, mut filter) = setup(Motion::curves(), |p| NavParams { imu_ctrl: 3, ..p }, 14);
    let faults = Faults {
        gps_off: Some((40.0, 1e9)),
        ..Faults::default()
    };
    let noaid = filter.params().noaid_timeout_s;
    let mut worst = (0.0_f64, 0.0_f64);
    let mut statuses = Vec::new();
    run(&mut truth, &mut filter, &faults, 80.0, |s| {
        let t = s.truth.t_s;
        if [40.5, 42.0, 44.5, 45.5, 46.0, 60.0, 80.0]
            .iter()
            .any(|c| (t - c).abs() < 1e-9)
        {
            statuses.push((t, s.filter.status()));
        }
        if t >= 40.0 {
            let (dp, _, dth) = errors(s.filter, &s.truth);
            worst = (worst.0.max(dth.norm()), worst.1.max(dp.z.abs()));
        }
    });
    for (t, st) in &statuses {
        let since = st.time_since_aiding_s.unwrap();
        assert!((since - (t - 39.9)).abs() < 0.05, "t = {t}: {since}");
        assert!(st.attitude_valid && st.vertical_position_valid, "t = {t}");
        assert_eq!(st.horizontal_position_valid, since <= noaid, "t = {t}");
        assert_eq!(st.velocity_valid, since <= noaid, "t = {t}");
        assert_eq!(st.dead_reckoning, since > DEAD_RECKONING_AFTER_S, "t = {t}");
        assert_eq!(st.position_hold, since > noaid, "t = {t}");
        if *t >= 46.0 {
            assert_eq!(st.active_height, HeightSource::Baro, "GNSS height timed out, t = {t}");
            assert_eq!(st.gps.health, SourceHealth::TimedOut);
        }
    }
    // 40 s of manoeuvres held only by the position-hold pseudo-measurement: degraded, not lost.
    assert!(worst.0.to_degrees() < 5.0, "attitude {}°", worst.0.to_degrees());
    assert!(worst.1 < 1.0, "height {} m", worst.1);
}

#[test]
fn without_gps_the_gravity_vector_levels_the_filter_in_flight() {
    let (mut truth, mut filter) = setup(Motion::curves(), |p| p, 14);
    let faults = Faults {
        gps_off: Some((40.0, 1e9)),
        ..Faults::default()
    };
    let mut worst = 0.0_f64;
    let mut held = false;
    run(&mut truth, &mut filter, &faults, 80.0, |s| {
        if s.truth.t_s >= 40.0 {
            let (_, _, dth) = errors(s.filter, &s.truth);
            let tilt = dth.x.hypot(dth.y);
            worst = worst.max(tilt);
            held |= s.filter.status().position_hold;
        }
    });
    // In motion the position hold stays off (PX4's fake position with gravity fusion on).
    assert!(!held);
    assert!(worst.to_degrees() < 5.0, "tilt {}°", worst.to_degrees());
}

#[test]
fn never_any_gps_keeps_attitude_and_baro_height() {
    let (mut truth, mut filter) = setup(Motion::hover(0.3), |p| p, 15);
    let faults = Faults {
        gps_off: Some((0.0, 1e9)),
        ..Faults::default()
    };
    run(&mut truth, &mut filter, &faults, 60.0, |_| {});
    let st = filter.status();
    assert!(st.attitude_valid && st.vertical_position_valid && st.position_hold);
    assert!(!st.horizontal_position_valid && !st.velocity_valid && !st.dead_reckoning);
    assert_eq!((st.origin_w, st.time_since_aiding_s), (None, None));
    assert_eq!(st.active_height, HeightSource::Baro);
    assert_eq!(st.gps.health, SourceHealth::NoData);
    let (dp, dv, dth) = errors(&filter, &truth.motion.at(60.0));
    let est = filter.estimate();
    assert!(dth.norm().to_degrees() < 2.0 && dp.z.abs() < 1.0, "{dp} {dth}");
    assert!(
        (0..3).all(|i| dv[i].abs() < 3.0 * est.vel_std_w[i]),
        "{dv} vs σ {}",
        est.vel_std_w
    );
}

#[test]
fn a_late_magnetometer_sets_the_yaw() {
    let (mut truth, mut filter) = setup(Motion::hover(2.0), |p| p, 16);
    let faults = Faults {
        mag_off: Some((0.0, 3.0)),
        ..Faults::default()
    };
    let mut first = None;
    run(&mut truth, &mut filter, &faults, 30.0, |s| {
        if first.is_none() {
            first = s
                .mag
                .filter(|m| m.outcome != FusionOutcome::Skipped(SkipReason::NotAligned));
            if first.is_some() {
                assert!(s.filter.status().yaw_aligned);
            } else if s.truth.t_s > 1.5 {
                assert!(!s.filter.status().yaw_aligned);
            }
        }
    });
    assert_eq!(first.unwrap().outcome, FusionOutcome::Reset);
    assert_eq!(filter.status().resets.yaw, 1);
    let dth = errors(&filter, &truth.motion.at(30.0)).2;
    let std = filter.estimate().att_std_w;
    assert!(
        dth.z.abs() < 3.0 * std.z && dth.z.abs().to_degrees() < 4.0,
        "{dth} vs σ {std}"
    );
}

#[test]
fn poor_fixes_and_bad_readings_are_skipped_and_counted() {
    let (mut truth, mut filter) = setup(Motion::hover(0.0), |p| p, 17);
    run(&mut truth, &mut filter, &Faults::default(), 5.0, |_| {});
    let good = truth.gps(5.0);
    let skipped_before = filter.status().gps.skipped;
    let cases = [
        GpsReading { satellites: 4, ..good },
        GpsReading { fix_3d: false, ..good },
        GpsReading { h_acc_m: 8.0, ..good },
    ];
    for c in cases {
        assert_eq!(
            filter.fuse_gps(&c).horizontal.outcome,
            FusionOutcome::Skipped(SkipReason::Quality)
        );
    }
    let nan = GpsReading {
        pos_w: Vec3::new(f64::NAN, 0.0, 0.0),
        ..good
    };
    assert_eq!(
        filter.fuse_gps(&nan).velocity.outcome,
        FusionOutcome::Skipped(SkipReason::Invalid)
    );
    let st = filter.status();
    assert_eq!(st.gps.health, SourceHealth::Unusable);
    assert_eq!(st.gps.skipped - skipped_before, 4);
    let mut baro = truth.baro(5.0, 0.0);
    baro.pressure_pa = -1.0;
    assert_eq!(
        filter.fuse_baro(&baro).outcome,
        FusionOutcome::Skipped(SkipReason::Invalid)
    );
    let before = filter.estimate();
    let mut imu = truth.imu(4.0);
    filter.predict(&imu);
    imu.t_s = 5.001;
    imu.accel_b.x = f64::INFINITY;
    filter.predict(&imu);
    assert_eq!(filter.status().imu_dropped, 2);
    assert_eq!(filter.estimate(), before);
}
