//! What watches a lockstep run: an [`Observer`] sees every tick (sensed state, controller step,
//! plant flags, the pilot's report and the plant after the step) and may end the run. Run
//! statistics, `run.csv` writers and Monte Carlo judging are observers; [`Guard`] ends runs that
//! fault or fly away. Combine several as a tuple (all observe, the first to stop wins) or
//! leave one out with `None`. Pure.

use crate::sitl::SimPlant;

use super::{Exit, Tick};

/// Sees the ticks of a run with pilot report `R`.
pub trait Observer<R> {
    /// Looks at `tick` and the plant after its step; `Some` ends the run that way.
    fn observe(&mut self, tick: &Tick<R>, plant: &SimPlant) -> Option<Exit>;
}

/// Watches nothing.
impl<R> Observer<R> for () {
    fn observe(&mut self, _tick: &Tick<R>, _plant: &SimPlant) -> Option<Exit> {
        None
    }
}

/// An observer that may be absent.
impl<R, O: Observer<R>> Observer<R> for Option<O> {
    fn observe(&mut self, tick: &Tick<R>, plant: &SimPlant) -> Option<Exit> {
        self.as_mut().and_then(|o| o.observe(tick, plant))
    }
}

/// Both observe, in order; the first to stop wins.
impl<R, A: Observer<R>, B: Observer<R>> Observer<R> for (A, B) {
    fn observe(&mut self, tick: &Tick<R>, plant: &SimPlant) -> Option<Exit> {
        let a = self.0.observe(tick, plant);
        let b = self.1.observe(tick, plant);
        a.or(b)
    }
}

/// All three observe, in order; the first to stop wins.
impl<R, A: Observer<R>, B: Observer<R>, C: Observer<R>> Observer<R> for (A, B, C) {
    fn observe(&mut self, tick: &Tick<R>, plant: &SimPlant) -> Option<Exit> {
        let a = self.0.observe(tick, plant);
        let b = self.1.observe(tick, plant);
        let c = self.2.observe(tick, plant);
        a.or(b).or(c)
    }
}

/// Ends a run when the plant faults (non-finite state or refused step) or the true position
/// leaves the sphere of radius `fly_away_m` [m] around the origin (or is not a number).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Guard {
    /// Radius of the allowed sphere [m].
    pub fly_away_m: f64,
}

impl<R> Observer<R> for Guard {
    fn observe(&mut self, tick: &Tick<R>, plant: &SimPlant) -> Option<Exit> {
        if tick.status.state_non_finite || tick.status.dt_rejected {
            return Some(Exit::PlantFault);
        }
        let distance_m = plant.truth().pos_w.norm();
        (distance_m.is_nan() || distance_m > self.fly_away_m).then_some(Exit::FlyAway)
    }
}
