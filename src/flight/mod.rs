//! What flies the plant, behind one interface ([`Pilot`]) the lockstep calls every tick:
//!
//! - [`FlightController`]: the autopilot's flight software: commander (modes, failsafes,
//!   battery, land detector), flight core, parameter table, rotor-failure monitor and home;
//! - [`SetpointFollower`]: a bare flight core following a setpoint source (a trajectory, a
//!   take-off climb, a fixed hover), as scenario and Monte Carlo runs fly;
//! - [`OffboardPilot`]: the flight controller flown in OFFBOARD along a setpoint source, as
//!   scenarios with an `[autopilot]` table fly (failsafes and battery included).
//!
//! Pure: values in (the sensed state and time), values out (rotor speeds, the controller step,
//! events, the telemetry snapshot).
//!
//! # Layout
//!
//! - [`flight_core`]: one control tick: estimator → controller → allocation → estimator.
//! - [`controller`]: the flight controller.
//! - [`follower`]: the bare flight core and its setpoint sources.
//! - [`state_source`]: the state the controllers fly on: the state sensor's, or the navigation
//!   filter's estimate.
//! - [`offboard_pilot`]: the flight controller in OFFBOARD along a setpoint source.
//! - [`motor_failures`]: what the flight controller knows and does about failed motors:
//!   failure injection, the ESC check, the allocation around them.
//! - [`rotor_monitor`]: what a bare flight core knows of failed rotors.
//! - [`snapshot`]: the telemetry snapshot of a tick (the one place it is built).
//! - `stale_check`: a sensor whose readings repeat exactly is stuck (PX4's data validator).

pub mod flight_controller;
pub mod flight_core;
pub mod follower;
pub mod motor_failures;
pub mod offboard_pilot;
pub mod rotor_monitor;
pub mod snapshot;
mod stale_check;
pub mod state_source;

use crate::allocation::RotorSpeeds;
use crate::commander::Event;
use crate::control::{FlatSetpoint, VehicleState};
use crate::params::ParamTable;
use crate::sitl::{EscReport, PlantTruth, Sensors};

pub use flight_controller::{FlightController, Reply, AUTOPILOT_TILT_MAX_DEG, DEFAULT_ESTIMATOR};
pub use flight_core::{vehicle_model, CoreError, CoreStep, FlightCore};
pub use follower::{SetpointFollower, SetpointSource};
pub use motor_failures::{MotorChange, MotorFailureParams, MotorFailures};
pub use offboard_pilot::OffboardPilot;
pub use state_source::StateSource;

/// What one control tick commands.
#[derive(Debug, Clone, PartialEq)]
pub struct Control {
    /// The vehicle's state as the pilot knew it this tick (its navigation estimate): what the
    /// controllers flew on.
    pub state: VehicleState,
    /// Rotor count.
    pub rotors: usize,
    /// The flight core's step; `None` while the motors are off.
    pub step: Option<CoreStep>,
    /// Setpoint flown, when one is.
    pub setpoint: Option<FlatSetpoint>,
    /// What the commander did on its own this tick (always empty for a bare flight core).
    pub events: Vec<Event>,
}

impl Control {
    /// Rotor speeds for the plant over the next step [rad/s]: the allocation's, or every rotor
    /// stopped while the motors are off.
    pub fn rotor_speeds(&self) -> RotorSpeeds {
        match &self.step {
            Some(step) => step.allocation.omega(),
            None => RotorSpeeds::idle(self.rotors),
        }
    }
}

/// What flies the plant in a [`Lockstep`](crate::lockstep::Lockstep).
pub trait Pilot {
    /// What a tick publishes once the plant has stepped: the telemetry snapshot for the flight
    /// controller, nothing for a bare flight core.
    type Report;

    /// One control tick at simulated time `t_s` [s] from what the plant sensed, its ESCs and its
    /// battery current sensor report.
    fn control(&mut self, t_s: f64, sensors: &Sensors, esc: &EscReport<'_>) -> Control;

    /// The tick's report once the plant has stepped with `control`, its rotors now turning at
    /// `motor_speeds` [rad/s]; `truth` reads the plant's exact state after the step, for a
    /// pilot that passes it through to telemetry (never an input of the flight controller; a
    /// pilot that publishes nothing never reads it).
    fn report(
        &self,
        t_s: f64,
        sensors: &Sensors,
        control: &Control,
        motor_speeds: &[f64],
        truth: impl FnOnce() -> PlantTruth,
    ) -> Self::Report;

    /// The parameter table, for a flight controller (a bare flight core has none).
    fn params(&self) -> Option<&ParamTable> {
        None
    }
}
