//! The 1 kHz tick on a dedicated thread (architecture.md §5, mavlink.md §13.5): sleep to
//! absolute deadlines `t0 + k·dt`; when late, run the missed ticks back-to-back with the fixed dt
//! up to [`MAX_BACKLOG_TICKS`], then rebase and count an overrun. The thread never waits on the
//! network: commands arrive through a bounded queue read with `try_recv`, the state leaves
//! through a `watch` (latest value only) and events through a bounded queue that drops when full.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use tokio::sync::{mpsc, oneshot, watch};

use crate::commander::{Event, Outcome, Request};
use crate::params::{ParamError, ParamTable};
use crate::telemetry::Snapshot;

use super::vehicle::Vehicle;

/// Missed ticks run back-to-back before the schedule is rebased (100 ms at 1 kHz).
pub const MAX_BACKLOG_TICKS: u64 = 100;

/// Something for the vehicle to do at the next tick boundary, with where to send the result.
#[derive(Debug)]
pub enum VehicleCommand {
    /// A commander request.
    Request {
        /// The request.
        request: Request,
        /// Outcome channel (the link answers the sender with it).
        reply: Option<oneshot::Sender<Outcome>>,
    },
    /// A parameter set.
    SetParam {
        /// Parameter name.
        name: String,
        /// New value.
        value: f64,
        /// Index of the parameter, or why it was refused.
        reply: oneshot::Sender<Result<usize, ParamError>>,
    },
}

/// Counters of the scheduler.
#[derive(Debug, Default)]
pub struct SchedulerStats {
    /// Ticks run.
    pub ticks: AtomicU64,
    /// Times the backlog exceeded [`MAX_BACKLOG_TICKS`] and the schedule was rebased.
    pub overruns: AtomicU64,
}

/// Channels and flags the tick thread works with.
pub struct SchedulerIo {
    /// Requests from the links.
    pub inbox: mpsc::Receiver<VehicleCommand>,
    /// Latest state.
    pub snapshot: watch::Sender<Snapshot>,
    /// Current parameter table (republished after every accepted set).
    pub params: watch::Sender<Arc<ParamTable>>,
    /// Commander events.
    pub events: mpsc::Sender<Event>,
    /// Set to stop at the next tick boundary.
    pub stop: Arc<AtomicBool>,
    /// Counters.
    pub stats: Arc<SchedulerStats>,
}

/// Runs `vehicle` at `dt` until `io.stop` is set.
pub fn run(mut vehicle: Vehicle, dt: Duration, mut io: SchedulerIo) {
    let t0 = Instant::now();
    let mut next: u64 = 0;
    let mut base = t0;
    while !io.stop.load(Ordering::Relaxed) {
        let deadline = base + dt * next as u32;
        let now = Instant::now();
        if deadline > now {
            std::thread::sleep(deadline - now);
        } else if now - deadline > dt * MAX_BACKLOG_TICKS as u32 {
            io.stats.overruns.fetch_add(1, Ordering::Relaxed);
            base = now;
            next = 0;
        }
        while let Ok(cmd) = io.inbox.try_recv() {
            match cmd {
                VehicleCommand::Request { request, reply } => {
                    let outcome = vehicle.apply(request);
                    if let Some(reply) = reply {
                        let _ = reply.send(outcome);
                    }
                }
                VehicleCommand::SetParam { name, value, reply } => {
                    let result = vehicle.set_param(&name, value);
                    if result.is_ok() {
                        io.params.send_replace(Arc::new(vehicle.params().clone()));
                    }
                    let _ = reply.send(result);
                }
            }
        }
        let out = vehicle.step();
        io.snapshot.send_replace(out.snapshot);
        for e in out.events {
            // Events are announcements; a full queue drops them rather than stall the tick.
            let _ = io.events.try_send(e);
        }
        io.stats.ticks.fetch_add(1, Ordering::Relaxed);
        next += 1;
        if next >= u64::from(u32::MAX) {
            base += dt * next as u32;
            next = 0;
        }
    }
}
