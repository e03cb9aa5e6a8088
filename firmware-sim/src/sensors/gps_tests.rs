//! Tests of the GPS model (kept apart so that gps.rs stays short).

use super::*;
use crate::sensors::fault::SensorUnit;
use crate::sensors::gauss::seeded_stream;
use crate::sensors::test_support::{stats, tick_s, truth_at};

/// A vehicle flying a straight line at (1, −2, −0.5) m/s from (0, 0, −1) m, at tick `i` (1 kHz).
fn moving_truth(i: u64) -> TruthState {
    let mut truth = truth_at(tick_s(i));
    let v = Vector3::new(1.0, -2.0, -0.5);
    truth.body.vel_w = v;
    truth.body.pos_w = Vector3::new(0.0, 0.0, -1.0) + v * truth.t_s;
    truth
}

#[test]
fn a_sample_arriving_at_t_measures_the_truth_at_t_minus_latency() {
    let config = GpsConfig {
        latency_s: 0.11,
        ..GpsConfig::ideal()
    };
    let mut gps = GpsModel::new(config, seeded_stream(1, 3));
    let mut delivered = Vec::new();
    for i in 0..2000 {
        if let Some(s) = gps.read(&moving_truth(i)) {
            let measured = moving_truth(i - 110);
            assert_eq!(s.t_s, tick_s(i));
            assert_eq!(s.pos_w, measured.body.pos_w);
            assert_eq!(s.vel_w, measured.body.vel_w);
            assert_eq!((s.fix, s.satellites, s.h_acc_m), (GpsFix::Fix3d, 10, 0.9));
            delivered.push(i);
        }
    }
    assert_eq!(delivered, (0..19).map(|k| 100 * k + 110).collect::<Vec<_>>());
}

#[test]
fn ten_hertz_gives_exactly_ten_samples_a_second() {
    for (config, expected) in [(GpsConfig::ideal(), 100), (GpsConfig::typical(), 99)] {
        let mut gps = GpsModel::new(config, seeded_stream(2, 3));
        let n = (0..10_000)
            .filter(|&i| gps.read(&truth_at(tick_s(i))).is_some())
            .count();
        assert_eq!(n, expected, "latency {}", config.latency_s);
    }
    let mut gps = GpsModel::new(
        GpsConfig {
            rate_hz: 5.0,
            ..GpsConfig::ideal()
        },
        seeded_stream(2, 3),
    );
    assert_eq!(
        (0..10_000)
            .filter(|&i| gps.read(&truth_at(tick_s(i))).is_some())
            .count(),
        50
    );
}

/// Position and velocity errors of `n` samples read at the grid times (latency 0).
fn errors(config: GpsConfig, n: u64, seed: u64) -> (Vec<Vector3<f64>>, Vec<Vector3<f64>>) {
    let mut gps = GpsModel::new(config, seeded_stream(seed, 3));
    let (mut dp, mut dv) = (Vec::new(), Vec::new());
    for k in 0..n {
        let truth = truth_at(k as f64 / config.rate_hz);
        if let Some(s) = gps.read(&truth) {
            dp.push(s.pos_w - truth.body.pos_w);
            dv.push(s.vel_w - truth.body.vel_w);
        }
    }
    (dp, dv)
}

fn axis(xs: &[Vector3<f64>], i: usize) -> Vec<f64> {
    xs.iter().map(|v| v[i]).collect()
}

#[test]
fn white_position_and_velocity_noise_have_the_configured_deviations() {
    let config = GpsConfig {
        h_noise_m: 0.3,
        v_noise_m: 0.45,
        vel_noise_m_s: 0.1,
        ..GpsConfig::ideal()
    };
    let n = 30_000;
    let (dp, dv) = errors(config, n, 7);
    assert_eq!(dp.len() as u64, n);
    // Standard error of a variance from m independent values: √(2/m); allow five.
    let tol = |m: usize| 5.0 * (2.0 / m as f64).sqrt();
    let horizontal: Vec<f64> = axis(&dp, 0).into_iter().chain(axis(&dp, 1)).collect();
    for (xs, sd) in [
        (horizontal, 0.3),
        (axis(&dp, 2), 0.45),
        (dv.iter().flat_map(|v| v.iter().copied()).collect(), 0.1),
    ] {
        let (mean, var) = stats(&xs);
        assert!(mean.abs() < 5.0 * sd / (xs.len() as f64).sqrt(), "mean {mean}");
        assert!((var / (sd * sd) - 1.0).abs() < tol(xs.len()), "var {var}, sd {sd}");
    }
}

#[test]
fn wandering_error_is_first_order_gauss_markov() {
    let config = GpsConfig {
        h_wander_m: 0.4,
        v_wander_m: 0.6,
        wander_tau_s: 2.0,
        ..GpsConfig::ideal()
    };
    let (dp, _) = errors(config, 200_000, 9);
    let phi = (-0.1f64 / 2.0).exp();
    // Effective sample size of an AR(1) series for its variance: n (1 − φ²)/(1 + φ²) ≈ 10 000
    // per axis, so √(2/n_eff) ≈ 1.4 %; allow five (two horizontal axes pooled: a bit better).
    let n_eff = 200_000.0 * (1.0 - phi * phi) / (1.0 + phi * phi);
    for (i, sd) in [(0, 0.4), (1, 0.4), (2, 0.6)] {
        let xs = axis(&dp, i);
        let (mean, var) = stats(&xs);
        assert!(
            mean.abs() < 5.0 * sd * ((1.0 + phi) / (1.0 - phi) / 200_000.0f64).sqrt(),
            "mean {mean}"
        );
        assert!(
            (var / (sd * sd) - 1.0).abs() < 5.0 * (2.0 / n_eff).sqrt(),
            "axis {i}: var {var}"
        );
        // Lag-one autocorrelation φ = e^{−Δt/τ} (docs/model.md §10.3, eq. (10.8)); standard error
        // ≈ √((1 − φ²)/n).
        let lag1 = xs.windows(2).map(|w| (w[0] - mean) * (w[1] - mean)).sum::<f64>() / (xs.len() - 1) as f64 / var;
        assert!(
            (lag1 - phi).abs() < 5.0 * ((1.0 - phi * phi) / 200_000.0f64).sqrt(),
            "lag1 {lag1} vs {phi}"
        );
    }
}

#[test]
fn fix_follows_the_satellite_count() {
    let fix = |satellites| {
        GpsConfig {
            satellites,
            ..GpsConfig::typical()
        }
        .fix()
    };
    assert_eq!(
        (fix(0), fix(2), fix(3), fix(4), fix(12)),
        (
            GpsFix::NoFix,
            GpsFix::NoFix,
            GpsFix::Fix2d,
            GpsFix::Fix3d,
            GpsFix::Fix3d
        )
    );
}

#[test]
fn wrong_drift_starts_smoothly_and_its_velocity_is_the_rate_of_its_position() {
    assert_eq!(wrong_drift(0.0), (0.0, 0.0));
    assert_eq!(wrong_drift(-1.0), (0.0, 0.0));
    for s in [0.5, 3.0, 10.0, 40.0] {
        let h = 1e-5;
        let rate = (wrong_drift(s + h).0 - wrong_drift(s - h).0) / (2.0 * h);
        assert!((rate - wrong_drift(s).1).abs() < 1e-6, "s {s}");
    }
    let (p, v) = wrong_drift(100.0);
    assert!((v - GPS_WRONG_DRIFT_M_S).abs() < 1e-6 && (p - 2.0 * (100.0 - 5.0)).abs() < 1e-6);
}

/// A GPS fault context `since_onset_s` [s] after the onset, with onset draw 0.5.
fn ctx(rng: &mut ChaCha8Rng, since_onset_s: f64) -> FaultCtx<'_> {
    FaultCtx {
        unit: SensorUnit::Gps,
        since_onset_s,
        onset_draw: 0.5,
        rng,
    }
}

#[test]
fn wrong_moves_east_with_a_healthy_fix_and_garbage_loses_then_degrades_the_fix() {
    let mut rng = seeded_stream(4, 99);
    let healthy = GpsSample {
        pos_w: Vector3::new(1.0, 2.0, -3.0),
        vel_w: Vector3::new(0.5, 0.0, 0.0),
        h_acc_m: 0.9,
        v_acc_m: 1.78,
        speed_acc_m_s: 0.4,
        fix: GpsFix::Fix3d,
        satellites: 10,
        ..GpsSample::ZERO
    };
    let w = healthy.wrong(&mut ctx(&mut rng, 10.0));
    let (p, v) = wrong_drift(10.0);
    assert_eq!(w.pos_w, healthy.pos_w + Vector3::new(0.0, p, 0.0));
    assert_eq!(w.vel_w, healthy.vel_w + Vector3::new(0.0, v, 0.0));
    assert_eq!(
        (w.fix, w.satellites, w.h_acc_m),
        (healthy.fix, healthy.satellites, healthy.h_acc_m)
    );

    // onset_draw 0.5: blackout 1 + 5·0.5 = 3.5 s.
    let lost = healthy.garbage(&mut ctx(&mut rng, 3.4));
    assert_eq!(
        (lost.fix, lost.satellites, lost.vel_w),
        (GpsFix::NoFix, 0, Vector3::zeros())
    );
    for _ in 0..200 {
        let g = healthy.garbage(&mut ctx(&mut rng, 3.6));
        assert_eq!(g.fix, GpsFix::Fix3d);
        assert!((2..=6).contains(&g.satellites));
        assert!((20.0..40.0).contains(&g.h_acc_m) && (30.0..54.0).contains(&g.v_acc_m));
        assert!((80.0..120.0).contains(&g.speed_acc_m_s));
        let d = g.pos_w - healthy.pos_w;
        assert!(d.x.abs() <= g.h_acc_m && d.y.abs() <= g.h_acc_m && d.z == 0.0);
    }
}
