//! The wrench estimator's Chebyshev design (`RP_EST_*`, docs/estimator.md §6): order 0 switches it off.

use crate::params::{ParamDef, VehicleSettings};
use crate::wrench_estimator::{ChebyshevDesign, MAX_ORDER};

/// Ripple [dB] and passband edge [rad/s] shown while the estimator is off, and taken when an
/// order switches it on before its ripple and edge are set (the homework's first design).
const WHEN_OFF: ChebyshevDesign = ChebyshevDesign {
    order: 1,
    ripple_db: 3.0,
    passband_rad_s: 2.0,
};

fn order(s: &VehicleSettings) -> f64 {
    s.estimator.map_or(0.0, |d| d.order as f64)
}

/// Order 0 switches the estimator off; another order keeps the design's ripple and edge.
fn set_order(s: &mut VehicleSettings, v: f64) -> Result<(), String> {
    let order = v as usize;
    let design = s.estimator.unwrap_or(WHEN_OFF);
    s.estimator = (order > 0).then_some(ChebyshevDesign { order, ..design });
    Ok(())
}

/// Order, ripple and passband edge (indices 9–11).
pub(super) static DESIGN: &[ParamDef] = &[
    row!(
        "RP_EST_ORDER",
        Int32,
        [0.0, MAX_ORDER as f64],
        "",
        Estimator,
        "Wrench estimator order (0: off); it only observes while RP_COMP is 0",
        order,
        set_order
    ),
    row!(
        "RP_EST_RIPPLE",
        Real32,
        [0.01, 20.0],
        "dB",
        Estimator,
        "Passband ripple of the estimator's Chebyshev filter",
        field ripple_db of estimator or WHEN_OFF
    ),
    row!(
        "RP_EST_WP",
        Real32,
        [0.01, 1000.0],
        "rad/s",
        Estimator,
        "Passband edge of the estimator's Chebyshev filter; a design unstable at the tick is refused, naming the largest stable edge",
        field passband_rad_s of estimator or WHEN_OFF
    ),
];
