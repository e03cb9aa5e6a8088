//! `rotorpilot estimate`: the offline estimator run as a JSON summary and an OUT.csv text.

use std::fmt::Write as _;

use serde::Serialize;

use crate::wrench_estimator::log_replay::ReplayRow;

/// Final external wrench: force world NED [N], torque body FRD [N·m].
#[derive(Debug, Clone, Copy, Serialize, PartialEq)]
pub struct FinalWrench {
    /// [N]
    pub fx: f64,
    /// [N]
    pub fy: f64,
    /// [N]
    pub fz: f64,
    /// [N·m]
    pub tx: f64,
    /// [N·m]
    pub ty: f64,
    /// [N·m]
    pub tz: f64,
}

/// `{"samples": N, "final": {...}, "mass_estimate": ..}`.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct EstimateReport {
    /// Rows processed.
    pub samples: usize,
    /// Estimate after the last row.
    #[serde(rename = "final")]
    pub final_wrench: FinalWrench,
    /// m_e + f̂_z / g after the last row [kg].
    pub mass_estimate: f64,
}

impl EstimateReport {
    /// Summary of a replay; `None` for an empty one.
    pub fn new(rows: &[ReplayRow]) -> Option<Self> {
        let last = rows.last()?.estimate;
        Some(Self {
            samples: rows.len(),
            final_wrench: FinalWrench {
                fx: last.force_w.x,
                fy: last.force_w.y,
                fz: last.force_w.z,
                tx: last.torque_b.x,
                ty: last.torque_b.y,
                tz: last.torque_b.z,
            },
            mass_estimate: last.mass_kg,
        })
    }
}

/// OUT.csv: `t,fx,fy,fz,tx,ty,tz,mass`, one row per sample.
pub fn estimate_csv(rows: &[ReplayRow]) -> String {
    let mut out = String::from("t,fx,fy,fz,tx,ty,tz,mass\n");
    for r in rows {
        let (f, t) = (r.estimate.force_w, r.estimate.torque_b);
        let _ = writeln!(
            out,
            "{},{},{},{},{},{},{},{}",
            r.t_s, f.x, f.y, f.z, t.x, t.y, t.z, r.estimate.mass_kg
        );
    }
    out
}
