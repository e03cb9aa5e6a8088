//! Tests of the sensor suite: rates, exactness of the ideal suite, determinism and every fault.

use nalgebra::{UnitQuaternion, Vector3};

use super::*;
use crate::sensors::baro::{isa_altitude_m, isa_pressure_pa, isa_temperature_k};
use crate::sensors::gps::wrong_drift;
use crate::sensors::imu::{GYRO_FULL_SCALE_RAD_S, GYRO_WRONG_OFFSET_RAD_S};
use crate::sensors::test_support::{stats, tick_s, truth_at};
use crate::GRAVITY_M_S2;

/// A vehicle weaving, climbing and turning, at plant tick `i` (1 kHz).
fn flying(i: u64) -> TruthState {
    let mut truth = truth_at(tick_s(i));
    let t = truth.t_s;
    truth.body.pos_w = Vector3::new(t.sin(), 0.5 * t, -2.0 - 0.1 * t);
    truth.body.vel_w = Vector3::new(t.cos(), 0.5, -0.1);
    truth.body.q_wb = UnitQuaternion::from_euler_angles(0.1 * t.sin(), 0.05 * t.cos(), 0.2 * t);
    truth.body.omega_b = Vector3::new(0.1 * t.cos(), -0.05 * t.sin(), 0.2);
    truth.mean_omega_b = truth.body.omega_b;
    truth.accel_w = Vector3::new(-t.sin(), 0.0, 0.0);
    truth
}

/// Readings of ticks `range` of a suite.
fn run(suite: &mut SensorSuite, range: std::ops::Range<u64>) -> Vec<SensorReadings> {
    range.map(|i| suite.read(&flying(i))).collect()
}

const HOME: GeoSite = GeoSite::PX4_DEFAULT_HOME;

fn typical(seed: u64) -> SensorSuite {
    SensorSuite::new(SensorSuiteConfig::typical(), &HOME, seed).unwrap()
}

#[test]
fn ideal_suite_reads_exact_truth_derived_values_at_the_configured_rates() {
    let config = SensorSuiteConfig::ideal();
    let mut suite = SensorSuite::new(config, &HOME, 3).unwrap();
    let field_w = config.mag.field_at(&HOME).unwrap().field_w();
    let mut counts = [0usize; 4];
    for i in 0..10_000 {
        let truth = flying(i);
        let r = suite.read(&truth);
        let q = truth.body.q_wb;
        let imu = r.imu.unwrap();
        let specific_w = truth.accel_w - Vector3::new(0.0, 0.0, GRAVITY_M_S2);
        assert_eq!(imu.accel_b, Some(q.inverse_transform_vector(&specific_w)));
        assert_eq!(imu.gyro_b, Some(truth.mean_omega_b));
        counts[0] += 1;
        if let Some(g) = r.gps {
            assert_eq!(
                (g.t_s, g.pos_w, g.vel_w),
                (truth.t_s, truth.body.pos_w, truth.body.vel_w)
            );
            counts[1] += 1;
        }
        if let Some(b) = r.baro {
            let alt = 488.0 - truth.body.pos_w.z;
            assert_eq!(
                (b.pressure_pa, b.temperature_c),
                (isa_pressure_pa(alt), isa_temperature_k(alt) - 273.15)
            );
            counts[2] += 1;
        }
        if let Some(m) = r.mag {
            assert_eq!(m.field_b, q.inverse_transform_vector(&field_w));
            counts[3] += 1;
        }
    }
    assert_eq!(counts, [10_000, 100, 500, 500]);
}

#[test]
fn the_barometers_origin_is_the_homes_altitude_unless_the_configuration_fixes_one() {
    let cmac = GeoSite {
        lat_deg: -35.363261,
        lon_deg: 149.165230,
        alt_m: 584.0,
    };
    let pressure_at = |config: SensorSuiteConfig, home: &GeoSite| {
        let mut suite = SensorSuite::new(config, home, 1).unwrap();
        (0..100)
            .find_map(|i| suite.read(&truth_at(tick_s(i))).baro)
            .unwrap()
            .pressure_pa
    };
    let ideal = SensorSuiteConfig::ideal();
    // truth_at stands 1 m above z = 0.
    assert_eq!(pressure_at(ideal, &cmac), isa_pressure_pa(585.0));
    assert_eq!(pressure_at(ideal, &HOME), isa_pressure_pa(489.0));
    let mut fixed = ideal;
    fixed.baro.origin_alt_m = Some(0.0);
    assert_eq!(pressure_at(fixed, &cmac), isa_pressure_pa(1.0));
}

#[test]
fn typical_suite_delivers_imu_every_tick_gps_at_10_hz_after_its_latency_baro_and_mag_at_50_hz() {
    let readings = run(&mut typical(8), 0..10_000);
    let count = |f: fn(&SensorReadings) -> bool| readings.iter().filter(|r| f(r)).count();
    // The first GPS sample arrives at 0.11 s; the hundredth would arrive at 10.01 s.
    assert_eq!(
        [
            count(|r| r.imu.is_some()),
            count(|r| r.gps.is_some()),
            count(|r| r.baro.is_some()),
            count(|r| r.mag.is_some())
        ],
        [10_000, 99, 500, 500]
    );
}

#[test]
fn same_seed_gives_identical_readings_and_another_seed_different_ones() {
    let a = run(&mut typical(21), 0..3000);
    assert_eq!(a, run(&mut typical(21), 0..3000));
    let b = run(&mut typical(22), 0..3000);
    assert!(a.iter().zip(&b).all(|(x, y)| x.imu != y.imu));
    assert_ne!(typical(21).errors(), typical(22).errors());
}

#[test]
fn faults_on_some_units_leave_the_others_reading_exactly_as_before() {
    let healthy = run(&mut typical(5), 0..4000);
    let mut suite = typical(5);
    suite.set_fault(SensorUnit::Gyro, SensorFault::Garbage);
    suite.set_fault(SensorUnit::Gps, SensorFault::Off);
    suite.set_fault(SensorUnit::Baro, SensorFault::INTERMITTENT);
    let faulty = run(&mut suite, 0..4000);
    for (h, f) in healthy.iter().zip(&faulty) {
        assert_eq!(h.imu.map(|s| s.accel_b), f.imu.map(|s| s.accel_b));
        assert_eq!(h.mag, f.mag);
        assert!(f.gps.is_none());
    }
}

#[test]
fn off_delivers_nothing_and_ok_restores_the_models_that_kept_running() {
    let healthy = run(&mut typical(6), 0..3000);
    let mut suite = typical(6);
    run(&mut suite, 0..1000);
    suite.set_fault(SensorUnit::Gyro, SensorFault::Off);
    for r in run(&mut suite, 1000..1500) {
        let imu = r.imu.unwrap();
        assert!(imu.accel_b.is_some() && imu.gyro_b.is_none());
    }
    suite.set_fault(SensorUnit::Accel, SensorFault::Off);
    suite.set_fault(SensorUnit::Mag, SensorFault::Off);
    assert!(run(&mut suite, 1500..2000)
        .iter()
        .all(|r| r.imu.is_none() && r.mag.is_none()));
    for unit in SensorUnit::ALL {
        suite.set_fault(unit, SensorFault::Ok);
    }
    assert_eq!(run(&mut suite, 2000..3000), healthy[2000..3000]);
}

#[test]
fn stuck_repeats_the_last_healthy_sample_with_fresh_timestamps() {
    let mut suite = typical(7);
    let before = run(&mut suite, 0..1000);
    let last = before.iter().rev().find_map(|r| r.baro).unwrap();
    let last_gyro = before[999].imu.unwrap().gyro_b;
    suite.set_fault(SensorUnit::Baro, SensorFault::Stuck);
    suite.set_fault(SensorUnit::Gyro, SensorFault::Stuck);
    let mut n = 0;
    for (i, r) in (1000..2000).zip(run(&mut suite, 1000..2000)) {
        assert_eq!(r.imu.unwrap().gyro_b, last_gyro);
        if let Some(b) = r.baro {
            assert_eq!(
                (b.t_s, b.pressure_pa, b.temperature_c),
                (tick_s(i), last.pressure_pa, last.temperature_c)
            );
            n += 1;
        }
    }
    assert_eq!(n, 50, "still 50 Hz");
}

#[test]
fn garbage_gyro_is_uniform_over_its_full_scale() {
    let mut suite = typical(8);
    suite.set_fault(SensorUnit::Gyro, SensorFault::Garbage);
    let xs: Vec<f64> = run(&mut suite, 0..20_000)
        .iter()
        .flat_map(|r| r.imu.unwrap().gyro_b.unwrap().iter().copied().collect::<Vec<_>>())
        .collect();
    assert!(xs.iter().all(|x| x.abs() <= GYRO_FULL_SCALE_RAD_S));
    // Uniform on ±F: variance F²/3; 60 000 values give ≈ 0.37 % standard error.
    let (mean, var) = stats(&xs);
    let f = GYRO_FULL_SCALE_RAD_S;
    assert!(mean.abs() < 5.0 * f / (3.0 * 60_000f64).sqrt(), "mean {mean}");
    assert!((var / (f * f / 3.0) - 1.0).abs() < 0.02, "var {var}");
}

#[test]
fn wrong_adds_the_documented_offsets() {
    let healthy = run(&mut typical(9), 0..5000);
    let mut suite = typical(9);
    run(&mut suite, 0..1000);
    for unit in SensorUnit::ALL {
        suite.set_fault(unit, SensorFault::Wrong);
    }
    for (i, (h, w)) in (1000..5000).zip(healthy[1000..].iter().zip(run(&mut suite, 1000..5000))) {
        let (hi, wi) = (h.imu.unwrap(), w.imu.unwrap());
        let dg = wi.gyro_b.unwrap() - hi.gyro_b.unwrap();
        let da = wi.accel_b.unwrap() - hi.accel_b.unwrap();
        assert!(dg.iter().all(|d| (d - GYRO_WRONG_OFFSET_RAD_S).abs() < 1e-12), "{dg}");
        assert!(da.iter().all(|d| (d - 1.0).abs() < 1e-12), "{da}");
        if let (Some(hm), Some(wm)) = (h.mag, w.mag) {
            assert!((wm.field_b - hm.field_b).iter().all(|d| (d - 0.3).abs() < 1e-12));
        }
        if let (Some(hb), Some(wb)) = (h.baro, w.baro) {
            let dh = isa_altitude_m(wb.pressure_pa) - isa_altitude_m(hb.pressure_pa);
            assert!((dh - 100.0).abs() < 1e-6, "{dh}");
        }
        assert_eq!(h.gps.is_some(), w.gps.is_some());
        if let (Some(hg), Some(wg)) = (h.gps, w.gps) {
            let (p, v) = wrong_drift(tick_s(i) - 1.0);
            assert!((wg.pos_w - hg.pos_w - Vector3::new(0.0, p, 0.0)).norm() < 1e-9);
            assert!((wg.vel_w - hg.vel_w - Vector3::new(0.0, v, 0.0)).norm() < 1e-9);
            assert_eq!((wg.fix, wg.satellites), (hg.fix, hg.satellites));
        }
    }
}

#[test]
fn slow_divides_the_rate() {
    let mut suite = typical(10);
    for unit in [SensorUnit::Accel, SensorUnit::Mag, SensorUnit::Gps] {
        suite.set_fault(unit, SensorFault::SLOW);
    }
    let readings = run(&mut suite, 0..10_000);
    let accel = readings
        .iter()
        .filter(|r| r.imu.and_then(|s| s.accel_b).is_some())
        .count();
    let gyro = readings
        .iter()
        .filter(|r| r.imu.and_then(|s| s.gyro_b).is_some())
        .count();
    let mag = readings.iter().filter(|r| r.mag.is_some()).count();
    let gps = readings.iter().filter(|r| r.gps.is_some()).count();
    assert_eq!([accel, gyro, mag, gps], [1000, 10_000, 50, 10]);
}

#[test]
fn delayed_delivers_what_the_healthy_sensor_gave_that_much_earlier() {
    let healthy = run(&mut typical(11), 0..3000);
    let mut suite = typical(11);
    run(&mut suite, 0..1000);
    suite.set_fault(SensorUnit::Baro, SensorFault::Delayed { extra_s: 0.3 });
    suite.set_fault(SensorUnit::Gyro, SensorFault::Delayed { extra_s: 0.05 });
    for (i, r) in (1000..3000).zip(run(&mut suite, 1000..3000)) {
        let gyro = r.imu.unwrap().gyro_b;
        assert_eq!(gyro, healthy[i as usize - 50].imu.unwrap().gyro_b);
        assert_eq!(r.baro.is_some(), healthy[i as usize].baro.is_some(), "rate unchanged");
        if let Some(b) = r.baro {
            let old = healthy[i as usize - 300].baro.unwrap();
            assert_eq!((b.t_s, b.pressure_pa), (tick_s(i), old.pressure_pa));
        }
    }
}

#[test]
fn intermittent_windows_follow_the_availability_and_the_seed() {
    let fault = SensorFault::Intermittent {
        period_s: 0.2,
        availability: 0.3,
    };
    let pattern = |seed| {
        let mut suite = typical(seed);
        suite.set_fault(SensorUnit::Mag, fault);
        let mut per_window = vec![0u32; 1000];
        for i in 0..200_000u64 {
            if suite.read(&flying(i)).mag.is_some() {
                per_window[(i / 200) as usize] += 1;
            }
        }
        per_window
    };
    let a = pattern(12);
    assert!(a.iter().all(|&n| n == 0 || n == 10), "a window is all on or all off");
    // 1000 windows: the on fraction has standard error √(0.3·0.7/1000) ≈ 0.0145; allow five.
    let on = a.iter().filter(|&&n| n > 0).count() as f64 / 1000.0;
    assert!((on - 0.3).abs() < 0.073, "on fraction {on}");
    assert_eq!(a, pattern(12));
    assert_ne!(a, pattern(13));
}

#[test]
fn set_fault_reports_the_sanitized_fault_and_defaults_to_ok() {
    let mut suite = typical(14);
    assert!(SensorUnit::ALL.iter().all(|&u| suite.fault(u) == SensorFault::Ok));
    suite.set_fault(SensorUnit::Gps, SensorFault::Delayed { extra_s: 9.0 });
    assert_eq!(suite.fault(SensorUnit::Gps), SensorFault::Delayed { extra_s: 1.0 });
    assert_eq!(suite.fault(SensorUnit::Baro), SensorFault::Ok);
    assert_eq!(suite.config(), &SensorSuiteConfig::typical());
}
