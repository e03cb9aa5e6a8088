//! Vehicle state, setpoints and the three flight-control laws of the homework behind one
//! interface ([`Controller`]). Controllers take the state and a setpoint and return a
//! [`Wrench`](crate::allocation::Wrench); they never touch clocks or I/O.
//!
//! - [`geometric`]: Lee et al. on SE(3) (docs/control.md §5).
//! - [`hierarchical`]: RPY, feedback-linearised inner loop (docs/control.md §4).
//! - [`passivity`]: RPY, passivity-based, no feedback linearisation (docs/control.md §6).
//!
//! The two RPY laws are their gains' outer and inner loops run by one shared skeleton
//! (`rpy_law`: μ_d → η_d by `rpy_reference` → τ_b, estimate compensation); the attitude part
//! of the geometric law also serves offboard attitude targets ([`attitude_target`]).

pub mod attitude_target;
mod controller;
pub mod filters;
mod gains;
pub mod geometric;
pub mod hierarchical;
pub mod low_pass;
mod output;
pub mod passivity;
pub mod reference;
pub mod rpy_extraction;
mod rpy_law;
mod rpy_reference;
mod setpoint;
mod state;

pub use attitude_target::AttitudeTarget;
pub use controller::{ControlInput, Controller, ControllerError, ControllerKind};
pub use gains::{
    ControlLimits, ControllerGains, GeometricGains, HierarchicalGains, PassivityGains, VehicleModel,
    REFERENCE_INERTIA_KG_M2, REFERENCE_MASS_KG,
};
pub use geometric::DesiredRateMode;
pub use output::{ControlFlags, ControlOutput, TrackingErrors};
pub use setpoint::FlatSetpoint;
pub use state::VehicleState;
