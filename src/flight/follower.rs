//! A bare flight core following a setpoint source, without commander, failsafes or battery: how
//! `rotorpilot fly` (a take-off climb), `rotorpilot sim` (a scenario's trajectory) and Monte
//! Carlo runs (a fixed hover) fly. Rotors that fail (a scenario's `[[rotor_failure]]`) are
//! allocated around as the flight controller does. Pure.

use crate::control::{FlatSetpoint, VehicleState};
use crate::guidance::trajectory::Trajectory;
use crate::guidance::ClimbProfile;
use crate::sitl::{EscReport, PlantTruth, Sensors};

use super::rotor_monitor::RotorMonitor;
use super::state_source::StateSource;
use super::{Control, FlightCore, Pilot};

/// Where the setpoint of every tick comes from.
pub trait SetpointSource {
    /// The setpoint at simulated time `t_s` [s].
    fn setpoint(&self, t_s: f64) -> FlatSetpoint;
}

/// A fixed setpoint (hold).
impl SetpointSource for FlatSetpoint {
    fn setpoint(&self, _t_s: f64) -> FlatSetpoint {
        *self
    }
}

/// The take-off climb and the hover at its end.
impl SetpointSource for ClimbProfile {
    fn setpoint(&self, t_s: f64) -> FlatSetpoint {
        ClimbProfile::setpoint(self, t_s)
    }
}

/// A scenario trajectory, sampled with its derivatives.
impl SetpointSource for Trajectory {
    fn setpoint(&self, t_s: f64) -> FlatSetpoint {
        self.sample(t_s).setpoint()
    }
}

/// A flight core flying the setpoints of `S`.
#[derive(Debug, Clone)]
pub struct SetpointFollower<S> {
    /// The control law, allocation and estimator.
    pub core: FlightCore,
    /// Where the setpoints come from.
    pub source: S,
    rotors: RotorMonitor,
    nav: StateSource,
}

impl<S: SetpointSource> SetpointFollower<S> {
    /// `core` following `source`.
    pub fn new(core: FlightCore, source: S) -> Self {
        let rotors = RotorMonitor::new(core.allocator().rotor_count());
        Self {
            core,
            source,
            rotors,
            nav: StateSource::default(),
        }
    }

    /// The same follower with its navigation filter started at `x` (the plant's state when a
    /// headless run starts; docs/navigation_filter.md §11) instead of aligning at rest.
    pub fn starting_at(mut self, x: &VehicleState) -> Self {
        self.nav.start_at(x);
        self
    }
}

impl<S: SetpointSource> Pilot for SetpointFollower<S> {
    type Report = ();

    /// `FlightCore::step` on the sensed state and the source's setpoint, allocated around the
    /// rotors the ESCs report failed.
    fn control(&mut self, t_s: f64, sensors: &Sensors, esc: &EscReport<'_>) -> Control {
        self.rotors.reallocate(esc.failed_rotors(), &mut self.core);
        let setpoint = self.source.setpoint(t_s);
        let state = self.nav.update(t_s, sensors);
        Control {
            state,
            rotors: self.core.allocator().rotor_count(),
            step: Some(self.core.step(&state, &setpoint)),
            setpoint: Some(setpoint),
            events: Vec::new(),
        }
    }

    fn report(
        &self,
        _t_s: f64,
        _sensors: &Sensors,
        _control: &Control,
        _motor_speeds: &[f64],
        _truth: impl FnOnce() -> PlantTruth,
    ) {
    }
}
