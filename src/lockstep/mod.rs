//! The lockstep: one [`Pilot`] (the flight controller, or a bare flight core following
//! setpoints) and the plant, stepped together at a fixed step. Simulated time is `k·dt`; nothing
//! here reads a clock, so whoever paces it (the autopilot's tick thread, `sim --speedup`) or
//! runs it flat out (`fly`, `sim`, Monte Carlo, benchmarks) gets the same ticks. Pure.
//!
//! Tick k at t_k = k·dt (zero-order hold of the rotor commands over one step):
//!
//! ```text
//! scheduled rotor failures due at t_k → plant        (FailureSchedule, `--fail-rotor`)
//! sensors_k  = plant.read_sensors()                  sense → electrical power → ESC report
//! control_k  = pilot.control(t_k, sensors_k)         rotor speeds, controller step, events
//! status_k   = plant.step(control_k.rotor_speeds(), dt)
//! report_k   = pilot.report(t_k, sensors_k, control_k, true motor speeds)
//! ```
//!
//! This is the only place outside `src/sitl.rs` that steps the plant
//! (`tests/architecture-rules.sh` checks it). Observers ([`Observer`]) see every tick of
//! [`Lockstep::run`] and say when it ends ([`Exit`]).

pub mod observer;
pub mod rotor_schedule;

use serde::Serialize;

use crate::commander::{Outcome, Request};
use crate::flight::{Control, FlightController, Pilot};
use crate::math::Vec3;
use crate::params::ParamError;
use crate::sitl::{PlantChange, PlantStatus, Sensors, SimPlant};

pub use observer::{Guard, Observer};
pub use rotor_schedule::{FailureSchedule, ScheduledFailure};

/// How a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Exit {
    /// Flew the full duration.
    Complete,
    /// The plant reported a non-finite state or refused the step.
    PlantFault,
    /// Left the sphere the run allows.
    FlyAway,
    /// An observer stopped the run for its own reason (its log could not be written).
    Stopped,
}

impl Exit {
    /// The name in summaries: `complete`, `plant_fault`, `fly_away` or `stopped`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Complete => "complete",
            Self::PlantFault => "plant_fault",
            Self::FlyAway => "fly_away",
            Self::Stopped => "stopped",
        }
    }
}

/// One tick as it happened.
#[derive(Debug, Clone, PartialEq)]
pub struct Tick<R> {
    /// Simulated time of the tick [s].
    pub t_s: f64,
    /// What the plant sensed at the start of the tick.
    pub sensors: Sensors,
    /// What the pilot commanded.
    pub control: Control,
    /// The plant step's flags.
    pub status: PlantStatus,
    /// The pilot's report after the plant step.
    pub report: R,
}

impl<R> Tick<R> {
    /// Reference position of the tick: the setpoint's, else where the vehicle is (world NED) [m].
    pub fn reference_w(&self) -> Vec3 {
        let pos_w = self.sensors.state.pos_w;
        self.control.setpoint.and_then(|sp| sp.pos_w).unwrap_or(pos_w)
    }
}

/// A pilot and the plant it flies, in lockstep at a fixed step.
#[derive(Debug)]
pub struct Lockstep<P> {
    pilot: P,
    plant: SimPlant,
    failures: FailureSchedule,
    dt_s: f64,
    tick: u64,
}

impl<P: Pilot> Lockstep<P> {
    /// `pilot` flying `plant` at step `dt_s` [s] from t = 0.
    pub fn new(pilot: P, plant: SimPlant, dt_s: f64) -> Self {
        Self {
            failures: FailureSchedule::new(plant.failed_rotors().len()),
            pilot,
            plant,
            dt_s,
            tick: 0,
        }
    }

    /// What flies.
    pub fn pilot(&self) -> &P {
        &self.pilot
    }

    /// The plant (read only: it changes only through [`Self::step`] and the pilot's replies).
    pub fn plant(&self) -> &SimPlant {
        &self.plant
    }

    /// Step [s].
    pub fn dt_s(&self) -> f64 {
        self.dt_s
    }

    /// Ticks run so far.
    pub fn ticks(&self) -> u64 {
        self.tick
    }

    /// Simulated time of the next tick [s].
    pub fn time_s(&self) -> f64 {
        self.tick as f64 * self.dt_s
    }

    /// Stops a rotor at a simulated time (`--fail-rotor`).
    pub fn schedule_rotor_failure(&mut self, failure: ScheduledFailure) -> Result<(), String> {
        self.failures.schedule(failure)
    }

    /// One tick (module docs).
    pub fn step(&mut self) -> Tick<P::Report> {
        let t_s = self.time_s();
        if !self.failures.is_empty() {
            let plant = &mut self.plant;
            self.failures.take_due(t_s, |change| plant.apply(&change));
        }
        let sensors = self.plant.read_sensors();
        let control = self.pilot.control(t_s, &sensors);
        let status = self.plant.step(control.rotor_speeds().as_slice(), self.dt_s);
        let report = self.pilot.report(t_s, &sensors, &control, self.plant.motor_speeds());
        self.tick += 1;
        Tick {
            t_s,
            sensors,
            control,
            status,
            report,
        }
    }

    /// Runs up to `ticks` ticks, handing each to `observer`, until it says stop.
    pub fn run<O: Observer<P::Report>>(&mut self, ticks: u64, observer: &mut O) -> Exit {
        for _ in 0..ticks {
            let tick = self.step();
            if let Some(exit) = observer.observe(&tick, &self.plant) {
                return exit;
            }
        }
        Exit::Complete
    }
}

/// Requests and parameter sets between ticks, when the flight controller flies.
impl Lockstep<FlightController> {
    /// Applies a ground-station request at the current tick boundary (the commander sees the
    /// state sensed now; an accepted failure injection stops or restores rotors in the plant).
    pub fn request(&mut self, request: Request) -> Outcome {
        let t_s = self.time_s();
        let plant = &mut self.plant;
        let reply = self.pilot.request(request, t_s, || plant.sense());
        self.carry_out(reply.plant);
        reply.answer
    }

    /// Sets parameter `name` to `value` at the current tick boundary.
    pub fn set_param(&mut self, name: &str, value: f64) -> Result<usize, ParamError> {
        let reply = self.pilot.set_param(name, value);
        self.carry_out(reply.plant);
        reply.answer
    }

    /// Keeps the offboard setpoint fresh at the current tick (the stream is alive in wall time).
    pub fn refresh_offboard(&mut self) {
        let t_s = self.time_s();
        self.pilot.refresh_offboard(t_s);
    }

    fn carry_out(&mut self, change: Option<PlantChange>) {
        if let Some(change) = change {
            self.plant.apply(&change);
        }
    }
}
