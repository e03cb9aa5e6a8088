//! Vehicle state, setpoints and controllers. Controllers take the state and a setpoint and
//! return a [`Wrench`](crate::allocation::Wrench); they never touch clocks or I/O.

mod hover;
mod setpoint;
mod state;

pub use hover::{HoverController, HoverGains};
pub use setpoint::FlatSetpoint;
pub use state::VehicleState;
