//! Minimum-norm inverse of the allocation (docs/allocation.md §3, eq. (3.1)): `ω² = A w` with
//! `A = G_qᵀ (G_q G_qᵀ)⁻¹`, computed once per airframe.

use nalgebra::DMatrix;

use super::AllocationError;

/// Largest condition number of the row-normalised `G_q G_qᵀ` that is accepted.
pub const MAX_CONDITION: f64 = 1e8;

/// `A = G_qᵀ (G_q G_qᵀ)⁻¹` (n × 4); refuses a G_q whose rows are (nearly) dependent.
pub fn min_norm_inverse(g: &DMatrix<f64>) -> Result<DMatrix<f64>, AllocationError> {
    // Rows carry different units (N vs N·m); judge conditioning with each row scaled to unit norm.
    let scales: Vec<f64> = g.row_iter().map(|r| r.norm()).collect();
    if scales.iter().any(|s| *s <= 0.0 || !s.is_finite()) {
        return Err(AllocationError::Singular {
            condition: f64::INFINITY,
        });
    }
    let mut normalised = g.clone();
    for (mut row, s) in normalised.row_iter_mut().zip(&scales) {
        row /= *s;
    }
    let gram = &normalised * normalised.transpose();
    let eig = gram.clone().symmetric_eigenvalues();
    let (lo, hi) = eig
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), e| (lo.min(*e), hi.max(*e)));
    let condition = if lo > 0.0 { hi / lo } else { f64::INFINITY };
    if condition > MAX_CONDITION {
        return Err(AllocationError::Singular { condition });
    }
    let gram_inv = (g * g.transpose())
        .try_inverse()
        .ok_or(AllocationError::Singular { condition })?;
    Ok(g.transpose() * gram_inv)
}

/// Closed-form inverse for an even n ≥ 4 of evenly spaced rotors with alternating spins
/// (docs/allocation.md §3, eq. (3.3)):
/// `ω_i² = u_T/(n c_T) + 2 τx sin α_i/(n c_T l) + 2 τy cos α_i/(n c_T l) + s_i τz/(n c_Q)`.
/// `alpha_rad[i]` and `yaw_sign[i]` describe rotor i; returns A (n × 4).
pub fn closed_form_ring_inverse(c_t: f64, c_q: f64, arm_m: f64, alpha_rad: &[f64], yaw_sign: &[f64]) -> DMatrix<f64> {
    let n = alpha_rad.len() as f64;
    DMatrix::from_fn(alpha_rad.len(), 4, |i, col| match col {
        0 => 1.0 / (n * c_t),
        1 => 2.0 * alpha_rad[i].sin() / (n * c_t * arm_m),
        2 => 2.0 * alpha_rad[i].cos() / (n * c_t * arm_m),
        _ => yaw_sign[i] / (n * c_q),
    })
}
