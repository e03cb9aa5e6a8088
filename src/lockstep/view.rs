//! One tick's values as the logs read them ([`TickView`]): what the plant sensed, what the pilot
//! commanded, the telemetry snapshot when the pilot is a flight controller, and the plant's truth
//! after the step. `run.csv` rows and ULog records are both written from it. Pure.

use crate::commander::Event;
use crate::control::{FlatSetpoint, VehicleState};
use crate::flight::CoreStep;
use crate::math::Vec3;
use crate::sitl::{PlantTruth, SimPlant};
use crate::telemetry::Snapshot;

use super::Tick;

/// A pilot report that may carry the telemetry snapshot (the flight controller's does; a bare
/// flight core reports nothing).
pub trait SnapshotReport {
    /// The snapshot, when the pilot publishes one.
    fn snapshot(&self) -> Option<&Snapshot>;
}

impl SnapshotReport for () {
    fn snapshot(&self) -> Option<&Snapshot> {
        None
    }
}

impl SnapshotReport for Snapshot {
    fn snapshot(&self) -> Option<&Snapshot> {
        Some(self)
    }
}

/// One tick's values, borrowed from the tick and the plant.
#[derive(Debug, Clone, Copy)]
pub struct TickView<'a> {
    /// Simulated time [s].
    pub t_s: f64,
    /// State the controller flew on (its navigation estimate).
    pub state: &'a VehicleState,
    /// Specific force the accelerometer sensed, body FRD [m/s²].
    pub accel_b: Vec3,
    /// Reference position [m].
    pub ref_w: Vec3,
    /// Setpoint flown, when one is.
    pub setpoint: Option<&'a FlatSetpoint>,
    /// The tick's outputs; `None` while the motors are off.
    pub step: Option<&'a CoreStep>,
    /// What the commander did on its own this tick.
    pub events: &'a [Event],
    /// The flight controller's telemetry snapshot (`None` for a bare flight core).
    pub snapshot: Option<&'a Snapshot>,
    /// True motor speeds [rad/s].
    pub motor_speeds: &'a [f64],
    /// The plant's exact state and wind after the step.
    pub truth: PlantTruth,
}

impl<'a> TickView<'a> {
    /// The view of lockstep tick `tick`, with the plant `plant` after its step.
    pub fn of<R: SnapshotReport>(tick: &'a Tick<R>, plant: &'a SimPlant) -> Self {
        Self {
            t_s: tick.t_s,
            state: &tick.control.state,
            accel_b: tick.sensors.accel_b,
            ref_w: tick.reference_w(),
            setpoint: tick.control.setpoint.as_ref(),
            step: tick.control.step.as_ref(),
            events: &tick.control.events,
            snapshot: tick.report.snapshot(),
            motor_speeds: plant.motor_speeds(),
            truth: plant.truth(),
        }
    }
}

#[cfg(test)]
impl<'a> TickView<'a> {
    /// A tick of a vehicle in `state` with the motors off and nothing else going on (tests).
    pub(crate) fn resting(state: &'a VehicleState) -> Self {
        Self {
            t_s: state.t_s,
            state,
            accel_b: Vec3::new(0.0, 0.0, -crate::math::GRAVITY_M_S2),
            ref_w: state.pos_w,
            setpoint: None,
            step: None,
            events: &[],
            snapshot: None,
            motor_speeds: &[],
            truth: PlantTruth::at_rest(state),
        }
    }
}
