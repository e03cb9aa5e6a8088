//! The external wrench a controller may compensate (control.md §4–§6, "[− f̂_e]", "[− τ̂_e]").

use crate::math::Vec3;

/// Estimated external wrench handed to a controller.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ExternalWrench {
    /// f̂_e, world NED [N].
    pub force_w: Vec3,
    /// τ̂_e^b = Q⁻ᵀ τ̂_e, body FRD [N·m].
    pub torque_b: Vec3,
}

impl ExternalWrench {
    /// True when every component is finite.
    pub fn is_finite(&self) -> bool {
        self.force_w.iter().chain(self.torque_b.iter()).all(|x| x.is_finite())
    }
}
