//! The 1 kHz tick on dedicated threads (docs/architecture.md §5, docs/mavlink.md §11.3, §13.4). One thread
//! steps a group of vehicles; every tick of every vehicle in the group runs before the next
//! deadline of its [`Pacer`] (`t0 + k·dt/N`; backlog up to
//! [`MAX_BACKLOG`](super::pacer::MAX_BACKLOG), then rebased and an overrun counted). The thread
//! never waits on the network: commands arrive through bounded queues read with `try_recv`, the
//! state leaves through a `watch` (latest value only) and events through a bounded queue that
//! drops when full.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use tokio::sync::{mpsc, watch};

use crate::commander::Event;
use crate::mav::link::{Token, VehicleReply, VehicleRequest};
use crate::telemetry::Snapshot;

use super::pacer::{Pace, Pacer, Wait};
use super::vehicle::Vehicle;

/// How often the achieved real-time factor is logged (wall clock).
const RATE_REPORT_PERIOD: Duration = Duration::from_secs(10);

/// Something for the vehicle to do at the next tick boundary, with where to send the answer.
#[derive(Debug)]
pub struct VehicleCommand {
    /// What to do.
    pub request: VehicleRequest,
    /// Where the answer goes, when the link waits for one.
    pub reply: Option<ReplyTo>,
}

/// Where the answer to one [`VehicleCommand`] goes.
#[derive(Debug)]
pub struct ReplyTo {
    /// The link machine's name for the request.
    pub token: Token,
    /// The link task's answer queue.
    pub to: mpsc::UnboundedSender<(Token, VehicleReply)>,
}

/// Counters of the scheduler threads (shared by all groups).
#[derive(Debug, Default)]
pub struct SchedulerStats {
    /// Vehicle ticks run (a group of n vehicles adds n per dt).
    pub ticks: AtomicU64,
    /// Times the backlog exceeded [`MAX_BACKLOG`](super::pacer::MAX_BACKLOG) and the schedule was rebased.
    pub overruns: AtomicU64,
}

/// The channels of one vehicle.
pub struct VehicleIo {
    /// Requests from the links.
    pub inbox: mpsc::Receiver<VehicleCommand>,
    /// Latest state, shared with the link (which keeps the `Arc` it is handed, no copy).
    pub snapshot: watch::Sender<Arc<Snapshot>>,
    /// Commander events.
    pub events: mpsc::Sender<Event>,
}

/// A vehicle with its channels, as one tick thread holds it.
pub struct VehicleSlot {
    vehicle: Vehicle,
    io: VehicleIo,
}

impl VehicleSlot {
    /// `vehicle` talking through `io`.
    pub fn new(vehicle: Vehicle, io: VehicleIo) -> Self {
        Self { vehicle, io }
    }

    /// Applies the queued commands, runs one tick, publishes its state, then answers: an ACK
    /// never reaches a ground station before the state it changed is published.
    fn tick(&mut self) {
        let mut answers = Vec::new();
        while let Ok(cmd) = self.io.inbox.try_recv() {
            let answer = match cmd.request {
                VehicleRequest::Commander(request) => VehicleReply::Outcome(self.vehicle.apply(request)),
                VehicleRequest::SetParam { name, value } => VehicleReply::Param {
                    result: self.vehicle.set_param(&name, value),
                    table: self.vehicle.shared_params(),
                },
            };
            answers.extend(cmd.reply.map(|reply| (reply, answer)));
        }
        let out = self.vehicle.step();
        self.io.snapshot.send_replace(Arc::new(out.snapshot));
        for e in out.events {
            // Events are announcements; a full queue drops them rather than stall the tick.
            let _ = self.io.events.try_send(e);
        }
        for (reply, answer) in answers {
            // The link task may have stopped at shutdown; nothing waits then.
            let _ = reply.to.send((reply.token, answer));
        }
    }
}

/// Runs the vehicles of `group` at `dt` and `pace` until `stop` is set.
pub fn run_group(mut group: Vec<VehicleSlot>, dt: Duration, pace: Pace, stop: &AtomicBool, stats: &SchedulerStats) {
    let mut pacer = Pacer::new(pace, dt, Instant::now());
    let mut report = (Instant::now(), 0_u64);
    while !stop.load(Ordering::Relaxed) {
        let mut now = Instant::now();
        match pacer.next_tick(now) {
            Wait::Sleep(d) => {
                std::thread::sleep(d);
                now = Instant::now();
            }
            Wait::Rebased => {
                stats.overruns.fetch_add(1, Ordering::Relaxed);
            }
            Wait::Now => {}
        }
        for slot in &mut group {
            slot.tick();
        }
        stats.ticks.fetch_add(group.len() as u64, Ordering::Relaxed);
        report.1 += 1;
        let window = now.duration_since(report.0);
        if window >= RATE_REPORT_PERIOD {
            let factor = report.1 as f64 * dt.as_secs_f64() / window.as_secs_f64();
            tracing::info!(
                "real-time factor {factor:.2} over the last {:.0} s",
                window.as_secs_f64()
            );
            report = (now, 0);
        }
    }
}
