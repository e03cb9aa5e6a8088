//! Rotor failures of one vehicle (issue 6): injected over MAVLink (MAV_CMD_INJECT_FAILURE) or
//! scheduled at a simulated time (`--fail-rotor`), applied to the plant, and noticed by the
//! flight controller through the ESC report, which re-allocates around the stopped rotors and
//! lands ([`Commander::rotor_failed`]).

use crate::commander::{Commander, Event};
use crate::control::VehicleState;
use crate::core::FlightCore;
use crate::sitl::SimPlant;

/// A rotor that stops at a simulated time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScheduledFailure {
    /// Rotor, 1-based.
    pub rotor: usize,
    /// Simulated time it stops [s].
    pub at_s: f64,
}

impl std::str::FromStr for ScheduledFailure {
    type Err = String;

    /// `ROTOR@SECONDS`, e.g. `2@5.5`: rotor 2 stops 5.5 s after start (simulated time).
    fn from_str(text: &str) -> Result<Self, String> {
        let bad = || format!("--fail-rotor {text}: expected ROTOR@SECONDS, e.g. 2@5.5");
        let (rotor, at) = text.split_once('@').ok_or_else(bad)?;
        let rotor: usize = rotor.trim().parse().map_err(|_| bad())?;
        let at_s: f64 = at.trim().parse().map_err(|_| bad())?;
        if rotor == 0 || !(at_s.is_finite() && at_s >= 0.0) {
            return Err(bad());
        }
        Ok(Self { rotor, at_s })
    }
}

/// What the flight controller knows of the rotors, and what is still to fail.
#[derive(Debug, Clone, Default)]
pub struct RotorFailures {
    known: Vec<bool>,
    scheduled: Vec<ScheduledFailure>,
}

impl RotorFailures {
    /// `rotors` working rotors, nothing scheduled.
    pub fn new(rotors: usize) -> Self {
        Self {
            known: vec![false; rotors],
            scheduled: Vec::new(),
        }
    }

    /// Schedules `failure`; refused naming what is wrong.
    pub fn schedule(&mut self, failure: ScheduledFailure) -> Result<(), String> {
        if failure.rotor == 0 || failure.rotor > self.known.len() {
            return Err(format!(
                "rotor {}: this vehicle has rotors 1 to {}",
                failure.rotor,
                self.known.len()
            ));
        }
        if !(failure.at_s.is_finite() && failure.at_s >= 0.0) {
            return Err(format!(
                "rotor {} at {} s: the time must be >= 0",
                failure.rotor, failure.at_s
            ));
        }
        self.scheduled.push(failure);
        Ok(())
    }

    /// Stops (`failed`) or restores rotor `rotor` (1-based; 0 = every rotor) in the plant.
    pub fn inject(plant: &mut SimPlant, rotor: usize, failed: bool) -> Result<(), String> {
        let n = plant.failed_rotors().len();
        match rotor {
            0 => (0..n).for_each(|i| {
                plant.set_rotor_failed(i, failed);
            }),
            r if r <= n => {
                plant.set_rotor_failed(r - 1, failed);
            }
            r => return Err(format!("Failure injection: no motor {r} (1 to {n})")),
        }
        Ok(())
    }

    /// At simulated time `t_s` [s]: stops the rotors whose time has come, then, when the ESC
    /// report changed, re-allocates and lets the commander react; returns the announcements.
    pub fn tick(
        &mut self,
        t_s: f64,
        x: &VehicleState,
        plant: &mut SimPlant,
        core: &mut FlightCore,
        commander: &mut Commander,
    ) -> Vec<Event> {
        self.scheduled.retain(|f| {
            let due = f.at_s <= t_s;
            if due {
                plant.set_rotor_failed(f.rotor - 1, true);
            }
            !due
        });
        // Nothing to allocate on the 1 kHz path unless the ESC report changed.
        if plant.failed_rotors() == self.known.as_slice() {
            return Vec::new();
        }
        let reported = plant.failed_rotors().to_vec();
        let control = core.set_failed_rotors(&reported).ok();
        let mut events = Vec::new();
        for (i, (now, before)) in reported.iter().zip(&self.known).enumerate() {
            match (now, before) {
                (true, false) => events.extend(commander.rotor_failed(i + 1, control, x, t_s)),
                (false, true) => events.push(Event::Failsafe(format!("Motor {} working again", i + 1))),
                _ => {}
            }
        }
        self.known = reported;
        events
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn schedules_parse_and_are_checked_against_the_rotor_count() {
        assert_eq!(
            "2@5.5".parse::<ScheduledFailure>(),
            Ok(ScheduledFailure { rotor: 2, at_s: 5.5 })
        );
        for bad in ["2", "0@1", "x@1", "1@-2", "1@inf"] {
            let e = bad.parse::<ScheduledFailure>().unwrap_err();
            assert!(e.contains(bad) && e.contains("ROTOR@SECONDS"), "{e}");
        }
        let mut f = RotorFailures::new(4);
        assert!(f.schedule(ScheduledFailure { rotor: 4, at_s: 1.0 }).is_ok());
        let e = f.schedule(ScheduledFailure { rotor: 5, at_s: 1.0 }).unwrap_err();
        assert_eq!(e, "rotor 5: this vehicle has rotors 1 to 4");
    }
}
