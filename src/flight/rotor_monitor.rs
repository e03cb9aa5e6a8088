//! What a bare control law knows of its rotors in `sim` and Monte Carlo runs: it notices failed
//! rotors in the ESC report and re-allocates around every one of them
//! ([`RotorMonitor::reallocate`]). The flight controller handles motor failures as PX4 does
//! instead (`motor_failures`). Pure.

use crate::allocation::FailedRotors;

use super::FlightCore;

/// The rotors a bare control law last saw failed.
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
