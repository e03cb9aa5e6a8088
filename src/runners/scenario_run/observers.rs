//! What watches a scenario run ([`Observer`]s of its [`Lockstep::run`](crate::lockstep::Lockstep::run)):
//! the tracking statistics, the wrench estimate against the truth, the commander's events,
//! `run.csv`, and the wall-clock pacing of `--speedup`. Runtime layer only for the pacing (it
//! sleeps) and the CSV file; the rest is pure.

use std::time::{Duration, Instant};

use crate::lockstep::{Exit, Observer, SnapshotReport, Tick, TickView};
use crate::math::Vec3;
use crate::runtime::pacer::{Pace, Pacer, Wait};
use crate::scenario::estimate_stats::EstimateStats;
use crate::scenario::summary::{RunStats, TickRecord};
use crate::sitl::SimPlant;
use crate::wrench_estimator::WrenchEstimate;

use super::run_csv::RunCsv;
use super::SimError;

/// The tracking statistics of every tick the flight core flew.
impl<R> Observer<R> for RunStats {
    fn observe(&mut self, tick: &Tick<R>, _plant: &SimPlant) -> Option<Exit> {
        let step = tick.control.step.as_ref()?;
        let state = &tick.control.state;
        self.add(&TickRecord {
            t_s: tick.t_s,
            pos_w: state.pos_w,
            ref_w: tick.reference_w(),
            vel_error_w: step.control.errors.vel_w,
            att_error: step.control.errors.attitude,
            tilt_rad: state.tilt_rad(),
            thrust_n: step.allocation.applied.thrust_n,
            torque_b: step.allocation.applied.torque_b,
            saturated: step.allocation.saturation.is_saturated(),
            controller_fault: step.control.flags.is_fault(),
        });
        None
    }
}

/// `run.csv` written tick by tick; the first write error stops the run and is returned by
/// [`CsvObserver::finish`].
pub(super) struct CsvObserver {
    pub(super) csv: RunCsv,
    pub(super) path: String,
    pub(super) error: Option<std::io::Error>,
}

impl CsvObserver {
    pub(super) fn finish(self) -> Result<(), SimError> {
        let path = self.path;
        match self.error {
            Some(source) => Err(SimError::Io { path, source }),
            None => self.csv.finish().map_err(|source| SimError::Io { path, source }),
        }
    }
}

impl<R: SnapshotReport> Observer<R> for CsvObserver {
    fn observe(&mut self, tick: &Tick<R>, plant: &SimPlant) -> Option<Exit> {
        let e = self.csv.row(&TickView::of(tick, plant)).err()?;
        self.error = Some(e);
        Some(Exit::Stopped)
    }
}

/// The wrench estimate of every tick against the truth after it: the force the estimator should
/// recover is the scripted force plus the drag plus the believed-mass error `mismatch_n` [N]
/// (docs/sweep.md §3).
pub(super) struct EstimateTracker {
    pub(super) stats: EstimateStats,
    /// The latest tick's estimate.
    pub(super) last: Option<WrenchEstimate>,
    /// (m_true − m_believed)·g, down [N].
    pub(super) mismatch_n: f64,
}

impl<R> Observer<R> for EstimateTracker {
    fn observe(&mut self, tick: &Tick<R>, plant: &SimPlant) -> Option<Exit> {
        self.last = tick.control.step.and_then(|s| s.estimate);
        let truth = plant.truth();
        self.stats.add(
            tick.t_s,
            self.last.as_ref(),
            truth.external_and_drag_force_w() + Vec3::new(0.0, 0.0, self.mismatch_n),
            truth.external_torque_b,
        );
        None
    }
}

/// What the commander did on its own, each with the simulated time (`summary.json`'s `events`).
#[derive(Debug, Default)]
pub(super) struct EventLog(pub(super) Vec<String>);

impl<R> Observer<R> for EventLog {
    fn observe(&mut self, tick: &Tick<R>, _plant: &SimPlant) -> Option<Exit> {
        let t_s = tick.t_s;
        let events = tick.control.events.iter();
        self.0.extend(events.map(|e| format!("{t_s:.3} s: {}", e.describe())));
        None
    }
}

/// Simulated time held to the wall clock (`--speedup`): after each tick, waits for the next
/// tick's deadline; `Pace::Max` never waits.
pub(super) struct Paced(Pacer);

impl Paced {
    /// Paced at `pace` with step `dt`, the first tick due now.
    pub(super) fn new(pace: Pace, dt: Duration) -> Self {
        let mut pacer = Pacer::new(pace, dt, Instant::now());
        if pacer.is_paced() {
            // The first tick's deadline, which is now.
            pacer.next_tick(Instant::now());
        }
        Self(pacer)
    }
}

impl<R> Observer<R> for Paced {
    fn observe(&mut self, _tick: &Tick<R>, _plant: &SimPlant) -> Option<Exit> {
        if self.0.is_paced() {
            if let Wait::Sleep(d) = self.0.next_tick(Instant::now()) {
                std::thread::sleep(d);
            }
        }
        None
    }
}
