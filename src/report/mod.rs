//! What the informational commands print: `alloc` (G_q), `gains` (estimator design) and
//! `estimate` (offline estimator run).

mod alloc;
mod estimate;
mod gains;

pub use alloc::AllocReport;
pub use estimate::{estimate_csv, EstimateReport, FinalWrench};
pub use gains::GainsReport;
