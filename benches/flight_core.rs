//! Flight-controller costs per 1 kHz tick: each controller's update, the wrench estimator at
//! r = 1 and r = 7, and one full lockstep tick (sensors + estimator + controller + allocation +
//! plant, `Lockstep::step` of a bare flight core holding hover) of the homework vehicle.
//! Target: full tick under 2 µs median on one core.
#![allow(clippy::expect_used, clippy::unwrap_used)] // a broken bench set-up should stop the bench

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use rotorpilot::airframe::{Airframe, AirframeSource};
use rotorpilot::control::{ControlInput, ControllerKind, FlatSetpoint, VehicleState};
use rotorpilot::estimation::{ChebyshevDesign, WrenchObserver};
use rotorpilot::flight::{FlightCore, SetpointFollower};
use rotorpilot::lockstep::Lockstep;
use rotorpilot::math::{UnitQuat, Vec3};
use rotorpilot::sitl::SimPlant;

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

fn full_tick(c: &mut Criterion) {
    let af = airframe();
    let src = AirframeSource::resolve("fsr_quad").unwrap();
    for kind in ControllerKind::ALL {
        let mut core = FlightCore::for_airframe(&af, kind, 1e-3).unwrap();
        core.set_observer(Some(observer(7)));
        core.controller.set_compensation(true);
        let mut plant = SimPlant::from_source(&src, 0).unwrap();
        let hover_pos = Vec3::new(0.0, 0.0, -1.0);
        plant.set_initial_state(
            Some(hover_pos),
            Vec3::zeros(),
            UnitQuat::identity(),
            Vec3::zeros(),
            true,
        );
        let sp = FlatSetpoint::hold(hover_pos, 0.0);
        let mut lockstep = Lockstep::new(SetpointFollower::new(core, sp), plant, 1e-3);
        c.bench_function(&format!("full_tick_{}_r7", kind.name()), |b| {
            b.iter(|| black_box(lockstep.step()))
        });
    }
}

criterion_group!(benches, controllers, estimators, full_tick);
criterion_main!(benches);
