//! Convergence from the alignment, tracking with ideal sensors, and the benefit of fusing
//! GNSS at its time of validity (docs/navigation_filter.md §7, §11, §15).

use super::truth::{Motion, SimulatedErrors, Truth, DECLINATION_RAD};
use super::{errors, run, Faults};
use crate::math::Vec3;
use crate::nav_filter::{NavFilter, NavParams, SourceHealth};

/// Largest errors over a time window: position [m], velocity [m/s], attitude [rad], and the
/// final bias errors.
#[derive(Debug, Default)]
struct Worst {
    pos: f64,
    vel: f64,
    att: f64,
    accel_bias: Vec3,
    gyro_bias: Vec3,
}

fn worst_after(
    params: NavParams,
    errors_in: SimulatedErrors,
    motion: Motion,
    seed: u64,
    from_s: f64,
    to_s: f64,
) -> Worst {
    let mut truth = Truth::new(motion, errors_in, seed);
    let mut filter = NavFilter::new(params).unwrap();
    let mut w = Worst::default();
    run(&mut truth, &mut filter, &Faults::default(), to_s, |s| {
        if s.truth.t_s >= from_s {
            let (dp, dv, dth) = errors(s.filter, &s.truth);
            w.pos = w.pos.max(dp.norm());
            w.vel = w.vel.max(dv.norm());
            w.att = w.att.max(dth.norm());
            let est = s.filter.estimate();
            w.accel_bias = (est.accel_bias_b - s.biases.0).abs();
            w.gyro_bias = (est.gyro_bias_b - s.biases.1).abs();
        }
    });
    w
}

#[test]
fn converges_from_alignment_with_biases_and_noise() {
    let e = SimulatedErrors::realistic();
    let w = worst_after(e.matched_params(), e, Motion::curves(), 1, 60.0, 120.0);
    assert!(w.att.to_degrees() < 1.0, "{w:?}");
    assert!(w.pos < 1.0, "{w:?}");
    assert!(w.vel < 0.3, "{w:?}");
    // Biases: switch-on values of 0.1 m/s² and 0.01 rad/s learned to a few per cent.
    assert!(w.gyro_bias.max() < 1e-3, "{w:?}");
    assert!(w.accel_bias.max() < 0.03, "{w:?}");
}

#[test]
fn converges_with_px4_default_tuning() {
    let e = SimulatedErrors::realistic();
    // The declination PX4 would look up where the simulated field is.
    let params = NavParams {
        baro_noise_m: 1.0,
        mag_declination_rad: DECLINATION_RAD,
        ..NavParams::default()
    };
    let w = worst_after(params, e, Motion::curves(), 2, 60.0, 120.0);
    assert!(w.att.to_degrees() < 1.5, "{w:?}");
    assert!(w.pos < 1.5, "{w:?}");
    assert!(w.gyro_bias.max() < 2e-3, "{w:?}");
}

#[test]
fn ideal_sensors_track_the_truth_tightly() {
    let e = SimulatedErrors::ideal();
    let w = worst_after(e.matched_params(), e, Motion::curves(), 3, 2.0, 60.0);
    assert!(w.pos < 2e-3, "{w:?}");
    assert!(w.vel < 2e-3, "{w:?}");
    assert!(w.att.to_degrees() < 0.05, "{w:?}");
    assert!(w.gyro_bias.max() < 1e-5 && w.accel_bias.max() < 1e-3, "{w:?}");
}

#[test]
fn alignment_sets_attitude_origin_and_flags() {
    let e = SimulatedErrors::realistic();
    let params = e.matched_params();
    let mut truth = Truth::new(Motion::hover(2.5), e, 4);
    let mut filter = NavFilter::new(params).unwrap();
    let mut before = None;
    run(&mut truth, &mut filter, &Faults::default(), 3.0, |s| {
        if (s.truth.t_s - 0.5).abs() < 1e-9 {
            before = Some(s.filter.status());
        }
    });
    let before = before.unwrap();
    assert!(!before.attitude_valid && !before.horizontal_position_valid && !before.vertical_position_valid);
    let st = filter.status();
    assert!(st.attitude_valid && st.yaw_aligned && st.horizontal_position_valid && st.velocity_valid);
    assert!(st.vertical_position_valid);
    assert_eq!(st.mag.health, SourceHealth::Fused);
    let est = filter.estimate();
    let (roll, pitch, yaw) = est.q_wb.euler_angles();
    // Tilt error of an unknown accelerometer bias b is about b / g (0.15 / 9.81 rad at most).
    assert!(roll.abs() < 0.02 && pitch.abs() < 0.02, "{roll} {pitch}");
    assert!((yaw - 2.5).abs() < 2f64.to_radians(), "{yaw}");
    assert!(st.origin_w.is_some() && st.baro_origin_m.is_some());
}

/// RMS position error [m] over [20 s, 90 s] with the filter told `assumed_delay_s`.
fn rms_position_error(assumed_delay_s: f64, seed: u64) -> f64 {
    let e = SimulatedErrors {
        gps_h: 0.1,
        gps_v: 0.15,
        gps_vel: 0.05,
        ..SimulatedErrors::realistic()
    };
    let params = NavParams {
        gps_delay_s: assumed_delay_s,
        ..e.matched_params()
    };
    let mut motion = Motion::curves();
    motion.pos_amp = Vec3::new(40.0, -30.0, -5.0);
    let mut truth = Truth::new(motion, e, seed);
    let mut filter = NavFilter::new(params).unwrap();
    let (mut sum, mut n) = (0.0, 0.0);
    run(&mut truth, &mut filter, &Faults::default(), 90.0, |s| {
        if s.truth.t_s >= 20.0 {
            sum += errors(s.filter, &s.truth).0.norm_squared();
            n += 1.0;
        }
    });
    (sum / n).sqrt()
}

#[test]
fn fusing_gps_at_its_time_of_validity_beats_ignoring_the_delay() {
    let delayed = rms_position_error(0.11, 5);
    let undelayed = rms_position_error(0.0, 5);
    assert!(
        delayed < 0.6 * undelayed,
        "delayed {delayed} m, as if undelayed {undelayed} m"
    );
    assert!(delayed < 0.15, "{delayed}");
}
