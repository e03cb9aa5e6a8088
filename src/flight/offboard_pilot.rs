//! The flight controller flown in OFFBOARD by a setpoint source, as a companion computer flies
//! PX4: how `rotorpilot sim` flies a scenario with an `[autopilot]` table. At its first tick it
//! sends the first setpoint, switches to OFFBOARD and arms (with the pre-arm checks; the vehicle
//! boots resting on the ground); at every tick it sends the source's setpoint, so the stream is
//! never lost. The
//! commander's failsafes (battery, geofence, rotor failure) act as in `rotorpilot run`: once one
//! of them leaves OFFBOARD, the setpoints are no longer flown. Pure.

use crate::commander::{FlightMode, Outcome, Request};
use crate::sitl::{EscReport, PlantTruth, Sensors};
use crate::telemetry::Snapshot;

use super::{Control, FlightController, Pilot, SetpointSource};

/// A flight controller and the setpoint source that flies it in OFFBOARD.
#[derive(Debug)]
pub struct OffboardPilot<S> {
    controller: FlightController,
    source: S,
    started: bool,
    refused: Option<String>,
}

impl<S: SetpointSource> OffboardPilot<S> {
    /// `controller` to be flown along `source` from the first tick.
    pub fn new(controller: FlightController, source: S) -> Self {
        Self {
            controller,
            source,
            started: false,
            refused: None,
        }
    }

    /// The flight controller.
    pub fn controller(&self) -> &FlightController {
        &self.controller
    }

    /// Why the start (OFFBOARD, arming) was refused, if it was.
    pub fn start_refused(&self) -> Option<&str> {
        self.refused.as_deref()
    }
}

impl<S: SetpointSource> Pilot for OffboardPilot<S> {
    type Report = Snapshot;

    /// Sends the setpoint of `t_s` (and at the first tick the mode switch and the arming), then
    /// runs the flight controller's tick.
    fn control(&mut self, t_s: f64, sensors: &Sensors, esc: &EscReport<'_>) -> Control {
        let setpoint = Request::offboard(self.source.setpoint(t_s));
        let mut requests = vec![setpoint];
        if !self.started {
            self.started = true;
            requests.extend([Request::SetMode(FlightMode::Offboard), Request::Arm { force: false }]);
        }
        for request in requests {
            let what = format!("{request:?}");
            let outcome = self.controller.request(request, t_s).answer;
            if outcome != Outcome::Accepted && self.refused.is_none() {
                self.refused = Some(format!("{what}: {outcome:?}"));
            }
        }
        self.controller.control(t_s, sensors, esc)
    }

    fn report(
        &self,
        t_s: f64,
        sensors: &Sensors,
        control: &Control,
        motor_speeds: &[f64],
        truth: impl FnOnce() -> PlantTruth,
    ) -> Snapshot {
        self.controller.report(t_s, sensors, control, motor_speeds, truth)
    }

    fn params(&self) -> Option<&crate::params::ParamTable> {
        Pilot::params(&self.controller)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::airframe::{Airframe, AirframeSource};
    use crate::control::{ControllerKind, FlatSetpoint};
    use crate::guidance::Home;
    use crate::lockstep::Lockstep;
    use crate::math::Vec3;
    use crate::sitl::SimPlant;

    #[test]
    fn the_source_is_flown_in_offboard_from_the_ground() {
        let src = AirframeSource::resolve("quad_x").unwrap();
        let af = Airframe::from_source(&src).unwrap();
        let fc = FlightController::new(&af, ControllerKind::Geometric, Home::default(), 1e-3).unwrap();
        let target = FlatSetpoint::hold(Vec3::new(1.0, 0.0, -2.0), 0.0);
        let plant = SimPlant::from_source(&src, 0).unwrap();
        let mut lockstep = Lockstep::new(OffboardPilot::new(fc, target), plant, 1e-3);
        for _ in 0..10_000 {
            lockstep.step();
        }
        let pilot = lockstep.pilot();
        assert_eq!(pilot.start_refused(), None);
        assert_eq!(pilot.controller().commander().mode(), FlightMode::Offboard);
        assert!(pilot.controller().commander().armed());
        let p = lockstep.plant().truth().pos_w;
        assert!((p - Vec3::new(1.0, 0.0, -2.0)).norm() < 0.05, "{p:?}");
    }
}
