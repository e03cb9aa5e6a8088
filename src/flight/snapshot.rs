//! The telemetry [`Snapshot`] of one tick: the one place it is built from the flight
//! controller's state (before the first tick, [`Snapshot::initial`] stands in). Pure.

use crate::airframe::MAX_ROTORS;
use crate::math::euler_zyx;
use crate::sitl::{PlantTruth, Sensors};
use crate::telemetry::{BatterySnapshot, Snapshot};

use super::{Control, FlightController};

impl FlightController {
    /// What the links publish after a tick at simulated time `t_s` [s]: the sensed state,
    /// commander state, the controller step of `control` (and the motor outputs it commands,
    /// with the motors the flight controller stops), the true rotor speeds `motor_speeds`
    /// [rad/s] and the plant's `truth` after the plant step (telemetry only).
    pub fn snapshot(
        &self,
        t_s: f64,
        sensors: &Sensors,
        control: &Control,
        motor_speeds: &[f64],
        truth: &PlantTruth,
    ) -> Snapshot {
        let x = &control.state;
        let commander = self.commander();
        let step = control.step.as_ref();
        let mut rotor_speeds = [0.0; MAX_ROTORS];
        for (slot, w) in rotor_speeds.iter_mut().zip(motor_speeds) {
            *slot = *w;
        }
        let mut rotor_commands = [0.0; MAX_ROTORS];
        for (slot, w) in rotor_commands.iter_mut().zip(control.rotor_speeds().as_slice()) {
            *slot = *w;
        }
        let (gauge, pack) = commander.battery();
        Snapshot {
            t_s,
            pos_w: x.pos_w,
            vel_w: x.vel_w,
            eta: euler_zyx(&x.r_wb),
            omega_b: x.omega_b,
            accel_b: sensors.accel_b,
            estimate: step.and_then(|s| s.estimate),
            setpoint: control.setpoint,
            eta_desired: step.map(|s| s.control.eta_desired),
            thrust_fraction: step.map_or(0.0, |s| {
                s.allocation.applied.thrust_n / self.core().allocator().thrust_max_n()
            }),
            rotor_speeds,
            rotor_commands,
            rotors_stopped: if step.is_some() {
                self.motors_stopped()
            } else {
                u32::MAX
            },
            rotor_count: self.rotor_count(),
            rotor_max_rad_s: self.rotor_max_rad_s(),
            battery: BatterySnapshot {
                fraction: gauge.fraction(&pack),
                cell_v: gauge.cell_voltage_v(&pack),
                cells: pack.cells,
                current_a: gauge.current_a(&pack),
                consumed_mah: gauge.consumed_mah(&pack),
                energy_j: gauge.used_j(),
            },
            nav: self.state_source().snapshot(t_s, self.commander().navigation_armable()),
            truth: Some(*truth),
            ..Snapshot::initial(self.home())
        }
        .with_commander(commander)
    }
}
