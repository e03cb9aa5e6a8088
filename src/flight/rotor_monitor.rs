//! What the flight controller knows of its rotors (issue 6): it notices failed rotors in the ESC
//! report, re-allocates around them and lets the commander react
//! ([`Commander::rotor_failed`]); and it turns a failure-injection request
//! (MAV_CMD_INJECT_FAILURE) into the [`PlantChange`] the simulated hardware must carry out.
//! Pure.

use crate::commander::{Commander, Event};
use crate::control::VehicleState;
use crate::sitl::PlantChange;

use super::FlightCore;

/// The rotors the flight controller last saw failed.
#[derive(Debug, Clone, Default)]
pub struct RotorMonitor {
    known: Vec<bool>,
}

impl RotorMonitor {
    /// `rotors` working rotors.
    pub fn new(rotors: usize) -> Self {
        Self {
            known: vec![false; rotors],
        }
    }

    /// Rotor count.
    pub fn rotor_count(&self) -> usize {
        self.known.len()
    }

    /// The plant change that stops (`failed`) or restores rotor `rotor` (1-based; 0 = every
    /// rotor), or why there is none.
    pub fn injection(&self, rotor: usize, failed: bool) -> Result<PlantChange, String> {
        let n = self.known.len();
        let rotors = match rotor {
            0 => 0..n,
            r if r <= n => r - 1..r,
            r => return Err(format!("Failure injection: no motor {r} (1 to {n})")),
        };
        Ok(PlantChange::Rotors { rotors, failed })
    }

    /// At simulated time `t_s` [s], with the ESCs reporting `reported`: when the report changed,
    /// re-allocates and lets the commander react; returns the announcements.
    pub fn check(
        &mut self,
        reported: &[bool],
        t_s: f64,
        x: &VehicleState,
        core: &mut FlightCore,
        commander: &mut Commander,
    ) -> Vec<Event> {
        // Nothing to allocate on the 1 kHz path unless the ESC report changed.
        if reported == self.known.as_slice() {
            return Vec::new();
        }
        let control = core.set_failed_rotors(reported).ok();
        let mut events = Vec::new();
        for (i, (now, before)) in reported.iter().zip(&self.known).enumerate() {
            match (now, before) {
                (true, false) => events.extend(commander.rotor_failed(i + 1, control, x, t_s)),
                (false, true) => events.push(Event::Failsafe(format!("Motor {} working again", i + 1))),
                _ => {}
            }
        }
        self.known = reported.to_vec();
        events
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn injection_names_the_rotors_or_why_not() {
        let m = RotorMonitor::new(4);
        assert_eq!(
            m.injection(2, true),
            Ok(PlantChange::Rotors {
                rotors: 1..2,
                failed: true
            })
        );
        assert_eq!(
            m.injection(0, false),
            Ok(PlantChange::Rotors {
                rotors: 0..4,
                failed: false
            })
        );
        assert_eq!(
            m.injection(5, true),
            Err("Failure injection: no motor 5 (1 to 4)".to_string())
        );
    }
}
