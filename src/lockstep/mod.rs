//! The lockstep: one [`Pilot`] (the flight controller, or a bare flight core following
//! setpoints) and the plant, stepped together at a fixed step. Simulated time is `k·dt`; nothing
//! here reads a clock, so whoever paces it (the autopilot's tick thread, `sim --speedup`) or
//! runs it flat out (`fly`, `sim`, Monte Carlo, benchmarks) gets the same ticks. Pure.
//!
//! Tick k at t_k = k·dt (zero-order hold of the rotor commands over one step):
//!
//! ```text
//! scheduled failures due at t_k → plant              (FailureSchedule, `--fail-rotor`, `--fail`)
//! sensors_k  = plant.read_sensors()                  sensed state, accelerometer
//! control_k  = pilot.control(t_k, sensors_k, esc)    rotor speeds, controller step, events
//!                                                    (esc: failed rotors, electrical power)
//! status_k   = plant.step(control_k.rotor_speeds(), dt)
//! report_k   = pilot.report(t_k, sensors_k, control_k, true motor speeds, plant truth)
//!                                                    (the truth read only by a pilot that
//!                                                    publishes it: telemetry, never control)
//! ```
//!
//! This is the only place outside `src/sitl.rs` that steps the plant
//! (`tests/architecture-rules.sh` checks it). Observers ([`Observer`]) see every tick of
//! [`Lockstep::run`] and say when it ends ([`Exit`]).

pub mod failure_schedule;
pub mod observer;
pub mod view;

use serde::Serialize;
use thiserror::Error;

use crate::airframe::AirframeError;
use crate::commander::{Outcome, Request};
use crate::flight::{Control, CoreError, FlightController, Pilot};
use crate::math::Vec3;
use crate::params::ParamError;
use crate::sitl::{PlantChange, PlantStatus, Sensors, SimPlant, SitlError};

pub use failure_schedule::{FailureSchedule, ScheduledFailure, ScheduledSensorFailure};
pub use observer::{Guard, Observer};
pub use view::{SnapshotReport, TickView};

/// Why a flight cannot be set up: the flight controller's view of the airframe, its flight core
/// or the plant was refused. Every runner (`fly`, `sim`, Monte Carlo, the autopilot) reports it.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SetupError {
    /// The FC refused the airframe.
    #[error(transparent)]
    Airframe(#[from] AirframeError),
    /// The flight core cannot be built for the airframe.
    #[error(transparent)]
    Core(#[from] CoreError),
    /// The plant refused the airframe.
    #[error(transparent)]
    Plant(#[from] SitlError),
}

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
        let pos_w = self.control.state.pos_w;
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

    /// Fails a sensor at a simulated time (`--fail`).
    pub fn schedule_sensor_failure(&mut self, failure: ScheduledSensorFailure) {
        self.failures.schedule_sensor(failure);
    }

    /// Replaces the rotor failures to come with `schedule` (checked against the same airframe,
    /// e.g. a scenario's `[[rotor_failure]]`).
    pub fn set_rotor_failures(&mut self, schedule: FailureSchedule) {
        self.failures = schedule;
    }

    /// One tick (module docs).
    pub fn step(&mut self) -> Tick<P::Report> {
        let t_s = self.time_s();
        if !self.failures.is_empty() {
            let plant = &mut self.plant;
            self.failures.take_due(t_s, |change| plant.apply(&change));
        }
        let sensors = self.plant.read_sensors();
        let control = self.pilot.control(t_s, &sensors, &self.plant.esc());
        let status = self.plant.step(control.rotor_speeds().as_slice(), self.dt_s);
        let plant = &self.plant;
        let report = self
            .pilot
            .report(t_s, &sensors, &control, plant.motor_speeds(), || plant.truth());
        self.tick += 1;
        Tick {
            t_s,
            sensors,
            control,
            status,
            report,
        }
    }

    /// One tick ([`Self::step`]) handed to `observer`: the tick, and the end of the run the
    /// observer asks for, if it does. A runner that does something between ticks (the
    /// autopilot applies requests) steps this way; [`Self::run`] is the same in a loop.
    pub fn step_observed<O: Observer<P::Report>>(&mut self, observer: &mut O) -> (Tick<P::Report>, Option<Exit>) {
        let tick = self.step();
        let exit = observer.observe(&tick, &self.plant);
        (tick, exit)
    }

    /// Runs up to `ticks` ticks, handing each to `observer`, until it says stop.
    pub fn run<O: Observer<P::Report>>(&mut self, ticks: u64, observer: &mut O) -> Exit {
        for _ in 0..ticks {
            if let (_, Some(exit)) = self.step_observed(observer) {
                return exit;
            }
        }
        Exit::Complete
    }
}

/// Requests and parameter sets between ticks, when the flight controller flies.
impl Lockstep<FlightController> {
    /// Applies a ground-station request at the current tick boundary (the commander sees the
    /// state the latest tick flew on, never a reading of its own; an accepted failure injection
    /// stops or restores rotors in the plant).
    pub fn request(&mut self, request: Request) -> Outcome {
        let t_s = self.time_s();
        let reply = self.pilot.request(request, t_s);
        self.carry_out(reply.plant);
        reply.answer
    }

    /// Sets parameter `name` to `value` at the current tick boundary.
    pub fn set_param(&mut self, name: &str, value: f64) -> Result<usize, ParamError> {
        let reply = self.pilot.set_param(name, value);
        self.carry_out(reply.plant);
        reply.answer
    }

    fn carry_out(&mut self, change: Option<PlantChange>) {
        if let Some(change) = change {
            self.plant.apply(&change);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::airframe::{Airframe, AirframeSource};
    use crate::commander::Event;
    use crate::control::{ControllerKind, FlatSetpoint};
    use crate::flight::{FlightCore, SetpointFollower};
    use crate::guidance::Home;

    fn hover(preset: &str) -> Lockstep<SetpointFollower<FlatSetpoint>> {
        let src = AirframeSource::resolve(preset).unwrap();
        let af = Airframe::from_source(&src).unwrap();
        let core = FlightCore::for_airframe(&af, ControllerKind::Geometric, 1e-3).unwrap();
        let plant = SimPlant::from_source(&src, 0).unwrap();
        Lockstep::new(
            SetpointFollower::new(core, FlatSetpoint::hold(Vec3::zeros(), 0.0)),
            plant,
            1e-3,
        )
    }

    fn autopilot(preset: &str) -> Lockstep<FlightController> {
        let src = AirframeSource::resolve(preset).unwrap();
        let af = Airframe::from_source(&src).unwrap();
        let fc = FlightController::new(&af, ControllerKind::Geometric, Home::default(), 1e-3).unwrap();
        Lockstep::new(fc, SimPlant::from_source(&src, 0).unwrap(), 1e-3)
    }

    /// Stops after `n` ticks.
    struct StopAfter(u64);

    impl<R> Observer<R> for StopAfter {
        fn observe(&mut self, _tick: &Tick<R>, _plant: &SimPlant) -> Option<Exit> {
            self.0 -= 1;
            (self.0 == 0).then_some(Exit::Stopped)
        }
    }

    #[test]
    fn runs_count_ticks_in_simulated_time_and_end_where_an_observer_says() {
        let mut l = hover("quad_x");
        assert_eq!(l.run(3, &mut ()), Exit::Complete);
        assert_eq!((l.ticks(), l.time_s()), (3, 3.0 * 1e-3));
        let tick = l.step();
        assert_eq!(tick.t_s, 3.0 * 1e-3);
        assert_eq!(tick.control.rotor_speeds().as_slice().len(), 4);
        assert_eq!(l.run(100, &mut (StopAfter(5), ())), Exit::Stopped);
        assert_eq!(l.ticks(), 9);
        // A sphere the vehicle is already outside of ends the run after one tick.
        assert_eq!(l.run(100, &mut Guard { fly_away_m: -1.0 }), Exit::FlyAway);
        assert_eq!(l.ticks(), 10);
    }

    #[test]
    fn a_scheduled_rotor_failure_reaches_the_esc_report_at_its_time() {
        let mut l = autopilot("hexa_x");
        let bad = ScheduledFailure { rotor: 7, at_s: 0.0 };
        assert_eq!(
            l.schedule_rotor_failure(bad),
            Err("rotor 7: this vehicle has rotors 1 to 6".to_string())
        );
        l.schedule_rotor_failure(ScheduledFailure { rotor: 2, at_s: 0.0025 })
            .unwrap();
        for k in 0..5 {
            let tick = l.step();
            let failed = l.plant().failed_rotors()[1];
            assert_eq!(failed, k >= 3, "tick {k} at {} s", tick.t_s);
            let announced = tick
                .control
                .events
                .iter()
                .any(|e| matches!(e, Event::Failsafe(_, t) if t.starts_with("Motor 2 failed")));
            // Disarmed, no motor is commanded: the ESC check (FD_ACT_EN) suspects none.
            assert!(!announced, "tick {k}: {:?}", tick.control.events);
        }
    }

    #[test]
    fn failure_injection_is_gated_by_the_flight_controller_and_carried_out_on_the_plant() {
        let mut l = autopilot("hexa_x");
        let inject = Request::InjectRotorFailure { rotor: 1, failed: true };
        l.set_param("SYS_FAILURE_EN", 0.0).unwrap();
        assert!(matches!(l.request(inject.clone()), Outcome::Denied(_)));
        assert!(!l.plant().failed_rotors()[0]);
        l.set_param("SYS_FAILURE_EN", 1.0).unwrap();
        assert_eq!(l.request(inject), Outcome::Accepted);
        assert!(l.plant().failed_rotors()[0], "failed at once, before the next tick");
        let restore = Request::InjectRotorFailure {
            rotor: 0,
            failed: false,
        };
        assert_eq!(l.request(restore), Outcome::Accepted);
        assert!(l.plant().failed_rotors().iter().all(|f| !f));
    }

    #[test]
    fn a_request_between_ticks_reads_nothing_from_the_plant() {
        let (mut asked, mut quiet) = (autopilot("quad_x"), autopilot("quad_x"));
        for _ in 0..3 {
            assert_eq!(asked.step().sensors, quiet.step().sensors);
        }
        // The commander decides on the state of the latest tick: the plant's noise is not
        // drawn between ticks, so the next readings are the same as without the request.
        assert_eq!(asked.request(Request::Arm { force: false }), Outcome::Accepted);
        assert_eq!(asked.step().sensors, quiet.step().sensors);
    }

    #[test]
    fn the_flight_controller_idles_the_rotors_and_reports_a_snapshot_while_disarmed() {
        let mut l = autopilot("quad_x");
        let tick = l.step();
        assert!(tick.control.step.is_none() && tick.control.setpoint.is_none());
        assert_eq!(tick.control.rotor_speeds().as_slice(), &[0.0; 4]);
        let s = tick.report;
        assert!(!s.armed);
        assert_eq!((s.t_s, s.rotor_count), (0.0, 4));
        assert_eq!(s.pos_w, tick.control.state.pos_w);
        assert_eq!(&s.rotor_speeds[..4], l.plant().motor_speeds());
    }
}
