//! Estimation: Chebyshev gain design, the momentum-based wrench estimator (docs/estimator.md), the
//! [`WrenchEstimate`] it produces (the one external-wrench value every layer passes on) and its
//! offline run over a flight log.

mod chebyshev;
pub mod log_replay;
pub mod ulog_log;
mod wrench_estimate;
mod wrench_observer;

pub use chebyshev::{estimator_gains, ChebyshevDesign, DesignError, Pole, MAX_ORDER};
pub use wrench_estimate::WrenchEstimate;
pub use wrench_observer::{ObserverError, ObserverInput, WrenchObserver};
