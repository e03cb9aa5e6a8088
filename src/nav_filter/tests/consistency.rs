//! Filter consistency: normalised estimation error squared (NEES) of position, velocity and
//! attitude over Monte Carlo runs against chi-square bounds
//! (docs/navigation_filter.md §15, eqs. (15.1)–(15.2)).

use super::truth::{Motion, SimulatedErrors, Truth};
use super::{nees3, run, Faults};
use crate::nav_filter::NavFilter;

/// Runs of the Monte Carlo set [-].
const RUNS: u64 = 30;
/// Two-sided 95 % bounds of the run-averaged NEES of a 3-dof error over 30 runs:
/// χ²₃₀·₃(0.025) / 30 and χ²₉₀(0.975) / 30 (docs/navigation_filter.md §15, eq. (15.2)).
const NEES_BOUNDS: (f64, f64) = (65.647 / 30.0, 118.136 / 30.0);
/// Checkpoints: every 2 s from 30 s to 90 s.
const FIRST_S: f64 = 30.0;
const EVERY_S: f64 = 2.0;
const CHECKPOINTS: usize = 31;

#[test]
fn nees_of_position_velocity_and_attitude_is_within_chi_square_bounds() {
    let mut sums = [[0.0; 3]; CHECKPOINTS];
    let errors = SimulatedErrors::realistic();
    for seed in 0..RUNS {
        let mut truth = Truth::new(Motion::curves(), errors, 100 + seed);
        let mut filter = NavFilter::new(errors.matched_params()).unwrap();
        let t_end = FIRST_S + EVERY_S * (CHECKPOINTS - 1) as f64;
        run(&mut truth, &mut filter, &Faults::default(), t_end, |s| {
            let k = ((s.truth.t_s - FIRST_S) / EVERY_S).round();
            if k >= 0.0 && (s.truth.t_s - FIRST_S - k * EVERY_S).abs() < 1e-9 {
                let n = nees3(s.filter, &s.truth);
                for (sum, v) in sums[k as usize].iter_mut().zip(n) {
                    *sum += v;
                }
            }
        });
    }
    let (lo, hi) = NEES_BOUNDS;
    for (q, name) in ["position", "velocity", "attitude"].iter().enumerate() {
        let averaged: Vec<f64> = sums.iter().map(|s| s[q] / RUNS as f64).collect();
        let mean = averaged.iter().sum::<f64>() / CHECKPOINTS as f64;
        let inside = averaged.iter().filter(|v| (lo..=hi).contains(*v)).count();
        eprintln!(
            "{name}: mean NEES {mean:.2}, {inside}/{CHECKPOINTS} checkpoints in [{lo:.2}, {hi:.2}]: {averaged:.2?}"
        );
        assert!(
            (lo..=hi).contains(&mean),
            "{name}: mean NEES {mean} outside [{lo}, {hi}]"
        );
        assert!(
            inside * 10 >= CHECKPOINTS * 8,
            "{name}: only {inside} of {CHECKPOINTS} checkpoints in bounds"
        );
    }
}
