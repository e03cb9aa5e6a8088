//! Estimation: Chebyshev gain design and the momentum-based wrench estimator (control.md §7).

mod chebyshev;
mod wrench_observer;

pub use chebyshev::{estimator_gains, ChebyshevDesign, DesignError, Pole, MAX_ORDER};
pub use wrench_observer::{ObserverInput, WrenchEstimate, WrenchObserver};
