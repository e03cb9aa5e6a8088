//! What the informational commands print: `alloc` (G_q) and `gains` (estimator design).

mod alloc;
mod gains;

pub use alloc::AllocReport;
pub use gains::GainsReport;
