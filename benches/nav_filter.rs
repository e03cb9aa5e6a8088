//! Navigation-filter costs: one 1 kHz IMU sample (the covariance predicted every tenth), and one
//! second of readings (1000 IMU samples, 10 GNSS fixes, 50 barometer and 50 magnetometer
//! samples), on a hovering vehicle after the alignment.
#![allow(clippy::expect_used, clippy::unwrap_used)] // a broken bench set-up should stop the bench

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use rotorpilot::math::{Vec3, GRAVITY_M_S2};
use rotorpilot::nav_filter::isa::pressure_at_altitude_pa;
use rotorpilot::nav_filter::{BaroReading, GpsReading, ImuReading, MagReading, NavFilter, NavParams};

/// Feeds the readings of a level hover at the origin for the milliseconds `from_ms..to_ms`.
fn feed(f: &mut NavFilter, from_ms: u64, to_ms: u64) {
    for k in from_ms..to_ms {
        let t = k as f64 * 1e-3;
        let wobble = 0.01 * (t * 7.0).sin();
        f.predict(&ImuReading {
            t_s: t,
            accel_b: Vec3::new(wobble, -wobble, -GRAVITY_M_S2),
            gyro_b: Vec3::new(0.001, wobble, -0.002),
        });
        if k % 100 == 0 {
            f.fuse_gps(&GpsReading {
                t_s: t,
                pos_w: Vec3::new(0.1, 0.0, 0.0),
                vel_w: Vec3::zeros(),
                h_acc_m: 0.5,
                v_acc_m: 0.8,
                speed_acc_m_s: 0.2,
                fix_3d: true,
                satellites: 12,
            });
        }
        if k % 20 == 5 {
            f.fuse_baro(&BaroReading {
                t_s: t,
                pressure_pa: pressure_at_altitude_pa(488.0),
                temperature_c: 20.0,
            });
        }
        if k % 20 == 10 {
            f.fuse_mag(&MagReading {
                t_s: t,
                field_b: Vec3::new(0.21, 0.01, 0.43),
            });
        }
    }
}

fn nav_filter(c: &mut Criterion) {
    let mut f = NavFilter::new(NavParams::default()).unwrap();
    feed(&mut f, 0, 3000);
    assert!(f.status().horizontal_position_valid);
    let mut ms = 3000;
    c.bench_function("nav_filter_imu_sample", |b| {
        b.iter(|| {
            ms += 1;
            f.predict(black_box(&ImuReading {
                t_s: ms as f64 * 1e-3,
                accel_b: Vec3::new(0.0, 0.0, -GRAVITY_M_S2),
                gyro_b: Vec3::zeros(),
            }));
        })
    });
    let mut f = NavFilter::new(NavParams::default()).unwrap();
    feed(&mut f, 0, 3000);
    let mut ms = 3000;
    c.bench_function("nav_filter_one_second_of_readings", |b| {
        b.iter(|| {
            feed(&mut f, ms, ms + 1000);
            ms += 1000;
            black_box(f.estimate())
        })
    });
}

criterion_group!(benches, nav_filter);
criterion_main!(benches);
