//! Flight-controller costs per 1 kHz tick: each controller's update, the wrench estimator at
//! r = 1 and r = 7, and one full lockstep tick (sensors + estimator + controller + allocation +
//! plant, `Lockstep::step` of a bare flight core holding hover) of the homework vehicle, and
//! the same tick on realistic sensors with the navigation filter (quad_x).
//! Targets: full tick under 2 µs median on one core; with the filter, under 3 µs.
#![allow(clippy::expect_used, clippy::unwrap_used)] // a broken bench set-up should stop the bench

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use rotorpilot::airframe::{Airframe, AirframeSource};
use rotorpilot::control::{ControlInput, ControllerKind, FlatSetpoint, VehicleState};
use rotorpilot::flight::{FlightCore, SetpointFollower};
use rotorpilot::lockstep::Lockstep;
use rotorpilot::math::{UnitQuat, Vec3};
use rotorpilot::sitl::{SensorModel, SimPlant};
use rotorpilot::wrench_estimator::{ChebyshevDesign, WrenchObserver};

fn state(k: u32) -> VehicleState {
    let a = 0.01 * f64::from(k % 100);
    VehicleState {
        t_s: 0.0,
        pos_w: Vec3::new(0.1 + a, -0.2, -1.0),
        vel_w: Vec3::new(0.05, a, -0.02),
        r_wb: UnitQuat::from_euler_angles(0.05, -0.03 + a, 0.4)
            .to_rotation_matrix()
            .into_inner(),
        omega_b: Vec3::new(0.1, -0.05, a),
    }
}

fn airframe() -> Airframe {
    Airframe::from_source(&AirframeSource::resolve("fsr_quad").unwrap()).unwrap()
}

fn observer(order: usize) -> WrenchObserver {
    let design = ChebyshevDesign {
        order,
        ripple_db: 3.0,
        passband_rad_s: 2.0,
    };
    WrenchObserver::new(
        1.5,
        Vec3::new(1.2416, 1.2416, 2.4832),
        design.gains(1e-3).unwrap(),
        1e-3,
    )
    .unwrap()
}

fn controllers(c: &mut Criterion) {
    let af = airframe();
    let sp = FlatSetpoint {
        vel_w: Some(Vec3::new(0.1, 0.1, -0.1)),
        acc_w: Some(Vec3::new(0.01, 0.0, 0.0)),
        ..FlatSetpoint::hold(Vec3::new(1.0, 1.0, -1.0), 0.2)
    };
    for kind in ControllerKind::ALL {
        let mut core = FlightCore::for_airframe(&af, kind, 1e-3).unwrap();
        let mut k = 0u32;
        c.bench_function(&format!("controller_update_{}", kind.name()), |b| {
            b.iter(|| {
                k = k.wrapping_add(1);
                let x = state(k);
                black_box(core.controller.update(&ControlInput {
                    state: black_box(&x),
                    setpoint: &sp,
                    estimate: None,
                }))
            })
        });
    }
}

fn estimators(c: &mut Criterion) {
    for order in [1, 7] {
        let mut obs = observer(order);
        let mut k = 0u32;
        c.bench_function(&format!("estimator_update_r{order}"), |b| {
            b.iter(|| {
                k = k.wrapping_add(1);
                let a = 0.001 * f64::from(k % 100);
                let est = obs.observe(
                    &Vec3::new(0.1, a, 0.0),
                    &Vec3::new(0.05, -0.02, 0.3),
                    &Vec3::new(0.1, a, 0.0),
                );
                obs.apply(black_box(14.7), &Vec3::new(0.01, 0.0, a));
                black_box(est)
            })
        });
    }
}

/// `plant` hovering level and still at `pos_w` [m], its motors at hover speed.
fn hovering(mut plant: SimPlant, pos_w: Vec3) -> SimPlant {
    plant.set_initial_state(Some(pos_w), Vec3::zeros(), UnitQuat::identity(), Vec3::zeros(), true);
    plant
}

fn full_tick(c: &mut Criterion) {
    let af = airframe();
    let src = AirframeSource::resolve("fsr_quad").unwrap();
    for kind in ControllerKind::ALL {
        let mut core = FlightCore::for_airframe(&af, kind, 1e-3).unwrap();
        core.set_observer(Some(observer(7)));
        core.controller.set_compensation(true);
        let hover_pos = Vec3::new(0.0, 0.0, -1.0);
        let plant = hovering(SimPlant::from_source(&src, 0).unwrap(), hover_pos);
        let sp = FlatSetpoint::hold(hover_pos, 0.0);
        let mut lockstep = Lockstep::new(SetpointFollower::new(core, sp), plant, 1e-3);
        c.bench_function(&format!("full_tick_{}_r7", kind.name()), |b| {
            b.iter(|| black_box(lockstep.step()))
        });
    }
}

/// The full tick on realistic sensors: the sensor suite (IMU, GPS, barometer, magnetometer) read
/// and the navigation filter run every tick, quad_x hovering on the geometric law with the
/// estimator at r = 7 (target: ≤ 3 µs).
fn full_tick_realistic(c: &mut Criterion) {
    let src = AirframeSource::resolve("quad_x").unwrap();
    let af = Airframe::from_source(&src).unwrap();
    let mut core = FlightCore::for_airframe(&af, ControllerKind::Geometric, 1e-3).unwrap();
    core.set_observer(Some(observer(7)));
    let hover_pos = Vec3::new(0.0, 0.0, -2.0);
    let plant = hovering(
        SimPlant::from_source(&src, 0)
            .unwrap()
            .with_sensor_model(SensorModel::Suite),
        hover_pos,
    );
    let follower = SetpointFollower::new(core, FlatSetpoint::hold(hover_pos, 0.0)).starting_at(&plant.true_state());
    let mut lockstep = Lockstep::new(follower, plant, 1e-3);
    for _ in 0..2_000 {
        lockstep.step();
    }
    c.bench_function("full_tick_geometric_r7_realistic", |b| {
        b.iter(|| black_box(lockstep.step()))
    });
}

criterion_group!(benches, controllers, estimators, full_tick, full_tick_realistic);
criterion_main!(benches);
