//! What a flight controller knows of its rotors: it notices failed rotors in the ESC report and
//! re-allocates around them ([`RotorMonitor::reallocate`], also for a bare control law in `sim`
//! and Monte Carlo runs), lets the commander react ([`Commander::rotor_failed`]), and turns a
//! failure-injection request (MAV_CMD_INJECT_FAILURE) into the [`PlantChange`] the simulated
//! hardware must carry out. Pure.

use crate::allocation::FailedRotors;
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

    /// When the ESC report `reported` differs from the last one: re-allocates `core` around the
    /// failed rotors and says what changed (`None`: nothing did).
    pub fn reallocate(&mut self, reported: &[bool], core: &mut FlightCore) -> Option<RotorChange> {
        // Nothing to allocate on the 1 kHz path unless the ESC report changed.
        if reported == self.known.as_slice() {
            return None;
        }
        let change = RotorChange {
            control: core.set_failed_rotors(reported).ok(),
            rotors: (reported.iter().zip(&self.known).enumerate())
                .filter(|(_, (now, before))| now != before)
                .map(|(i, (now, _))| (i + 1, *now))
                .collect(),
        };
        self.known = reported.to_vec();
        Some(change)
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
        let Some(change) = self.reallocate(reported, core) else {
            return Vec::new();
        };
        let mut events = Vec::new();
        for (rotor, failed) in change.rotors {
            if failed {
                events.extend(commander.rotor_failed(rotor, change.control, x, t_s));
            } else {
                events.push(Event::Failsafe(format!("Motor {rotor} working again")));
            }
        }
        events
    }
}

/// What changed in the ESC report and what the new allocation can still control.
#[derive(Debug, Clone, PartialEq)]
pub struct RotorChange {
    /// What the allocation controls now; `None`: no allocation is left (the last one stays).
    pub control: Option<FailedRotors>,
    /// Each rotor that changed (1-based) and whether it is failed now.
    pub rotors: Vec<(usize, bool)>,
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

    #[test]
    fn a_changed_esc_report_re_allocates_once_and_names_the_rotors() {
        use crate::airframe::{Airframe, AirframeSource};
        use crate::control::ControllerKind;
        let af = Airframe::from_source(&AirframeSource::resolve("hexa_x").unwrap()).unwrap();
        let mut core = FlightCore::for_airframe(&af, ControllerKind::Geometric, 1e-3).unwrap();
        let mut m = RotorMonitor::new(6);
        let mut report = [false; 6];
        assert_eq!(m.reallocate(&report, &mut core), None, "nothing changed");
        report[1] = true;
        let change = m.reallocate(&report, &mut core).unwrap();
        assert_eq!(change.rotors, vec![(2, true)]);
        assert!(change.control.is_some(), "a hexa keeps an allocation without rotor 2");
        assert!(core.allocator().effectiveness().column(1).iter().all(|g| *g == 0.0));
        assert_eq!(m.reallocate(&report, &mut core), None, "once per change");
        report[1] = false;
        let change = m.reallocate(&report, &mut core).unwrap();
        assert_eq!(change.rotors, vec![(2, false)]);
        assert_eq!(change.control, Some(FailedRotors::FullControl));
    }
}
