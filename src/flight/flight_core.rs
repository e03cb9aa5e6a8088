//! One flight-controller tick (docs/architecture.md §4, docs/estimator.md §6): estimation →
//! control → allocation → estimation, as plain values in and out. The runtime decides when to
//! call it.
//!
//! ```text
//! ŵ_k   = observer.observe(q_k)            uses β_{k−1} (docs/estimator.md §4)
//! out_k = controller.update(x_k, sp_k, ŵ_k)
//! alloc = allocator.allocate(out_k.wrench) min-norm + saturation (docs/allocation.md §4)
//! observer.apply(alloc.applied)            β_k from the applied wrench, kept for tick k+1
//! ```

use thiserror::Error;

use crate::airframe::Airframe;
use crate::allocation::{Airmode, Allocation, AllocationError, Allocator, FailedRotors};
use crate::control::{
    AttitudeTarget, ControlInput, ControlOutput, Controller, ControllerError, ControllerGains, ControllerKind,
    FlatSetpoint, VehicleModel, VehicleState,
};
use crate::math::{euler_zyx, Vec3};
use crate::rpy;
use crate::wrench_estimator::{WrenchEstimate, WrenchObserver};

/// |cos θ| below which the estimator holds (RPY singularity of its momentum model) [-].
const ESTIMATOR_COS_THETA_MIN: f64 = 1e-3;

/// A flight core that cannot be built for an airframe.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum CoreError {
    /// The allocation cannot serve the airframe.
    #[error("{origin}: rotors: {source}")]
    Allocation {
        /// Airframe name.
        origin: String,
        /// Cause.
        source: AllocationError,
    },
    /// The controller refused its configuration.
    #[error(transparent)]
    Controller(#[from] ControllerError),
}

/// The controller's model of an airframe: believed mass and inertia, and full thrust.
pub fn vehicle_model(airframe: &Airframe, allocator: &Allocator) -> VehicleModel {
    VehicleModel {
        mass_kg: airframe.mass_kg,
        inertia_kg_m2: airframe.inertia_kg_m2,
        thrust_max_n: allocator.thrust_max_n(),
    }
}

/// Everything one tick produced.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoreStep {
    /// Controller output (requested wrench, desired attitude, errors, flags).
    pub control: ControlOutput,
    /// Rotor commands and the wrench they apply.
    pub allocation: Allocation,
    /// Estimator output of this tick, when the estimator runs.
    pub estimate: Option<WrenchEstimate>,
}

/// Controller, allocator and (optionally) the wrench estimator of one vehicle.
#[derive(Debug, Clone)]
pub struct FlightCore {
    /// The active control law.
    pub controller: Controller,
    allocator: Allocator,
    /// The allocator with every rotor working (rotor failures are applied to it).
    nominal: Allocator,
    observer: Option<WrenchObserver>,
}

impl FlightCore {
    /// Core with an optional estimator (compensation is a controller setting).
    pub fn new(controller: Controller, allocator: Allocator, observer: Option<WrenchObserver>) -> Self {
        Self {
            controller,
            nominal: allocator.clone(),
            allocator,
            observer,
        }
    }

    /// Core for `airframe` running `kind` with the homework gains scaled to the airframe
    /// ([`ControllerGains::for_vehicle`]), compensation off and no estimator, at `ts_s` [s].
    pub fn for_airframe(airframe: &Airframe, kind: ControllerKind, ts_s: f64) -> Result<Self, CoreError> {
        let allocator = Allocator::new(airframe).map_err(|source| CoreError::Allocation {
            origin: airframe.name.clone(),
            source,
        })?;
        let model = vehicle_model(airframe, &allocator);
        let controller = Controller::new(kind, model, ControllerGains::for_vehicle(&model), ts_s)?;
        Ok(Self::new(controller, allocator, None))
    }

    /// The allocator.
    pub fn allocator(&self) -> &Allocator {
        &self.allocator
    }

    /// Sets the allocation's saturation policy, for the nominal allocator and the one in force
    /// (docs/allocation.md §4).
    pub fn set_airmode(&mut self, airmode: Airmode) {
        self.nominal = self.nominal.clone().with_airmode(airmode);
        self.allocator = self.allocator.clone().with_airmode(airmode);
    }

    /// Allocates around the rotors marked in `failed` from now on (all `false`: the nominal
    /// allocator again); what can still be controlled, or why nothing can (the allocator is
    /// then left as it was).
    pub fn set_failed_rotors(&mut self, failed: &[bool]) -> Result<FailedRotors, AllocationError> {
        if !failed.iter().any(|f| *f) {
            self.allocator = self.nominal.clone();
            return Ok(FailedRotors::FullControl);
        }
        let (allocator, mode) = self.nominal.with_failed_rotors(failed)?;
        self.allocator = allocator;
        Ok(mode)
    }

    /// The rotor mounted opposite rotor `i` (0-based) that turns the other way, if any
    /// ([`Allocator::counter_rotating_opposite`] of the allocator with every rotor working).
    pub fn counter_rotating_opposite(&self, i: usize) -> Option<usize> {
        self.nominal.counter_rotating_opposite(i)
    }

    /// Replaces (or removes) the estimator; a new one starts from ŵ = 0.
    pub fn set_observer(&mut self, observer: Option<WrenchObserver>) {
        self.observer = observer;
    }

    /// One tick for state `x` and setpoint `sp`.
    pub fn step(&mut self, x: &VehicleState, sp: &FlatSetpoint) -> CoreStep {
        let estimate = self.observe(x);
        let control = self.controller.update(&ControlInput {
            state: x,
            setpoint: sp,
            estimate,
        });
        self.allocate(control, estimate)
    }

    /// One tick of direct attitude / rate control (offboard SET_ATTITUDE_TARGET).
    pub fn step_attitude(&mut self, x: &VehicleState, target: &AttitudeTarget) -> CoreStep {
        let estimate = self.observe(x);
        let control = self.controller.update_attitude(x, target);
        self.allocate(control, estimate)
    }

    /// ŵ_k from this tick's momentum and β_{k−1}.
    fn observe(&mut self, x: &VehicleState) -> Option<WrenchEstimate> {
        self.observer.as_mut().map(|obs| {
            let eta = euler_zyx(&x.r_wb);
            match rpy::q_inverse(&eta, ESTIMATOR_COS_THETA_MIN) {
                Some(q_inv) => obs.observe(&x.vel_w, &eta, &(q_inv * x.omega_b)),
                None => obs.observe(&x.vel_w, &eta, &Vec3::repeat(f64::NAN)),
            }
        })
    }

    /// Allocation of the controller's wrench, and β_k from the applied one.
    fn allocate(&mut self, control: ControlOutput, estimate: Option<WrenchEstimate>) -> CoreStep {
        let allocation = self.allocator.allocate(&control.wrench);
        if let Some(obs) = self.observer.as_mut() {
            obs.apply(allocation.applied.thrust_n, &allocation.applied.torque_b);
        }
        CoreStep {
            control,
            allocation,
            estimate,
        }
    }
}
