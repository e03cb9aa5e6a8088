//! Allocation: golden matrices (docs/allocation.md §2, eq. (2.3): the homework's octocopter; quad-X,
//! hex-X), min-norm inverse properties, and the saturation priority of docs/allocation.md §4.
#![allow(clippy::unwrap_used, clippy::expect_used)] // a failed set-up step should panic in a test

use nalgebra::{DMatrix, Vector3};
use rand_chacha::rand_core::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rotorpilot::airframe::{Airframe, AirframeSource};
use rotorpilot::allocation::{closed_form_ring_inverse, Airmode, Allocation, Allocator, Wrench};

fn airframe(name: &str) -> Airframe {
    Airframe::from_source(&AirframeSource::resolve(name).unwrap()).unwrap()
}

fn assert_matrix_eq(g: &DMatrix<f64>, expected: &[Vec<f64>], scale: f64) {
    assert_eq!(g.nrows(), expected.len());
    for (r, row) in expected.iter().enumerate() {
        assert_eq!(g.ncols(), row.len());
        for (c, e) in row.iter().enumerate() {
            assert!(
                (g[(r, c)] - e).abs() <= 1e-12 * scale,
                "G[{r}][{c}] = {} expected {e}",
                g[(r, c)]
            );
        }
    }
}

#[test]
fn octocopter_equals_homework_eqs_2_to_5_entry_by_entry() {
    let af = airframe("octo");
    let (ct, cq, l) = (af.c_t, af.c_q, af.arm_length_m());
    let s1 = 2f64.sqrt() * ct * l / 2.0;
    let expected = vec![
        vec![ct; 8],
        vec![0.0, s1, ct * l, s1, 0.0, -s1, -ct * l, -s1],
        vec![ct * l, s1, 0.0, -s1, -ct * l, -s1, 0.0, s1],
        vec![-cq, cq, -cq, cq, -cq, cq, -cq, cq],
    ];
    assert_matrix_eq(Allocator::new(&af).unwrap().effectiveness(), &expected, ct);
}

#[test]
fn quad_x_golden() {
    let af = airframe("quad_x");
    let (ct, cq) = (5.84e-6, 3.504e-7);
    let k = ct * 0.25 / 2f64.sqrt();
    // Rotors at 45°, 135°, 225°, 315° counter-clockwise seen from above: front-right, front-left,
    // rear-left, rear-right in FRD; rotor 1 clockwise.
    let expected = vec![
        vec![ct; 4],
        vec![k, k, -k, -k],
        vec![k, -k, -k, k],
        vec![-cq, cq, -cq, cq],
    ];
    assert_matrix_eq(Allocator::new(&af).unwrap().effectiveness(), &expected, ct);
}

#[test]
fn hexa_x_golden() {
    let af = airframe("hexa_x");
    let ct = 8.54858e-6;
    let cq = 1.3677728e-7;
    let l = 0.215;
    let (h, f) = (ct * l * 0.5, ct * l * 3f64.sqrt() / 2.0);
    // α = 30°, 90°, …, 330°: τx row c_T l sin α, τy row c_T l cos α.
    let expected = vec![
        vec![ct; 6],
        vec![h, ct * l, h, -h, -ct * l, -h],
        vec![f, 0.0, -f, -f, 0.0, f],
        vec![-cq, cq, -cq, cq, -cq, cq],
    ];
    assert_matrix_eq(Allocator::new(&af).unwrap().effectiveness(), &expected, ct);
}

#[test]
fn min_norm_inverse_is_a_right_inverse_and_matches_the_closed_form() {
    for name in ["quad_x", "quad_plus", "hexa_x", "octo", "fsr_quad"] {
        let af = airframe(name);
        let alloc = Allocator::new(&af).unwrap();
        let (g, a) = (alloc.effectiveness(), alloc.inverse());
        let ga = g * a;
        assert!((ga - DMatrix::<f64>::identity(4, 4)).norm() < 1e-9, "{name}: G A != I");
        let alphas: Vec<f64> = af.rotors.iter().map(|r| r.angle_rad).collect();
        let signs: Vec<f64> = af.rotors.iter().map(|r| r.spin.yaw_sign()).collect();
        let closed = closed_form_ring_inverse(af.c_t, af.c_q, af.arm_length_m(), &alphas, &signs);
        let rel = (&closed - a).norm() / a.norm();
        assert!(rel < 1e-10, "{name}: closed form differs by {rel}");
    }
}

#[test]
fn feasible_wrenches_are_reproduced_exactly() {
    let mut rng = ChaCha8Rng::seed_from_u64(42);
    let mut uniform = move || (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
    for name in ["quad_x", "hexa_x", "octo", "fsr_quad"] {
        let af = airframe(name);
        let alloc = Allocator::new(&af).unwrap();
        let weight = af.mass_kg * 9.81;
        let mut tried = 0;
        while tried < 200 {
            let w = Wrench {
                thrust_n: weight * (0.5 + uniform()),
                torque_b: Vector3::new(uniform() - 0.5, uniform() - 0.5, uniform() - 0.5) * 0.2 * weight * 0.05,
            };
            let out = alloc.allocate(&w);
            // Only wrenches whose unconstrained solution is inside the box count as feasible.
            let raw = alloc.inverse()
                * nalgebra::DVector::from_vec(vec![w.thrust_n, w.torque_b.x, w.torque_b.y, w.torque_b.z]);
            if raw.iter().any(|x| *x < 0.0 || *x > af.omega_max_rad_s.powi(2)) {
                continue;
            }
            tried += 1;
            assert!(!out.saturation.is_saturated(), "{name}: {:?}", out.saturation);
            assert!((out.applied.thrust_n - w.thrust_n).abs() < 1e-9 * weight);
            assert!((out.applied.torque_b - w.torque_b).norm() < 1e-9);
        }
    }
}

/// Allocates the wrench of thrust `thrust_n(allocator)` [N] and body torque `torque_b` [N·m] on
/// airframe `name`; the rotor commands must stay in `[0, ω_max²]`.
fn allocate_in_box(name: &str, thrust_n: impl FnOnce(&Allocator) -> f64, torque_b: [f64; 3]) -> (Wrench, Allocation) {
    let af = airframe(name);
    let alloc = Allocator::new(&af).unwrap();
    let w = Wrench {
        thrust_n: thrust_n(&alloc),
        torque_b: torque_b.into(),
    };
    let out = alloc.allocate(&w);
    let max = af.omega_max_rad_s.powi(2);
    assert!(out.omega_sq().iter().all(|x| *x >= 0.0 && *x <= max), "{name}: {out:?}");
    (w, out)
}

#[test]
fn too_much_yaw_gives_up_yaw_only() {
    let (w, out) = allocate_in_box("quad_x", |_| 14.715, [0.3, -0.2, 2.0]);
    assert!(out.saturation.yaw_scale < 1.0 && out.saturation.yaw_scale > 0.0);
    assert_eq!(out.saturation.roll_pitch_scale, 1.0);
    assert_eq!(out.saturation.thrust_shift_n, 0.0);
    assert!((out.applied.thrust_n - w.thrust_n).abs() < 1e-9);
    assert!((out.applied.torque_b.xy() - w.torque_b.xy()).norm() < 1e-9);
    assert!((out.applied.torque_b.z - out.saturation.yaw_scale * w.torque_b.z).abs() < 1e-9);
    assert!(out.saturation.clipped != 0, "some rotor must sit on a limit");
}

#[test]
fn roll_near_full_thrust_shifts_the_collective_and_keeps_roll() {
    let (_, out) = allocate_in_box("quad_x", |alloc| alloc.thrust_max_n() * 0.98, [1.5, 0.0, 0.5]);
    assert_eq!(out.saturation.roll_pitch_scale, 1.0);
    assert!(out.saturation.thrust_shift_n < 0.0);
    assert!(
        (out.applied.torque_b.x - 1.5).abs() < 1e-9,
        "roll kept: {:?}",
        out.applied
    );
    assert!(out.applied.torque_b.z.abs() < 0.5, "yaw given up first");
}

/// Low collective with a large roll torque: with air mode the collective rises to keep the
/// roll; without it (PX4's default, the flight controller's) the collective stays at the
/// request and the roll is scaled down, so a vehicle asked for little thrust never lifts off
/// to make a torque (docs/allocation.md §4, eq. (4.3)).
#[test]
fn without_air_mode_the_collective_never_rises_to_make_room_for_roll() {
    let af = airframe("hexa_x");
    let with_air = Allocator::new(&af).unwrap();
    let without_air = with_air.clone().with_airmode(Airmode::DISABLED);
    let weight_n = 1.5 * 9.81;
    for thrust_n in [0.0, 0.2 * weight_n, 0.5 * weight_n] {
        let w = Wrench {
            thrust_n,
            torque_b: Vector3::new(1.5, -1.0, 0.2),
        };
        let raised = with_air.allocate(&w);
        assert_eq!(raised.saturation.roll_pitch_scale, 1.0, "{thrust_n} N: roll kept");
        assert!(
            raised.applied.thrust_n > thrust_n + 1.0,
            "{thrust_n} N: collective raised"
        );
        let kept = without_air.allocate(&w);
        assert!(
            kept.applied.thrust_n <= thrust_n + 1e-9,
            "{thrust_n} N: collective {} N",
            kept.applied.thrust_n
        );
        let s = kept.saturation.roll_pitch_scale;
        assert!(s < 1.0, "{thrust_n} N: roll scaled ({s})");
        let t = kept.applied.torque_b;
        assert!(
            (t.x - s * 1.5).abs() < 1e-6 && (t.y + s * 1.0).abs() < 1e-6,
            "direction kept"
        );
    }
    // A wrench that fits is allocated the same either way.
    let hover = Wrench {
        thrust_n: weight_n,
        torque_b: Vector3::new(0.1, -0.1, 0.01),
    };
    assert_eq!(with_air.allocate(&hover), without_air.allocate(&hover));
}

#[test]
fn impossible_roll_is_scaled_and_output_stays_in_the_box() {
    let (_, out) = allocate_in_box("octo", |_| 30.0, [50.0, 20.0, 3.0]);
    let s = out.saturation.roll_pitch_scale;
    assert!(s > 0.0 && s < 1.0, "scale {s}");
    // Direction of the roll/pitch torque is kept.
    let t = out.applied.torque_b;
    assert!((t.x / t.y - 2.5).abs() < 1e-6);
    assert!((t.x - s * 50.0).abs() < 1e-6);
}

#[test]
fn thrust_is_clamped_to_what_the_motors_give() {
    let af = airframe("hexa_x");
    let alloc = Allocator::new(&af).unwrap();
    let out = alloc.allocate(&Wrench {
        thrust_n: 1e3,
        torque_b: Vector3::zeros(),
    });
    assert!((out.applied.thrust_n - alloc.thrust_max_n()).abs() < 1e-9);
    let out = alloc.allocate(&Wrench {
        thrust_n: -5.0,
        torque_b: Vector3::zeros(),
    });
    assert_eq!(out.applied.thrust_n, 0.0);
    assert!(out.saturation.is_saturated());
}

#[test]
fn non_finite_wrench_never_reaches_the_motors() {
    let af = airframe("quad_x");
    let alloc = Allocator::new(&af).unwrap();
    let out = alloc.allocate(&Wrench {
        thrust_n: f64::NAN,
        torque_b: Vector3::new(0.0, f64::INFINITY, 0.0),
    });
    assert!(out.omega_sq().iter().all(|x| *x == 0.0));
    assert!(out.saturation.is_saturated());
}

/// PX4's `MC_AIRMODE_LIM`: the collective rises above the request by at most this share of the
/// full collective to make room for roll and pitch (docs/allocation.md §4, eq. (4.3)).
#[test]
fn the_air_mode_limit_caps_how_far_the_collective_rises() {
    let with_air = Allocator::new(&airframe("hexa_x")).unwrap();
    let w = Wrench {
        thrust_n: 0.0,
        torque_b: Vector3::new(1.5, -1.0, 0.0),
    };
    let free = with_air.allocate(&w).applied.thrust_n;
    let limit = 0.05;
    let capped = with_air.clone().with_airmode(Airmode {
        raise_limit: limit,
        yaw: false,
    });
    let out = capped.allocate(&w);
    assert!(free > limit * with_air.thrust_max_n() + 1.0, "unlimited: {free} N");
    assert!(
        (out.applied.thrust_n - limit * with_air.thrust_max_n()).abs() < 1e-6,
        "raised by {} of {} N",
        out.applied.thrust_n,
        with_air.thrust_max_n()
    );
    assert!(out.saturation.roll_pitch_scale < 1.0, "roll and pitch scaled instead");
}

/// PX4's `MC_AIRMODE_YAW`: a yaw torque that does not fit at the requested collective moves the
/// collective instead of being scaled down.
#[test]
fn yaw_air_mode_moves_the_collective_for_the_full_yaw() {
    let af = airframe("quad_x");
    let alloc = Allocator::new(&af).unwrap().with_airmode(Airmode::ROLL_PITCH);
    let w = Wrench {
        thrust_n: 0.05 * alloc.thrust_max_n(),
        torque_b: Vector3::new(0.0, 0.0, 0.15),
    };
    let plain = alloc.allocate(&w);
    assert!(plain.saturation.yaw_scale < 1.0, "{:?}", plain.saturation);
    let yaw_air = alloc.clone().with_airmode(Airmode {
        raise_limit: 1.0,
        yaw: true,
    });
    let out = yaw_air.allocate(&w);
    assert_eq!(out.saturation.yaw_scale, 1.0);
    assert!((out.applied.torque_b.z - 0.15).abs() < 1e-9);
    assert!(out.applied.thrust_n > w.thrust_n, "collective raised");
    assert_eq!(Airmode::DISABLED.raise_limit, 0.0);
}
