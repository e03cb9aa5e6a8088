//! Statistics of a Monte Carlo campaign per control law: convergence rate, counts of
//! non-finite values, faults and panics, worst final errors, convergence-time quantiles
//! (nearest rank), convergence by band of initial tilt and rate, and the failed runs with the
//! draw that made them fail.

use serde::Serialize;

use super::envelope::{Draw, Envelope};
use super::trial::{Heading, TrialOutcome};
use crate::lockstep::Exit;

/// What one run produced.
#[derive(Debug, Clone, PartialEq)]
pub enum RunResult {
    /// The run finished (converged or not).
    Flew(TrialOutcome),
    /// The run panicked; the panic message.
    Panicked(String),
}

/// Nearest-rank quantiles [s].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Quantiles {
    /// 50th percentile.
    pub median: f64,
    /// 95th percentile.
    pub p95: f64,
    /// Largest value.
    pub max: f64,
}

/// Convergence of the runs whose drawn value fell in `[lo, hi)` (the last band includes `hi`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Band {
    /// Lower edge (unit of the band list).
    pub lo: f64,
    /// Upper edge.
    pub hi: f64,
    /// Runs in the band.
    pub runs: usize,
    /// Converged runs in the band.
    pub converged: usize,
}

/// A draw in readable units.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct DrawSummary {
    /// Initial tilt [deg].
    pub tilt_deg: f64,
    /// Initial roll, pitch, yaw (ZYX) [deg].
    pub rpy_deg: [f64; 3],
    /// Initial body rates, FRD [rad/s].
    pub rates_rad_s: [f64; 3],
    /// Initial velocity, world NED [m/s].
    pub velocity_m_s: [f64; 3],
    /// Initial position, world NED [m].
    pub position_m: [f64; 3],
    /// External force, world NED [N].
    pub force_n: [f64; 3],
    /// External torque, body FRD [N·m].
    pub torque_n_m: [f64; 3],
}

impl From<&Draw> for DrawSummary {
    fn from(d: &Draw) -> Self {
        let rpy = crate::math::euler_zyx(&d.q_wb.to_rotation_matrix().into_inner());
        Self {
            tilt_deg: d.tilt_rad().to_degrees(),
            rpy_deg: rpy.map(f64::to_degrees).into(),
            rates_rad_s: d.omega_b.into(),
            velocity_m_s: d.vel_w.into(),
            position_m: d.pos_w.into(),
            force_n: d.force_w.into(),
            torque_n_m: d.torque_b.into(),
        }
    }
}

/// A run that did not converge.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Failure {
    /// Run index (draw number).
    pub run: usize,
    /// Why: `panic: …`, `non_finite`, `plant_fault`, `fly_away`, `controller_fault` or
    /// `outside_tolerance`.
    pub reason: String,
    /// Final position error [m] (absent after a panic).
    pub final_position_error_m: Option<f64>,
    /// Final attitude error from the equilibrium [deg] (absent after a panic).
    pub final_attitude_error_deg: Option<f64>,
    /// Ticks with a controller fault flag.
    pub fault_ticks: u64,
    /// The draw.
    pub initial: DrawSummary,
}

/// Figures of one control law over a campaign.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ControllerSummary {
    /// Control law.
    pub controller: &'static str,
    /// Runs flown.
    pub runs: usize,
    /// Runs that met the criterion.
    pub converged: usize,
    /// 100 × converged / runs [%].
    pub converged_pct: f64,
    /// Runs with a non-finite value anywhere.
    pub non_finite_runs: usize,
    /// Runs with at least one controller fault flag.
    pub fault_runs: usize,
    /// Runs stopped by a plant fault.
    pub plant_fault_runs: usize,
    /// Runs stopped as fly-aways.
    pub fly_away_runs: usize,
    /// Runs that panicked.
    pub panics: usize,
    /// Largest final position error over the runs that did not panic [m].
    pub worst_final_position_error_m: Option<f64>,
    /// Largest final attitude error over the runs that did not panic [deg].
    pub worst_final_attitude_error_deg: Option<f64>,
    /// Largest tilt seen in any run [deg].
    pub max_tilt_deg: f64,
    /// Mean fraction of the run with the allocation saturated [%].
    pub saturated_pct: f64,
    /// Convergence time over the converged runs [s].
    pub convergence_time_s: Option<Quantiles>,
    /// Convergence by initial tilt [deg], three equal bands over the envelope.
    pub by_tilt_deg: Vec<Band>,
    /// Convergence by initial body-rate magnitude [rad/s], three equal bands.
    pub by_rate_rad_s: Vec<Band>,
    /// Convergence by the heading change asked for, |ψ_0 − ψ_sp| [deg], bands of 60°.
    pub by_heading_error_deg: Vec<Band>,
    /// Every run that did not converge.
    pub failures: Vec<Failure>,
}

/// The `p`-th percentile (0 < p ≤ 100) of `values` by nearest rank: the ⌈p n / 100⌉-th
/// smallest. `None` for an empty list.
pub fn nearest_rank(values: &[f64], p: f64) -> Option<f64> {
    if values.is_empty() {
        return None;
    }
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let rank = ((p / 100.0) * v.len() as f64).ceil() as usize;
    v.get(rank.clamp(1, v.len()) - 1).copied()
}

/// Counts of `(value, converged)` pairs in `bands` equal bands over `[0, max]`.
pub fn bands(pairs: &[(f64, bool)], max: f64, count: usize) -> Vec<Band> {
    let width = max / count as f64;
    let mut out: Vec<Band> = (0..count)
        .map(|i| Band {
            lo: i as f64 * width,
            hi: (i + 1) as f64 * width,
            runs: 0,
            converged: 0,
        })
        .collect();
    for &(value, ok) in pairs {
        let i = if width > 0.0 {
            ((value / width).floor().max(0.0) as usize).min(count - 1)
        } else {
            0
        };
        if let Some(b) = out.get_mut(i) {
            b.runs += 1;
            b.converged += usize::from(ok);
        }
    }
    out
}

fn reason(o: &TrialOutcome) -> &'static str {
    if o.non_finite {
        "non_finite"
    } else if o.end == Exit::PlantFault {
        "plant_fault"
    } else if o.end == Exit::FlyAway {
        "fly_away"
    } else if o.fault_ticks > 0 {
        "controller_fault"
    } else {
        "outside_tolerance"
    }
}

/// Summary of `results[i]` flown from `draws[i]` inside `env` to a setpoint at `heading`.
pub fn summarize(
    controller: &'static str,
    env: &Envelope,
    heading: Heading,
    draws: &[Draw],
    results: &[RunResult],
) -> ControllerSummary {
    let flew: Vec<&TrialOutcome> = results
        .iter()
        .filter_map(|r| match r {
            RunResult::Flew(o) => Some(o),
            RunResult::Panicked(_) => None,
        })
        .collect();
    let converged = |r: &RunResult| matches!(r, RunResult::Flew(o) if o.converged);
    let count = |f: &dyn Fn(&TrialOutcome) -> bool| flew.iter().filter(|o| f(o)).count();
    let worst = |f: &dyn Fn(&TrialOutcome) -> f64| {
        flew.iter()
            .map(|o| f(o))
            .filter(|x| x.is_finite())
            .fold(None, |m: Option<f64>, x| Some(m.map_or(x, |m| m.max(x))))
    };
    let times: Vec<f64> = flew.iter().filter_map(|o| o.convergence_time_s).collect();
    let n_conv = results.iter().filter(|r| converged(r)).count();
    let tilt_pairs: Vec<(f64, bool)> = draws
        .iter()
        .zip(results)
        .map(|(d, r)| (d.tilt_rad().to_degrees(), converged(r)))
        .collect();
    let rate_pairs: Vec<(f64, bool)> = draws
        .iter()
        .zip(results)
        .map(|(d, r)| (d.omega_b.norm(), converged(r)))
        .collect();
    let heading_pairs: Vec<(f64, bool)> = draws
        .iter()
        .zip(results)
        .map(|(d, r)| (heading.heading_error_rad(d).to_degrees(), converged(r)))
        .collect();
    let failures = draws
        .iter()
        .zip(results)
        .enumerate()
        .filter(|(_, (_, r))| !converged(r))
        .map(|(run, (d, r))| match r {
            RunResult::Flew(o) => Failure {
                run,
                reason: reason(o).into(),
                final_position_error_m: Some(o.final_position_error_m),
                final_attitude_error_deg: Some(o.final_attitude_error_rad.to_degrees()),
                fault_ticks: o.fault_ticks,
                initial: d.into(),
            },
            RunResult::Panicked(msg) => Failure {
                run,
                reason: format!("panic: {msg}"),
                final_position_error_m: None,
                final_attitude_error_deg: None,
                fault_ticks: 0,
                initial: d.into(),
            },
        })
        .collect();
    let saturated_pct = if flew.is_empty() {
        0.0
    } else {
        100.0
            * flew
                .iter()
                .map(|o| o.saturated_ticks as f64 / o.ticks.max(1) as f64)
                .sum::<f64>()
            / flew.len() as f64
    };
    ControllerSummary {
        controller,
        runs: results.len(),
        converged: n_conv,
        converged_pct: if results.is_empty() {
            0.0
        } else {
            100.0 * n_conv as f64 / results.len() as f64
        },
        non_finite_runs: count(&|o| o.non_finite),
        fault_runs: count(&|o| o.fault_ticks > 0),
        plant_fault_runs: count(&|o| o.end == Exit::PlantFault),
        fly_away_runs: count(&|o| o.end == Exit::FlyAway),
        panics: results.len() - flew.len(),
        worst_final_position_error_m: worst(&|o| o.final_position_error_m),
        worst_final_attitude_error_deg: worst(&|o| o.final_attitude_error_rad.to_degrees()),
        max_tilt_deg: worst(&|o| o.max_tilt_rad.to_degrees()).unwrap_or(0.0),
        saturated_pct,
        convergence_time_s: match (
            nearest_rank(&times, 50.0),
            nearest_rank(&times, 95.0),
            nearest_rank(&times, 100.0),
        ) {
            (Some(median), Some(p95), Some(max)) => Some(Quantiles { median, p95, max }),
            _ => None,
        },
        by_tilt_deg: bands(&tilt_pairs, env.max_tilt_rad.to_degrees(), 3),
        by_rate_rad_s: bands(&rate_pairs, env.max_rate_rad_s, 3),
        by_heading_error_deg: bands(&heading_pairs, 180.0, 3),
        failures,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{UnitQuat, Vec3};

    fn outcome(converged: bool, t: f64, e_p: f64) -> TrialOutcome {
        TrialOutcome {
            end: Exit::Complete,
            converged,
            convergence_time_s: converged.then_some(t),
            final_position_error_m: e_p,
            final_attitude_error_rad: 0.01,
            max_tilt_rad: 0.5,
            non_finite: false,
            fault_ticks: 0,
            saturated_ticks: 10,
            ticks: 100,
        }
    }

    fn draw(tilt_rad: f64) -> Draw {
        Draw {
            pos_w: Vec3::zeros(),
            vel_w: Vec3::zeros(),
            q_wb: UnitQuat::from_euler_angles(tilt_rad, 0.0, 0.0),
            omega_b: Vec3::new(0.0, 0.0, 1.0),
            force_w: Vec3::zeros(),
            torque_b: Vec3::zeros(),
            noise_seed: 0,
        }
    }

    #[test]
    fn nearest_rank_percentiles() {
        let v: Vec<f64> = (1..=20).rev().map(f64::from).collect();
        assert_eq!(nearest_rank(&v, 50.0), Some(10.0));
        assert_eq!(nearest_rank(&v, 95.0), Some(19.0));
        assert_eq!(nearest_rank(&v, 100.0), Some(20.0));
        assert_eq!(nearest_rank(&v, 0.1), Some(1.0));
        assert_eq!(nearest_rank(&[], 50.0), None);
        assert_eq!(nearest_rank(&[3.0], 95.0), Some(3.0));
    }

    #[test]
    fn bands_split_the_range_and_keep_the_top_edge() {
        let b = bands(&[(0.0, true), (1.0, false), (2.9, true), (3.0, true)], 3.0, 3);
        assert_eq!(b.iter().map(|b| b.runs).collect::<Vec<_>>(), [1, 1, 2]);
        assert_eq!(b.iter().map(|b| b.converged).collect::<Vec<_>>(), [1, 0, 2]);
        assert_eq!(bands(&[(0.0, true)], 0.0, 3)[0].runs, 1, "a zero-width envelope");
    }

    #[test]
    fn summary_counts_failures_and_panics() {
        let env = Envelope {
            max_tilt_rad: 1.0,
            max_rate_rad_s: 3.0,
            max_speed_m_s: 0.0,
            max_offset_m: 0.0,
            max_force_n: 0.0,
            max_torque_n_m: [0.0; 3],
        };
        let draws = [draw(0.1), draw(0.5), draw(0.9), draw(0.95)];
        let mut nan = outcome(false, 0.0, f64::NAN);
        nan.non_finite = true;
        let results = [
            RunResult::Flew(outcome(true, 1.0, 0.01)),
            RunResult::Flew(outcome(true, 2.0, 0.03)),
            RunResult::Flew(nan),
            RunResult::Panicked("boom".into()),
        ];
        let s = summarize("geometric", &env, Heading::Zero, &draws, &results);
        assert_eq!((s.runs, s.converged, s.panics, s.non_finite_runs), (4, 2, 1, 1));
        assert_eq!(s.converged_pct, 50.0);
        assert_eq!(s.worst_final_position_error_m, Some(0.03), "NaN is not a worst value");
        assert_eq!(
            s.convergence_time_s,
            Some(Quantiles {
                median: 1.0,
                p95: 2.0,
                max: 2.0
            })
        );
        assert_eq!(s.failures.iter().map(|f| f.run).collect::<Vec<_>>(), [2, 3]);
        assert_eq!(s.failures[0].reason, "non_finite");
        assert_eq!(s.failures[1].reason, "panic: boom");
        assert_eq!(s.by_tilt_deg.iter().map(|b| b.runs).collect::<Vec<_>>(), [1, 1, 2]);
        assert_eq!(s.by_tilt_deg[2].converged, 0);
        assert_eq!(s.by_heading_error_deg[0].runs, 4, "every draw heads north");
        assert!((s.saturated_pct - 10.0).abs() < 1e-12);
    }
}
