//! `rotorpilot alloc`: G_q of an airframe as JSON or as a table.

use serde::Serialize;

use crate::airframe::Airframe;
use crate::allocation::Allocator;

/// G_q of an airframe with the constants it is built from (SI units).
#[derive(Debug, Clone, Serialize)]
pub struct AllocReport {
    /// Airframe name.
    pub airframe: String,
    /// Number of rotors n.
    pub rotors: usize,
    /// Thrust coefficient [N/(rad/s)²].
    #[serde(rename = "c_T")]
    pub c_t: f64,
    /// Drag-torque coefficient [N·m/(rad/s)²].
    #[serde(rename = "c_Q")]
    pub c_q: f64,
    /// Hub distance from the centre of mass [m] (the largest if they differ).
    pub arm_length: f64,
    /// Rows u_T [N], τx, τy, τz [N·m], each per (rad/s)² of rotor 1 … n.
    #[serde(rename = "G")]
    pub g: [Vec<f64>; 4],
}

impl AllocReport {
    /// Report of `allocator`, built for `af`.
    pub fn new(af: &Airframe, allocator: &Allocator) -> Self {
        let m = allocator.effectiveness();
        let row = |k: usize| m.row(k).iter().copied().collect::<Vec<f64>>();
        Self {
            airframe: af.name.clone(),
            rotors: af.rotors.len(),
            c_t: af.c_t,
            c_q: af.c_q,
            arm_length: af.arm_length_m(),
            g: [row(0), row(1), row(2), row(3)],
        }
    }

    /// Human-readable table.
    pub fn to_table(&self) -> String {
        let mut s = format!(
            "airframe {}: {} rotors, c_T = {:e} N/(rad/s)², c_Q = {:e} N·m/(rad/s)², arm {} m\n",
            self.airframe, self.rotors, self.c_t, self.c_q, self.arm_length
        );
        s.push_str("G_q maps [ω_1², …, ω_n²] to [u_T, τx, τy, τz]:\n");
        s.push_str(&format!("{:>8}", ""));
        for i in 1..=self.rotors {
            s.push_str(&format!("{:>14}", format!("rotor {i}")));
        }
        s.push('\n');
        for (label, row) in ["u_T [N]", "τx [N·m]", "τy [N·m]", "τz [N·m]"].iter().zip(&self.g) {
            s.push_str(&format!("{label:>8}"));
            for v in row {
                s.push_str(&format!("{v:>14.6e}"));
            }
            s.push('\n');
        }
        s
    }
}
