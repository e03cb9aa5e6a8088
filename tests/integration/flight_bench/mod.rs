//! The autopilot's flight controller and the plant in lockstep at 1 kHz, with the events of
//! every tick kept (shared by the closed-loop commander tests).
#![allow(dead_code, clippy::unwrap_used, clippy::expect_used)]

use rotorpilot::airframe::{Airframe, AirframeSource};
use rotorpilot::commander::{Commander, CommanderParams, Event, Outcome, Request};
use rotorpilot::control::ControllerKind;
use rotorpilot::flight::FlightController;
use rotorpilot::guidance::Home;
use rotorpilot::lockstep::Lockstep;
use rotorpilot::math::Vec3;
use rotorpilot::mav::link::liveness::StreamLiveness;
use rotorpilot::sitl::SimPlant;

/// The flight controller flying the plant, and every event so far.
pub struct Sim {
    pub lockstep: Lockstep<FlightController>,
    pub events: Vec<Event>,
    /// The liveness of the streams the test sends, judged as a link judges it (simulated time).
    streams: StreamLiveness,
}

impl Sim {
    /// `airframe` with the commander settings `params`.
    pub fn new(airframe: &str, params: CommanderParams) -> Self {
        let src = AirframeSource::resolve(airframe).unwrap();
        let af = Airframe::from_source(&src).unwrap();
        let fc =
            FlightController::with_commander(&af, ControllerKind::Geometric, Home::default(), 1e-3, params).unwrap();
        Self::flying(fc, &src)
    }

    /// `airframe` with the autopilot's defaults ([`FlightController::new`]).
    pub fn autopilot(airframe: &str) -> Self {
        let src = AirframeSource::resolve(airframe).unwrap();
        let af = Airframe::from_source(&src).unwrap();
        let fc = FlightController::new(&af, ControllerKind::Geometric, Home::default(), 1e-3).unwrap();
        Self::flying(fc, &src)
    }

    fn flying(fc: FlightController, src: &AirframeSource) -> Self {
        Self {
            lockstep: Lockstep::new(fc, SimPlant::from_source(src, 0).unwrap(), 1e-3),
            events: Vec::new(),
            streams: StreamLiveness::default(),
        }
    }

    pub fn commander(&self) -> &Commander {
        self.lockstep.pilot().commander()
    }

    /// True position, world NED [m].
    pub fn position(&self) -> Vec3 {
        self.lockstep.plant().truth().pos_w
    }

    /// True velocity, world NED [m/s].
    pub fn velocity(&self) -> Vec3 {
        self.lockstep.plant().truth().vel_w
    }

    pub fn on_ground(&self) -> bool {
        self.lockstep.plant().truth().on_ground
    }

    pub fn request(&mut self, r: Request) -> Outcome {
        if let Some(stream) = r.input_stream() {
            let t_s = self.lockstep.time_s();
            self.streams.heard(stream, t_s, t_s);
        }
        self.lockstep.request(r)
    }

    pub fn run(&mut self, seconds: f64) {
        for _ in 0..(seconds * 1000.0).round() as u64 {
            let t_s = self.lockstep.time_s();
            let params = self.commander().params;
            for stream in self.streams.lost(t_s, t_s, &params) {
                self.lockstep.request(Request::StreamLost(stream));
            }
            let tick = self.lockstep.step();
            self.events.extend(tick.control.events);
        }
    }
}
