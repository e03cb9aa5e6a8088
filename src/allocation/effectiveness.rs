//! The allocation (effectiveness) matrix G_q ∈ R^{4×n} of n coplanar rotors
//! (docs/allocation.md §2, eqs. (2.1)–(2.3); the homework's octocopter matrix is the n = 8 case):
//! `[u_T, τx, τy, τz]ᵀ = G_q [ω_1², …, ω_n²]ᵀ` with column i
//! `[c_T, c_T l sin α_i, c_T l cos α_i, s_i c_Q]ᵀ`.

use nalgebra::DMatrix;

use crate::airframe::Airframe;

/// G_q built from the FC's own airframe description.
///
/// ```
/// use rotorpilot::airframe::{Airframe, AirframeSource};
/// use rotorpilot::allocation::effectiveness_matrix;
/// let af = Airframe::from_source(&AirframeSource::resolve("octo").unwrap()).unwrap();
/// let g = effectiveness_matrix(&af);
/// assert_eq!((g.nrows(), g.ncols()), (4, 8));
/// assert_eq!(g[(0, 0)], af.c_t);
/// ```
pub fn effectiveness_matrix(af: &Airframe) -> DMatrix<f64> {
    let n = af.rotors.len();
    DMatrix::from_fn(4, n, |row, i| {
        let r = &af.rotors[i];
        match row {
            0 => af.c_t,
            1 => af.c_t * r.arm_m * r.angle_rad.sin(),
            2 => af.c_t * r.arm_m * r.angle_rad.cos(),
            _ => r.spin.yaw_sign() * af.c_q,
        }
    })
}
