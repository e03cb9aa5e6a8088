//! One simulated vehicle: commander + flight core + plant, stepped in lockstep at a fixed dt.
//! Simulated time is `tick × dt`; nothing here reads a clock.

use crate::airframe::{Airframe, AirframeSource, MAX_ROTORS};
use crate::commander::{Commander, CommanderParams, Event, Outcome, Request};
use crate::control::ControllerKind;
use crate::core::{CoreError, FlightCore};
use crate::estimation::{ChebyshevDesign, WrenchObserver};
use crate::math::euler_zyx;
use crate::navigation::Home;
use crate::params::{ParamError, ParamTable, VehicleSettings};
use crate::sitl::{SimPlant, SitlError};
use crate::telemetry::{BatterySnapshot, EstimateSnapshot, Snapshot};

use super::flight_log::{LogSender, TickLog};
use super::rotor_failures::{RotorFailures, ScheduledFailure};

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

/// A vehicle that cannot be built.
#[derive(Debug, thiserror::Error)]
pub enum VehicleError {
    /// The FC refused the airframe.
    #[error(transparent)]
    Airframe(#[from] crate::airframe::AirframeError),
    /// The flight core cannot be built.
    #[error(transparent)]
    Core(#[from] CoreError),
    /// The plant refused the airframe.
    #[error(transparent)]
    Plant(#[from] SitlError),
}

/// Commander, flight core and plant of one vehicle.
#[derive(Debug)]
pub struct Vehicle {
    core: FlightCore,
    plant: SimPlant,
    commander: Commander,
    home: Home,
    tick: u64,
    dt_s: f64,
    idle: Vec<f64>,
    params: ParamTable,
    log: Option<LogSender>,
    believed_mass_kg: f64,
    rotor_max_rad_s: f64,
    believed_inertia_kg_m2: crate::math::Vec3,
    rotor_failures: RotorFailures,
    /// Collective thrust of the last tick over the believed weight [-] (land detector input).
    thrust_over_weight: f64,
}

/// What one tick produced for the links.
#[derive(Debug, Clone, PartialEq)]
pub struct TickOutput {
    /// Latest state.
    pub snapshot: Snapshot,
    /// What the commander did on its own.
    pub events: Vec<Event>,
}

impl Vehicle {
    /// Vehicle of airframe `src` flown by `kind`, home `home`, sensor seed `seed`, step `dt_s` [s].
    pub fn new(
        src: &AirframeSource,
        kind: ControllerKind,
        home: Home,
        seed: u64,
        dt_s: f64,
    ) -> Result<Self, VehicleError> {
        let airframe = Airframe::from_source(src)?;
        let mut core = FlightCore::for_airframe(&airframe, kind, dt_s)?;
        let mut gains = *core.controller.gains();
        gains.limits.tilt_max_rad = AUTOPILOT_TILT_MAX_DEG.to_radians();
        core.controller.set_gains(gains).map_err(CoreError::from)?;
        let plant = SimPlant::from_source(src, seed)?;
        for w in plant.warnings() {
            tracing::warn!("{w}");
        }
        let idle = vec![0.0; core.allocator().rotor_count()];
        let params = ParamTable::new(&VehicleSettings::new(kind, gains, Some(DEFAULT_ESTIMATOR)));
        let mut vehicle = Self {
            core,
            plant,
            commander: Commander::new(CommanderParams::default()),
            home,
            tick: 0,
            dt_s,
            idle,
            params,
            log: None,
            believed_mass_kg: airframe.mass_kg,
            rotor_max_rad_s: airframe.omega_max_rad_s,
            believed_inertia_kg_m2: airframe.inertia_kg_m2,
            rotor_failures: RotorFailures::new(airframe.rotors.len()),
            thrust_over_weight: 0.0,
        };
        vehicle.install_observer(Some(DEFAULT_ESTIMATOR));
        Ok(vehicle)
    }

    /// Replaces the wrench observer by one of `design` (none when `None` or not realisable).
    fn install_observer(&mut self, design: Option<ChebyshevDesign>) {
        let observer = design.and_then(|d| {
            let gains = d.gains(self.dt_s).ok()?;
            WrenchObserver::new(self.believed_mass_kg, self.believed_inertia_kg_m2, gains, self.dt_s).ok()
        });
        self.core.set_observer(observer);
    }

    /// Sends every tick to `log` (`run.csv` of `--log DIR`).
    pub fn set_log(&mut self, log: LogSender) {
        self.log = Some(log);
    }

    /// The parameter table.
    pub fn params(&self) -> &ParamTable {
        &self.params
    }

    /// Sets parameter `name` to `value` and applies the new settings at this tick boundary:
    /// commander limits, control law (its filters restart from the next sample), compensation,
    /// gains, and the estimator (a new design restarts it from ŵ = 0). Refused sets change nothing.
    pub fn set_param(&mut self, name: &str, value: f64) -> Result<usize, ParamError> {
        let before = self.params.settings();
        let index = self.params.set(name, value, self.dt_s)?;
        let s = self.params.settings();
        self.commander.params = s.commander;
        self.core.controller.set_kind(s.controller);
        self.core.controller.set_compensation(s.compensation);
        if let Err(e) = self.core.controller.set_gains(s.gains) {
            tracing::warn!("{e}");
        }
        self.plant.set_proximity_effects(s.ground_effect, s.ceiling_effect);
        if s.estimator != before.estimator {
            self.install_observer(s.estimator);
        }
        Ok(index)
    }

    /// Rotor count.
    pub fn rotor_count(&self) -> usize {
        self.idle.len()
    }

    /// Simulated time [s].
    pub fn time_s(&self) -> f64 {
        self.tick as f64 * self.dt_s
    }

    /// Applies a ground-station request at the current tick boundary: failure injection goes
    /// to the plant (when `SYS_FAILURE_EN` allows it), everything else to the commander.
    pub fn apply(&mut self, request: Request) -> Outcome {
        if let Request::InjectRotorFailure { rotor, failed } = request {
            if !self.commander.params.failure_injection {
                return Outcome::Denied("Failure injection disabled (SYS_FAILURE_EN = 0)".into());
            }
            return match RotorFailures::inject(&mut self.plant, rotor, failed) {
                Ok(()) => Outcome::Accepted,
                Err(why) => Outcome::Denied(why),
            };
        }
        let x = self.plant.sense();
        self.commander.request(request, &x, self.time_s())
    }

    /// Stops a rotor at a simulated time (`--fail-rotor`).
    pub fn schedule_rotor_failure(&mut self, failure: ScheduledFailure) -> Result<(), String> {
        self.rotor_failures.schedule(failure)
    }

    /// Keeps the offboard setpoint fresh at this tick (the stream is alive in wall time).
    pub fn refresh_offboard(&mut self) {
        let t_s = self.time_s();
        self.commander.refresh_offboard(t_s);
    }

    /// The parameter settings that the runtime's own timers read (`COM_OF_LOSS_T`, …).
    pub fn offboard_loss_s(&self) -> f64 {
        self.commander.params.offboard_loss_s
    }

    /// One tick: sense → commander → flight core → plant.
    pub fn step(&mut self) -> TickOutput {
        let t_s = self.time_s();
        let x = self.plant.sense();
        let power_w = self.plant.electrical_power_w();
        let mut failsafe_events =
            self.rotor_failures
                .tick(t_s, &x, &mut self.plant, &mut self.core, &mut self.commander);
        failsafe_events.extend(self.commander.check_failsafes(&x, power_w, self.dt_s, t_s));
        let mut tick = self.commander.update(&x, self.thrust_over_weight, t_s);
        if !failsafe_events.is_empty() {
            tick.events.splice(0..0, failsafe_events);
        }
        let step = match (tick.setpoint, tick.attitude) {
            (Some(sp), _) => Some(self.core.step(&x, &sp)),
            (None, Some(target)) => Some(self.core.step_attitude(&x, &target)),
            (None, None) => None,
        };
        match &step {
            Some(out) => self.plant.step(out.allocation.omega().as_slice(), self.dt_s),
            None => self.plant.step(&self.idle, self.dt_s),
        };
        self.thrust_over_weight = step.map_or(0.0, |s| {
            s.allocation.applied.thrust_n / (self.believed_mass_kg * crate::math::GRAVITY_M_S2)
        });
        let estimate = step.and_then(|s| s.estimate).map(|e| EstimateSnapshot {
            force_w: e.force_w,
            torque_b: e.torque_b,
            mass_kg: e.mass_kg,
        });
        if let Some(log) = &self.log {
            let truth = self.plant.truth();
            log.tick(TickLog {
                t_s,
                state: x,
                ref_w: tick.setpoint.and_then(|sp| sp.pos_w).unwrap_or(x.pos_w),
                step,
                motor_speeds: self.plant.motor_speeds().to_vec(),
                true_force_w: truth.external_force_w,
                true_torque_b: truth.external_torque_b,
            });
        }
        self.tick += 1;
        let eta = euler_zyx(&x.r_wb);
        let progress = self.commander.mission_progress();
        let mut rotor_speeds = [0.0; MAX_ROTORS];
        for (slot, w) in rotor_speeds.iter_mut().zip(self.plant.motor_speeds()) {
            *slot = *w;
        }
        TickOutput {
            snapshot: Snapshot {
                t_s,
                pos_w: x.pos_w,
                vel_w: x.vel_w,
                eta,
                omega_b: x.omega_b,
                accel_b: self.plant.accel_b(),
                armed: self.commander.armed(),
                mode: self.commander.mode(),
                landed: self.commander.landed_state(),
                home: self.home,
                home_w: self.commander.home_w(),
                geofence_breached: self.commander.geofence_breached(),
                mission_seq: progress.0 as u16,
                mission_total: progress.1 as u16,
                mission_state: progress.2,
                estimate,
                setpoint: tick.setpoint,
                eta_desired: step.map(|s| s.control.eta_desired),
                thrust_fraction: step.map_or(0.0, |s| {
                    s.allocation.applied.thrust_n / self.core.allocator().thrust_max_n()
                }),
                rotor_speeds,
                rotor_count: self.idle.len(),
                rotor_max_rad_s: self.rotor_max_rad_s,
                battery: {
                    let (gauge, pack) = self.commander.battery();
                    BatterySnapshot {
                        fraction: gauge.fraction(&pack),
                        cell_v: gauge.cell_voltage_v(&pack),
                        cells: pack.cells,
                        current_a: gauge.current_a(&pack),
                        consumed_mah: gauge.consumed_mah(&pack),
                        energy_j: gauge.used_j(),
                    }
                },
            },
            events: tick.events,
        }
    }
}
