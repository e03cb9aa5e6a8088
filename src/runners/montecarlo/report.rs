//! What `rotorpilot montecarlo` prints: one JSON object, or a text table per control law.

use std::fmt::Write as _;

use serde::Serialize;

use crate::lockstep::ScheduledFailure;
use crate::wrench_estimator::ChebyshevDesign;

use super::envelope::Envelope;
use super::stats::{Band, ControllerSummary};
use super::trial::{Criterion, Heading};

/// Failed runs listed per law in the text output (the JSON lists them all).
const TEXT_FAILURES: usize = 10;

/// The envelope in the units of the command line.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct EnvelopeReport {
    /// Largest initial tilt [deg].
    pub max_tilt_deg: f64,
    /// Initial heading: always any, uniform in [−180°, 180°).
    pub yaw: &'static str,
    /// Largest initial ‖ω_0‖ [rad/s].
    pub max_rate_rad_s: f64,
    /// Largest initial ‖v_0‖ [m/s].
    pub max_speed_m_s: f64,
    /// Largest initial ‖p_0‖ [m].
    pub max_offset_m: f64,
    /// Largest constant ‖f_e‖, world NED [N].
    pub max_force_n: f64,
    /// Largest constant |τ_e,i| per body axis, FRD [N·m].
    pub max_torque_n_m: [f64; 3],
}

impl From<&Envelope> for EnvelopeReport {
    fn from(e: &Envelope) -> Self {
        Self {
            max_tilt_deg: e.max_tilt_rad.to_degrees(),
            yaw: "any",
            max_rate_rad_s: e.max_rate_rad_s,
            max_speed_m_s: e.max_speed_m_s,
            max_offset_m: e.max_offset_m,
            max_force_n: e.max_force_n,
            max_torque_n_m: e.max_torque_n_m,
        }
    }
}

/// The criterion in readable units.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CriterionReport {
    /// Position tolerance [m].
    pub position_m: f64,
    /// Attitude tolerance [deg].
    pub attitude_deg: f64,
    /// Final window [s].
    pub window_s: f64,
}

impl From<&Criterion> for CriterionReport {
    fn from(c: &Criterion) -> Self {
        Self {
            position_m: c.position_m,
            attitude_deg: c.attitude_rad.to_degrees(),
            window_s: c.window_s,
        }
    }
}

/// The estimator's Chebyshev design.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct EstimatorReport {
    /// Order r.
    pub order: usize,
    /// Passband ripple [dB].
    pub ripple_db: f64,
    /// Passband edge [rad/s].
    pub wp_rad_s: f64,
}

impl From<&ChebyshevDesign> for EstimatorReport {
    fn from(d: &ChebyshevDesign) -> Self {
        Self {
            order: d.order,
            ripple_db: d.ripple_db,
            wp_rad_s: d.passband_rad_s,
        }
    }
}

/// A whole campaign. Deterministic: the same options and seed give the same value (no wall
/// time in it).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Report {
    /// Airframe name.
    pub airframe: String,
    /// Runs per control law.
    pub runs: usize,
    /// Seed of the draws.
    pub seed: u64,
    /// Simulated time per run [s].
    pub duration_s: f64,
    /// Step [s].
    pub dt_s: f64,
    /// Envelope of the draws.
    pub envelope: EnvelopeReport,
    /// Convergence criterion.
    pub criterion: CriterionReport,
    /// Estimator (`null`: off).
    pub estimator: Option<EstimatorReport>,
    /// Compensation of the estimated wrench.
    pub compensation: bool,
    /// Heading of the hover setpoint: `zero` or `initial`.
    pub heading: Heading,
    /// Rotors that stop in every run (`--fail-rotor`).
    pub rotor_failures: Vec<ScheduledFailure>,
    /// One summary per control law, in the order asked for.
    pub controllers: Vec<ControllerSummary>,
}

fn opt(x: Option<f64>, digits: usize) -> String {
    x.map_or("-".into(), |v| format!("{v:.digits$}"))
}

/// A band edge with at most two decimals and no trailing zeros.
fn edge(x: f64) -> String {
    let s = format!("{x:.2}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

fn band_line(bands: &[Band], unit: &str) -> String {
    bands
        .iter()
        .map(|b| {
            let pct = if b.runs == 0 {
                "-".into()
            } else {
                format!("{:.1} %", 100.0 * b.converged as f64 / b.runs as f64)
            };
            format!("{}–{}{unit}: {pct} of {}", edge(b.lo), edge(b.hi), b.runs)
        })
        .collect::<Vec<_>>()
        .join(", ")
}

impl Report {
    /// The text table.
    pub fn to_text(&self) -> String {
        let e = &self.envelope;
        let c = &self.criterion;
        let mut s = String::new();
        let _ = writeln!(
            s,
            "airframe {}, {} runs per law, seed {}, {} s each at dt {} s",
            self.airframe, self.runs, self.seed, self.duration_s, self.dt_s
        );
        let _ = writeln!(
            s,
            "envelope: tilt ≤ {:.1}°, any yaw, ‖ω‖ ≤ {} rad/s, ‖v‖ ≤ {} m/s, ‖p‖ ≤ {} m, ‖f_e‖ ≤ {:.3} N, |τ_e| ≤ [{:.3}, {:.3}, {:.3}] N·m",
            e.max_tilt_deg, e.max_rate_rad_s, e.max_speed_m_s, e.max_offset_m, e.max_force_n,
            e.max_torque_n_m[0], e.max_torque_n_m[1], e.max_torque_n_m[2]
        );
        let est = self.estimator.map_or("off".into(), |d| {
            format!("order {}, {} dB, wp {} rad/s", d.order, d.ripple_db, d.wp_rad_s)
        });
        let _ = writeln!(
            s,
            "criterion: ‖p‖ < {} m and attitude error < {}° over the last {} s; no non-finite value, no controller fault, no panic",
            c.position_m, c.attitude_deg, c.window_s
        );
        let _ = writeln!(
            s,
            "estimator: {est}; compensation {}; setpoint: hover at the origin, heading {}",
            if self.compensation { "on" } else { "off" },
            match self.heading {
                Heading::Zero => "0 (north)",
                Heading::Initial => "initial",
            }
        );
        for f in &self.rotor_failures {
            let _ = writeln!(s, "rotor {} stops at {} s in every run", f.rotor, f.at_s);
        }
        let _ = writeln!(s);
        let _ = writeln!(
            s,
            "{:<13} {:>5} {:>10} {:>10} {:>6} {:>6} {:>13} {:>11} {:>11} {:>9}",
            "controller",
            "runs",
            "converged",
            "non-finite",
            "faults",
            "panics",
            "worst e_p [m]",
            "t50 [s]",
            "t95 [s]",
            "sat [%]"
        );
        for r in &self.controllers {
            let t = r.convergence_time_s;
            let _ = writeln!(
                s,
                "{:<13} {:>5} {:>8.1} % {:>10} {:>6} {:>6} {:>13} {:>11} {:>11} {:>9.2}",
                r.controller,
                r.runs,
                r.converged_pct,
                r.non_finite_runs,
                r.fault_runs,
                r.panics,
                opt(r.worst_final_position_error_m, 4),
                opt(t.map(|q| q.median), 3),
                opt(t.map(|q| q.p95), 3),
                r.saturated_pct
            );
        }
        for r in &self.controllers {
            if r.failures.is_empty() {
                continue;
            }
            let _ = writeln!(s);
            let _ = writeln!(
                s,
                "{}: {} not converged; converged by tilt {}; by rate {}; by heading change {}",
                r.controller,
                r.failures.len(),
                band_line(&r.by_tilt_deg, "°"),
                band_line(&r.by_rate_rad_s, " rad/s"),
                band_line(&r.by_heading_error_deg, "°")
            );
            for f in r.failures.iter().take(TEXT_FAILURES) {
                let i = &f.initial;
                let _ = writeln!(
                    s,
                    "  run {:>4} {:<18} e_p {} m, e_R {}°; tilt {:.1}°, rpy [{:.0}, {:.0}, {:.0}]°, ‖ω‖ {:.2} rad/s, ‖v‖ {:.2} m/s, ‖f‖ {:.2} N",
                    f.run,
                    f.reason,
                    opt(f.final_position_error_m, 3),
                    opt(f.final_attitude_error_deg, 1),
                    i.tilt_deg,
                    i.rpy_deg[0],
                    i.rpy_deg[1],
                    i.rpy_deg[2],
                    nalgebra::Vector3::from(i.rates_rad_s).norm(),
                    nalgebra::Vector3::from(i.velocity_m_s).norm(),
                    nalgebra::Vector3::from(i.force_n).norm(),
                );
            }
            if r.failures.len() > TEXT_FAILURES {
                let _ = writeln!(s, "  … {} more (all in --json)", r.failures.len() - TEXT_FAILURES);
            }
        }
        s.trim_end().to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn band_edges_are_short() {
        assert_eq!(edge(0.0), "0");
        assert_eq!(edge(20.0), "20");
        assert_eq!(edge(1.0 / 6.0), "0.17");
        assert_eq!(edge(0.5), "0.5");
        let line = band_line(
            &[Band {
                lo: 0.0,
                hi: 1.5,
                runs: 4,
                converged: 3,
            }],
            " rad/s",
        );
        assert_eq!(line, "0–1.5 rad/s: 75.0 % of 4");
    }
}
