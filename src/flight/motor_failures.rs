//! What the flight controller knows and does about failed motors, as PX4's failure detector,
//! failure injection and control allocator do it:
//!
//! - failure injection (MAV_CMD_INJECT_FAILURE, motor off / ok) stops the motor (the simulated
//!   hardware carries it out as a [`PlantChange`]); with `SYS_FAIL_MOT_OFF` 0 (a soft failure,
//!   PX4's default) the motor is also reported failed, with 1 (a hard failure) it is only
//!   stopped and nothing is told;
//! - the ESC check (`FD_ACT_EN`) reports a motor the ESCs show stopped while the flight
//!   controller commands it at least `FD_ACT_MOT_THR` of full thrust, for `FD_ACT_MOT_TOUT`;
//!   a motor the flight controller stops itself is never suspected;
//! - with `CA_FAILURE_MODE` 1 the allocation leaves out the first reported failure and, where
//!   the motor opposite it turns the other way and the vehicle stays controllable without both,
//!   that one too (PX4's "opposite motor" of symmetric frames: a hexacopter with alternating
//!   spins then hovers without yaw torque instead of spinning; a quadrotor's or an
//!   octocopter's opposite motor turns the same way and keeps running); only the first failure
//!   is handled, and the allocation is restored once no failure is reported.
//!
//! The motors the flight controller stops (injected or left out) are what its outputs show
//! stopped. Pure: values in (ESC report, thrust commands, time), changes out.

use crate::airframe::MAX_ROTORS;
use crate::commander::{LossAllocation, RotorLoss};
use crate::sitl::PlantChange;

use super::FlightCore;

/// How motor failures are detected and handled (PX4 parameter names and defaults in brackets).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotorFailureParams {
    /// The ESC check runs (`FD_ACT_EN`, 1).
    pub detect: bool,
    /// Thrust command, as a fraction of full thrust, above which a motor the ESCs show stopped is
    /// suspected [-] (`FD_ACT_MOT_THR`, 0.2).
    pub detect_thrust: f64,
    /// How long a motor stays suspected before it is reported failed [s] (`FD_ACT_MOT_TOUT`,
    /// 100 ms).
    pub detect_time_s: f64,
    /// The allocation leaves the first failed motor (and its counter-rotating opposite) out
    /// (`CA_FAILURE_MODE` 1; PX4's firmware default is 0, this flight controller always
    /// re-allocated around failed rotors and keeps doing so).
    pub reallocate: bool,
    /// Injected motor failures are hard: the motor stops, nothing is reported
    /// (`SYS_FAIL_MOT_OFF`, 0).
    pub hard_injection: bool,
}

impl Default for MotorFailureParams {
    fn default() -> Self {
        Self {
            detect: true,
            detect_thrust: 0.2,
            detect_time_s: 0.1,
            reallocate: true,
            hard_injection: false,
        }
    }
}

/// A change of the reported motor failures.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MotorChange {
    /// A motor failed.
    Failed(RotorLoss),
    /// A motor reported failed works again (1-based).
    Working(usize),
}

/// Injected, detected, reported and left-out motors of one vehicle (bit i: motor i + 1).
#[derive(Debug, Clone)]
pub struct MotorFailures {
    n: usize,
    injected: u32,
    detected: u32,
    suspected_since_s: [Option<f64>; MAX_ROTORS],
    /// The reported failure the allocation works around (one motor, or none).
    handled: u32,
    /// The motors the allocation leaves out (the handled one and its opposite).
    removed: u32,
    /// What the last update reported.
    reported: u32,
}

fn bit(i: usize) -> u32 {
    1 << i
}

impl MotorFailures {
    /// `rotors` working motors (at most [`MAX_ROTORS`]).
    pub fn new(rotors: usize) -> Self {
        Self {
            n: rotors.min(MAX_ROTORS),
            injected: 0,
            detected: 0,
            suspected_since_s: [None; MAX_ROTORS],
            handled: 0,
            removed: 0,
            reported: 0,
        }
    }

    /// Motor count.
    pub fn rotor_count(&self) -> usize {
        self.n
    }

    /// Failure injection: stops (`failed`) or restores motor `rotor` (1-based; 0 = every
    /// motor); the change the simulated hardware must carry out, or why there is none.
    pub fn inject(&mut self, rotor: usize, failed: bool) -> Result<PlantChange, String> {
        let n = self.n;
        let rotors = match rotor {
            0 => 0..n,
            r if r <= n => r - 1..r,
            r => return Err(format!("Failure injection: no motor {r} (1 to {n})")),
        };
        for i in rotors.clone() {
            if failed {
                self.injected |= bit(i);
            } else {
                self.injected &= !bit(i);
            }
        }
        Ok(PlantChange::Rotors { rotors, failed })
    }

    /// The motors the flight controller stops (bit i: motor i + 1): injected, or left out of
    /// the allocation.
    pub fn stopped(&self) -> u32 {
        self.injected | self.removed
    }

    /// The motors reported failed at the last update (bit i: motor i + 1).
    pub fn reported(&self) -> u32 {
        self.reported
    }

    /// One tick at `t_s` [s]: the ESCs report `esc_failed`, the last tick commanded `thrust`
    /// (fraction of full thrust per motor). Detects, re-allocates `core` when the handled
    /// failure changes (`p`), and returns the motors that failed or work again since the last
    /// update, in motor order.
    pub fn update(
        &mut self,
        p: &MotorFailureParams,
        esc_failed: &[bool],
        thrust: &[f64],
        t_s: f64,
        core: &mut FlightCore,
    ) -> Vec<MotorChange> {
        self.detect(p, esc_failed, thrust, t_s);
        let injected_reported = if p.hard_injection { 0 } else { self.injected };
        let reported = (self.detected | injected_reported) & self.mask();
        let handled_now = self.allocate(p, reported, core);
        let mut changes = Vec::new();
        for i in 0..self.n {
            let (now, before) = (reported & bit(i) != 0, self.reported & bit(i) != 0);
            if now && !before {
                let (also_off, allocation) = match handled_now {
                    Some((handled, opposite, allocation)) if handled == i => (opposite, allocation),
                    _ => (None, LossAllocation::Unchanged),
                };
                changes.push(MotorChange::Failed(RotorLoss {
                    rotor: i + 1,
                    also_off: also_off.map(|o| o + 1),
                    allocation,
                }));
            } else if before && !now {
                changes.push(MotorChange::Working(i + 1));
            }
        }
        self.reported = reported;
        changes
    }

    fn mask(&self) -> u32 {
        u32::MAX >> (32 - self.n.max(1))
    }

    /// The ESC check: a motor the ESCs show stopped while commanded to run is suspected, and
    /// reported after `detect_time_s`; it is cleared when the ESCs show it running again.
    fn detect(&mut self, p: &MotorFailureParams, esc_failed: &[bool], thrust: &[f64], t_s: f64) {
        if !p.detect {
            self.detected = 0;
            self.suspected_since_s = [None; MAX_ROTORS];
            return;
        }
        let stopped = self.stopped();
        for i in 0..self.n {
            let failed = esc_failed.get(i).copied().unwrap_or(false);
            if !failed {
                self.detected &= !bit(i);
                self.suspected_since_s[i] = None;
                continue;
            }
            let commanded = stopped & bit(i) == 0 && thrust.get(i).is_some_and(|u| *u >= p.detect_thrust);
            match self.suspected_since_s[i] {
                _ if self.detected & bit(i) != 0 => {}
                Some(since) if t_s - since >= p.detect_time_s - 1e-9 => self.detected |= bit(i),
                Some(_) if !commanded => self.suspected_since_s[i] = None,
                None if commanded => self.suspected_since_s[i] = Some(t_s),
                _ => {}
            }
        }
    }

    /// `CA_FAILURE_MODE`: leaves out the first reported failure (and its opposite) or restores
    /// the allocation once nothing is reported; the motor handled now (0-based), the opposite
    /// left out with it and what the allocation can do, when it changed.
    fn allocate(
        &mut self,
        p: &MotorFailureParams,
        reported: u32,
        core: &mut FlightCore,
    ) -> Option<(usize, Option<usize>, LossAllocation)> {
        if self.handled != 0 && (!p.reallocate || reported == 0) {
            let nominal = vec![false; self.n];
            let _ = core.set_failed_rotors(&nominal);
            self.handled = 0;
            self.removed = 0;
        }
        if !p.reallocate || self.handled != 0 || reported.count_ones() != 1 {
            return None;
        }
        let i = reported.trailing_zeros() as usize;
        self.handled = bit(i);
        let without = |set: u32| (0..self.n).map(|k| set & bit(k) != 0).collect::<Vec<bool>>();
        if let Some(o) = core.counter_rotating_opposite(i) {
            // Left out with its opposite (so as many rotors turn each way as before) where that
            // still holds roll and pitch.
            if let Ok(mode) = core.set_failed_rotors(&without(bit(i) | bit(o))) {
                self.removed = bit(i) | bit(o);
                return Some((i, Some(o), LossAllocation::Around(mode)));
            }
        }
        match core.set_failed_rotors(&without(bit(i))) {
            Ok(mode) => {
                self.removed = bit(i);
                Some((i, None, LossAllocation::Around(mode)))
            }
            Err(_) => Some((i, None, LossAllocation::Impossible)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::airframe::{Airframe, AirframeSource};
    use crate::allocation::FailedRotors;
    use crate::control::ControllerKind;

    fn core(preset: &str) -> FlightCore {
        let af = Airframe::from_source(&AirframeSource::resolve(preset).unwrap()).unwrap();
        FlightCore::for_airframe(&af, ControllerKind::Geometric, 1e-3).unwrap()
    }

    const HOVER: [f64; 8] = [0.4; 8];

    #[test]
    fn injection_names_the_motors_or_why_not() {
        let mut m = MotorFailures::new(4);
        assert_eq!(
            m.inject(2, true),
            Ok(PlantChange::Rotors {
                rotors: 1..2,
                failed: true
            })
        );
        assert_eq!(m.stopped(), 0b10);
        assert_eq!(
            m.inject(0, false),
            Ok(PlantChange::Rotors {
                rotors: 0..4,
                failed: false
            })
        );
        assert_eq!(m.stopped(), 0);
        assert_eq!(
            m.inject(5, true),
            Err("Failure injection: no motor 5 (1 to 4)".to_string())
        );
    }

    #[test]
    fn a_soft_failure_leaves_the_motor_and_its_opposite_out_until_it_is_restored() {
        let mut core = core("hexa_x");
        let p = MotorFailureParams::default();
        let mut m = MotorFailures::new(6);
        m.inject(1, true).unwrap();
        let failed = [true, false, false, false, false, false];
        let changes = m.update(&p, &failed, &HOVER, 1.0, &mut core);
        let yaw_lost = LossAllocation::Around(FailedRotors::YawUncontrolled);
        assert_eq!(
            changes,
            vec![MotorChange::Failed(RotorLoss {
                rotor: 1,
                also_off: Some(4),
                allocation: yaw_lost
            })]
        );
        assert_eq!(m.stopped(), 0b1001, "motor 1 and its opposite, motor 4");
        assert!(core.allocator().effectiveness().column(3).iter().all(|g| *g == 0.0));
        assert!(m.update(&p, &failed, &HOVER, 1.001, &mut core).is_empty(), "once");
        // A second failure is reported but not handled (PX4 handles the first one only).
        m.inject(4, true).unwrap();
        let second = m.update(&p, &failed, &HOVER, 1.002, &mut core);
        assert_eq!(
            second,
            vec![MotorChange::Failed(RotorLoss {
                rotor: 4,
                also_off: None,
                allocation: LossAllocation::Unchanged
            })]
        );
        m.inject(0, false).unwrap();
        let back = m.update(&p, &[false; 6], &HOVER, 1.003, &mut core);
        assert_eq!(back, vec![MotorChange::Working(1), MotorChange::Working(4)]);
        assert_eq!(m.stopped(), 0);
        assert!(
            core.allocator().effectiveness().column(3)[0] > 0.0,
            "allocation restored"
        );
    }

    #[test]
    fn a_hard_failure_only_stops_the_motor() {
        let mut core = core("hexa_x");
        let p = MotorFailureParams {
            hard_injection: true,
            ..Default::default()
        };
        let mut m = MotorFailures::new(6);
        m.inject(1, true).unwrap();
        let failed = [true, false, false, false, false, false];
        for k in 0..500 {
            assert!(m.update(&p, &failed, &HOVER, f64::from(k) * 1e-3, &mut core).is_empty());
        }
        assert_eq!((m.stopped(), m.reported()), (0b1, 0));
        assert!(
            core.allocator().effectiveness().column(0)[0] > 0.0,
            "allocation unchanged"
        );
    }

    #[test]
    fn the_esc_check_reports_a_stopped_motor_commanded_to_run_after_fd_act_mot_tout() {
        let mut core = core("octo");
        let p = MotorFailureParams::default();
        let mut m = MotorFailures::new(8);
        let mut failed = [false; 8];
        failed[2] = true;
        let idle = [0.1; 8];
        assert!(
            m.update(&p, &failed, &idle, 0.0, &mut core).is_empty(),
            "below FD_ACT_MOT_THR"
        );
        assert!(m.update(&p, &failed, &HOVER, 0.5, &mut core).is_empty(), "suspected");
        assert!(m.update(&p, &failed, &HOVER, 0.599, &mut core).is_empty());
        let changes = m.update(&p, &failed, &HOVER, 0.6, &mut core);
        assert_eq!(
            changes,
            vec![MotorChange::Failed(RotorLoss {
                rotor: 3,
                also_off: None,
                allocation: LossAllocation::Around(FailedRotors::FullControl)
            })]
        );
        let off = MotorFailureParams { detect: false, ..p };
        assert_eq!(
            m.update(&off, &failed, &HOVER, 0.7, &mut core),
            vec![MotorChange::Working(3)]
        );
        assert_eq!(m.stopped(), 0, "FD_ACT_EN 0: nothing detected, the allocation restored");
    }

    #[test]
    fn a_quadrotor_keeps_the_opposite_rotor_and_ca_failure_mode_0_changes_nothing() {
        let mut core = core("quad_x");
        let mut m = MotorFailures::new(4);
        m.inject(2, true).unwrap();
        let changes = m.update(&MotorFailureParams::default(), &[false; 4], &HOVER, 0.0, &mut core);
        assert_eq!(
            changes,
            vec![MotorChange::Failed(RotorLoss {
                rotor: 2,
                also_off: None,
                allocation: LossAllocation::Around(FailedRotors::YawUncontrolled)
            })]
        );
        let ignore = MotorFailureParams {
            reallocate: false,
            ..Default::default()
        };
        let mut m = MotorFailures::new(4);
        let mut core = self::core("quad_x");
        m.inject(2, true).unwrap();
        let changes = m.update(&ignore, &[false; 4], &HOVER, 0.0, &mut core);
        assert_eq!(
            changes,
            vec![MotorChange::Failed(RotorLoss {
                rotor: 2,
                also_off: None,
                allocation: LossAllocation::Unchanged
            })]
        );
        assert_eq!(m.stopped(), 0b10, "only the injected motor stops");
    }
}
