//! The flight controller of one vehicle: commander (modes, failsafes, battery, land detector),
//! flight core, parameter table, motor failures and home. Pure: requests and parameter
//! sets between ticks, and one [`Pilot::control`] per tick from the sensed values; what the
//! simulated hardware must change comes back as a [`PlantChange`].
//!
//! One tick (the order every determinism test depends on):
//!
//! ```text
//! motor failures: injected, detected; re-allocate; react   (MotorFailures::update)
//! battery and failsafes from x_k and the electrical power  (Commander::check_failsafes)
//! commander.update(x_k, T_{k−1} / (m g), t_k)              setpoint, attitude target or idle
//! flight core: setpoint, else attitude target, else idle  (FlightCore::step / step_attitude)
//! ```

use crate::commander::FailsafeCause;
use std::sync::Arc;

use crate::airframe::{Airframe, MAX_ROTORS};
use crate::commander::{Commander, CommanderParams, Event, Outcome, Request};
use crate::control::{ControllerKind, VehicleState};
use crate::guidance::Home;
use crate::math::{Vec3, GRAVITY_M_S2};
use crate::params::{ParamError, ParamTable, VehicleSettings};
use crate::sitl::{EscReport, PlantChange, PlantTruth, Sensors};
use crate::telemetry::Snapshot;
use crate::wrench_estimator::{ChebyshevDesign, WrenchObserver};

use super::motor_failures::{MotorChange, MotorFailureParams, MotorFailures};
use super::state_source::StateSource;
use super::{Control, CoreError, FlightCore, Pilot};

/// The estimator the autopilot starts with: the homework's first-order design (Chebyshev
/// 3 dB ripple, passband edge 2 rad/s), observing only (RP_COMP = 0) so it changes nothing in
/// flight but streams the wrench and mass estimate.
pub const DEFAULT_ESTIMATOR: ChebyshevDesign = ChebyshevDesign {
    order: 1,
    ripple_db: 3.0,
    passband_rad_s: 2.0,
};

/// The autopilot's tilt limit [deg] (PX4's `MPC_TILTMAX_AIR` default; the homework
/// scenarios keep the controllers' own 40°).
pub const AUTOPILOT_TILT_MAX_DEG: f64 = 45.0;

/// The answer to a request, and what the simulated hardware must change because of it.
#[derive(Debug, Clone, PartialEq)]
pub struct Reply<T> {
    /// The answer for the sender.
    pub answer: T,
    /// The plant change to carry out now, if any.
    pub plant: Option<PlantChange>,
}

impl<T> Reply<T> {
    fn only(answer: T) -> Self {
        Self { answer, plant: None }
    }
}

/// Commander, flight core, parameters, motor failures and home of one vehicle.
#[derive(Debug)]
pub struct FlightController {
    core: FlightCore,
    commander: Commander,
    /// Published as it is after each set: shared with whoever holds it (the link), copied on
    /// write only while shared.
    params: Arc<ParamTable>,
    motors: MotorFailures,
    motor_params: MotorFailureParams,
    nav: StateSource,
    home: Home,
    dt_s: f64,
    believed_mass_kg: f64,
    believed_inertia_kg_m2: Vec3,
    rotor_max_rad_s: f64,
    /// Collective thrust the controller asked for at the last tick over the believed weight [-]
    /// (land detector input).
    thrust_over_weight: f64,
    /// Each rotor's thrust command at the last tick over its full thrust [-] (the ESC check's
    /// input).
    rotor_thrust: [f64; MAX_ROTORS],
}

impl FlightController {
    /// The autopilot's flight controller for `airframe` flown by `kind`, home `home`, step
    /// `dt_s` [s]: PX4's commander defaults with `MPC_THR_HOVER` at the airframe's hover thrust
    /// (where PX4's hover thrust estimator would settle), tilt limit
    /// [`AUTOPILOT_TILT_MAX_DEG`], the [`DEFAULT_ESTIMATOR`] observing.
    pub fn new(airframe: &Airframe, kind: ControllerKind, home: Home, dt_s: f64) -> Result<Self, CoreError> {
        let mut commander = CommanderParams::default();
        commander.manual.shaping.thrust_hover = airframe.hover_thrust_fraction().clamp(0.1, 0.8);
        Self::with_commander(airframe, kind, home, dt_s, commander)
    }

    /// [`Self::new`] with the commander settings `commander`.
    pub fn with_commander(
        airframe: &Airframe,
        kind: ControllerKind,
        home: Home,
        dt_s: f64,
        commander: CommanderParams,
    ) -> Result<Self, CoreError> {
        let mut core = FlightCore::for_airframe(airframe, kind, dt_s)?;
        let mut gains = *core.controller.gains();
        gains.limits.tilt_max_rad = AUTOPILOT_TILT_MAX_DEG.to_radians();
        core.controller.set_gains(gains).map_err(CoreError::from)?;
        let motors = MotorFailures::new(core.allocator().rotor_count());
        let settings = VehicleSettings {
            commander,
            ..VehicleSettings::new(kind, gains, Some(DEFAULT_ESTIMATOR))
        };
        core.set_airmode(settings.airmode);
        let mut fc = Self {
            core,
            commander: Commander::new(commander),
            params: Arc::new(ParamTable::new(&settings)),
            motors,
            motor_params: settings.motors,
            nav: StateSource::at(&home),
            home,
            dt_s,
            believed_mass_kg: airframe.mass_kg,
            believed_inertia_kg_m2: airframe.inertia_kg_m2,
            rotor_max_rad_s: airframe.omega_max_rad_s,
            thrust_over_weight: 0.0,
            rotor_thrust: [0.0; MAX_ROTORS],
        };
        fc.install_observer(Some(DEFAULT_ESTIMATOR));
        Ok(fc)
    }

    /// Replaces the wrench observer by one of `design` (none when `None` or not realisable).
    fn install_observer(&mut self, design: Option<ChebyshevDesign>) {
        let observer = design.and_then(|d| {
            let gains = d.gains(self.dt_s).ok()?;
            WrenchObserver::new(self.believed_mass_kg, self.believed_inertia_kg_m2, gains, self.dt_s).ok()
        });
        self.core.set_observer(observer);
    }

    /// The parameter table.
    pub fn params(&self) -> &ParamTable {
        &self.params
    }

    /// The parameter table as published, shared: a holder keeps this very table (no copy) until
    /// the next set publishes another (copy-on-write: a set copies the table only while it is
    /// held elsewhere).
    pub fn shared_params(&self) -> Arc<ParamTable> {
        Arc::clone(&self.params)
    }

    /// The commander (mode, arming, landed state, mission progress, battery).
    pub fn commander(&self) -> &Commander {
        &self.commander
    }

    /// Starts the navigation filter aligned at `x` (an `[autopilot]` scenario that starts in
    /// the air; docs/navigation_filter.md §11) instead of aligning at rest.
    pub fn start_navigation_at(&mut self, x: &VehicleState) {
        self.nav.start_at(x);
        self.commander.set_navigation(self.nav.validity());
    }

    /// Flies on the navigation filter fed by the sensor suite (`SensorModel::Suite`): nothing
    /// may arm before the filter is aligned, from the very first request.
    pub fn expect_sensor_suite(&mut self) {
        self.nav.expect_sensor_suite();
        self.commander.set_navigation(self.nav.validity());
    }

    /// What the flight controller knows of its state.
    pub fn state_source(&self) -> &StateSource {
        &self.nav
    }

    /// The flight core.
    pub fn core(&self) -> &FlightCore {
        &self.core
    }

    /// Geodetic position of the local NED origin.
    pub fn home(&self) -> Home {
        self.home
    }

    /// Rotor count.
    pub fn rotor_count(&self) -> usize {
        self.motors.rotor_count()
    }

    /// The motors the flight controller stops in flight (bit i: rotor i + 1): switched off by
    /// failure injection, or left out of the allocation.
    pub fn motors_stopped(&self) -> u32 {
        self.motors.stopped()
    }

    /// Highest rotor speed [rad/s].
    pub fn rotor_max_rad_s(&self) -> f64 {
        self.rotor_max_rad_s
    }

    /// Sets parameter `name` to `value` and applies the new settings at this tick boundary:
    /// commander limits, control law (its filters restart from the next sample), compensation,
    /// gains, the estimator (a new design restarts it from ŵ = 0), and the plant's ground and
    /// ceiling effects or its wind (the reply's plant change). Refused sets change nothing.
    pub fn set_param(&mut self, name: &str, value: f64) -> Reply<Result<usize, ParamError>> {
        let before = self.params.settings();
        let index = match Arc::make_mut(&mut self.params).set(name, value, self.dt_s) {
            Ok(index) => index,
            Err(e) => return Reply::only(Err(e)),
        };
        let s = self.params.settings();
        self.commander.params = s.commander;
        self.core.controller.set_kind(s.controller);
        self.core.controller.set_compensation(s.compensation);
        self.core.set_airmode(s.airmode);
        self.motor_params = s.motors;
        if let Err(e) = self.core.controller.set_gains(s.gains) {
            tracing::warn!("{e}");
        }
        if s.estimator != before.estimator {
            self.install_observer(s.estimator);
        }
        if s.nav != before.nav {
            if let Err(e) = self.nav.set_params(s.nav) {
                tracing::warn!("{e}");
            }
        }
        let plant = match s.wind {
            wind if wind != before.wind => PlantChange::Wind(wind),
            _ => PlantChange::ProximityEffects {
                ground: s.ground_effect,
                ceiling: s.ceiling_effect,
            },
        };
        Reply {
            answer: Ok(index),
            plant: Some(plant),
        }
    }

    /// Handles a ground-station request at simulated time `t_s` [s]: failure injection (when
    /// `SYS_FAILURE_EN` allows it) answers with the rotors the plant must stop or restore;
    /// everything else goes to the commander with the state the latest tick flew on (the state
    /// sensor's reading or the filter's estimate; at rest at the origin before the first tick),
    /// as PX4's commander acts on the latest `vehicle_local_position`. Nothing is sensed between
    /// ticks: the plant is read once per tick, in [`crate::lockstep::Lockstep::step`].
    pub fn request(&mut self, request: Request, t_s: f64) -> Reply<Outcome> {
        let injection = matches!(
            request,
            Request::InjectRotorFailure { .. } | Request::InjectSensorFailure(_)
        );
        if injection && !self.commander.params.failure_injection {
            return Reply::only(Outcome::Denied(
                "Failure injection disabled (SYS_FAILURE_EN = 0)".into(),
            ));
        }
        if let Request::InjectSensorFailure(failure) = request {
            if self.nav.status().is_none() {
                return Reply::only(Outcome::Failed(format!(
                    "Failure injection: {} needs realistic sensors",
                    failure.unit.name()
                )));
            }
            return Reply {
                answer: Outcome::Accepted,
                plant: Some(PlantChange::Sensor(failure)),
            };
        }
        if let Request::InjectRotorFailure { rotor, failed } = request {
            return match self.motors.inject(rotor, failed) {
                Ok(change) => Reply {
                    answer: Outcome::Accepted,
                    plant: Some(change),
                },
                Err(why) => Reply::only(Outcome::Denied(why)),
            };
        }
        let x = self
            .nav
            .latest()
            .unwrap_or_else(|| VehicleState::at_rest(t_s, Vec3::zeros()));
        Reply::only(self.commander.request(request, &x, t_s))
    }
}

impl Pilot for FlightController {
    type Report = Snapshot;

    /// One tick (module docs).
    fn control(&mut self, t_s: f64, sensors: &Sensors, esc: &EscReport<'_>) -> Control {
        let x = self.nav.update(t_s, sensors);
        let mut failsafe_events: Vec<Event> = self
            .nav
            .announcements()
            .into_iter()
            .map(|(text, warning)| Event::Navigation { text, warning })
            .collect();
        failsafe_events.extend(self.commander.check_navigation(self.nav.validity(), &x, t_s));
        let n = self.motors.rotor_count();
        let changes = self.motors.update(
            &self.motor_params,
            esc.failed_rotors(),
            &self.rotor_thrust[..n],
            t_s,
            &mut self.core,
        );
        for change in changes {
            match change {
                MotorChange::Failed(loss) => failsafe_events.extend(self.commander.rotor_failed(loss, &x, t_s)),
                MotorChange::Working(rotor) => {
                    failsafe_events.push(Event::Failsafe(
                        FailsafeCause::Other,
                        format!("Motor {rotor} working again"),
                    ));
                }
            }
        }
        failsafe_events.extend(self.commander.check_failsafes(&x, esc.power_w(), self.dt_s, t_s));
        let mut tick = self.commander.update(&x, self.thrust_over_weight, t_s);
        if self.commander.armed() {
            self.nav.armed();
        }
        if !failsafe_events.is_empty() {
            tick.events.splice(0..0, failsafe_events);
        }
        // The position loop's reach (PX4's P gains over the velocity limits): a reference the
        // vehicle was left far behind, or an estimate that jumped, is flown at the speed limits.
        if let Some(sp) = tick.setpoint.as_mut() {
            let motion = &self.commander.params.motion;
            sp.pos_w = sp.pos_w.map(|p| motion.within_reach(p, x.pos_w));
        }
        let step = match (tick.setpoint, tick.attitude) {
            (Some(sp), _) => Some(self.core.step(&x, &sp)),
            (None, Some(target)) => Some(self.core.step_attitude(&x, &target)),
            (None, None) => None,
        };
        // The collective thrust the controller asks for, as PX4's land detector reads its thrust
        // setpoint: on the ground, torques against an attitude the contact holds can keep the
        // applied thrust up while the controller asks for none.
        self.thrust_over_weight = step.map_or(0.0, |s| {
            s.control.wrench.thrust_n / (self.believed_mass_kg * GRAVITY_M_S2)
        });
        let full_sq = self.rotor_max_rad_s.powi(2);
        self.rotor_thrust = [0.0; MAX_ROTORS];
        if let Some(s) = &step {
            for (u, w2) in self.rotor_thrust.iter_mut().zip(s.allocation.omega_sq()) {
                *u = w2 / full_sq;
            }
        }
        Control {
            state: x,
            rotors: n,
            step,
            setpoint: tick.setpoint,
            events: tick.events,
        }
    }

    /// The telemetry snapshot of the tick.
    fn report(
        &self,
        t_s: f64,
        sensors: &Sensors,
        control: &Control,
        motor_speeds: &[f64],
        truth: impl FnOnce() -> PlantTruth,
    ) -> Snapshot {
        self.snapshot(t_s, sensors, control, motor_speeds, &truth())
    }

    fn params(&self) -> Option<&ParamTable> {
        Some(&self.params)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::airframe::AirframeSource;

    fn controller() -> FlightController {
        let af = Airframe::from_source(&AirframeSource::resolve("quad_x").unwrap()).unwrap();
        FlightController::new(&af, ControllerKind::Geometric, Home::default(), 1e-3).unwrap()
    }

    #[test]
    fn replies_say_what_the_plant_must_change() {
        let mut fc = controller();
        let inject = |rotor| Request::InjectRotorFailure { rotor, failed: true };
        assert!(fc.set_param("SYS_FAILURE_EN", 0.0).answer.is_ok());
        let denied = fc.request(inject(2), 0.0);
        assert!(matches!(&denied.answer, Outcome::Denied(why) if why.contains("SYS_FAILURE_EN")));
        assert_eq!(denied.plant, None);
        let set = fc.set_param("SYS_FAILURE_EN", 1.0);
        assert!(set.answer.is_ok());
        assert_eq!(
            set.plant,
            Some(PlantChange::ProximityEffects {
                ground: true,
                ceiling: true
            })
        );
        let wind = fc.set_param("SIH_WIND_E", 4.0);
        assert_eq!(
            wind.plant,
            Some(PlantChange::Wind(crate::params::WindParams {
                east_m_s: 4.0,
                ..Default::default()
            }))
        );
        let refused = fc.set_param("NO_SUCH_PARAM", 1.0);
        assert!(refused.answer.is_err() && refused.plant.is_none());
        let accepted = fc.request(inject(2), 0.0);
        assert_eq!(accepted.answer, Outcome::Accepted);
        assert_eq!(
            accepted.plant,
            Some(PlantChange::Rotors {
                rotors: 1..2,
                failed: true
            })
        );
        let none = fc.request(inject(5), 0.0);
        assert!(matches!(&none.answer, Outcome::Denied(why) if why == "Failure injection: no motor 5 (1 to 4)"));
    }

    #[test]
    fn commander_requests_see_the_state_of_the_latest_tick() {
        let mut fc = controller();
        // Before the first tick: at rest at the origin.
        assert_eq!(
            fc.request(Request::Arm { force: false }, 0.0),
            Reply::only(Outcome::Accepted)
        );
        assert!(fc.commander().armed());
        assert_eq!(fc.commander().home_w(), Vec3::zeros());
    }
}
