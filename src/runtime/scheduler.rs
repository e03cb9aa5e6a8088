//! The 1 kHz tick on dedicated threads (architecture.md §5, mavlink.md §11.3, §13.5). One thread
//! steps a group of vehicles; every tick of every vehicle in the group runs before the next
//! deadline `t0 + k·dt/N` (N = speed-up; no sleeping at all for `--speedup max`). When late,
//! the missed ticks run back-to-back with the fixed dt — physics never skips — up to
//! [`MAX_BACKLOG`] of wall time, then the schedule is rebased and an overrun counted. The thread
//! never waits on the network: commands arrive through bounded queues read with `try_recv`, the
//! state leaves through a `watch` (latest value only) and events through a bounded queue that
//! drops when full.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

use tokio::sync::{mpsc, watch};

use crate::commander::{Event, Request};
use crate::mav::link::{Token, VehicleReply, VehicleRequest};
use crate::telemetry::Snapshot;

use super::vehicle::Vehicle;

/// Missed ticks run back-to-back up to this much wall time before the schedule is rebased.
pub const MAX_BACKLOG: Duration = Duration::from_millis(100);
/// How often the achieved real-time factor is logged (wall clock).
const RATE_REPORT_PERIOD: Duration = Duration::from_secs(10);

/// How fast simulated time runs against the wall clock.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Pace {
    /// Simulated seconds per wall second (0.1 … 1000; 1 = real time).
    Speedup(f64),
    /// As fast as the CPU allows.
    Max,
}

impl Pace {
    /// Wall time of one tick of `dt`, `None` for [`Pace::Max`].
    fn tick_period(self, dt: Duration) -> Option<Duration> {
        match self {
            Pace::Speedup(x) => Some(dt.div_f64(x)),
            Pace::Max => None,
        }
    }
}

/// Slowest and fastest numeric speed-up.
pub const SPEEDUP_RANGE: (f64, f64) = (0.1, 1000.0);

impl std::str::FromStr for Pace {
    type Err = String;

    /// `max`, or a number of simulated seconds per wall second in [`SPEEDUP_RANGE`].
    fn from_str(text: &str) -> Result<Self, String> {
        if text.trim().eq_ignore_ascii_case("max") {
            return Ok(Pace::Max);
        }
        let (lo, hi) = SPEEDUP_RANGE;
        match text.trim().parse::<f64>() {
            Ok(x) if (lo..=hi).contains(&x) => Ok(Pace::Speedup(x)),
            _ => Err(format!("--speedup {text}: must be a number from {lo} to {hi}, or max")),
        }
    }
}

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
    /// Times the backlog exceeded [`MAX_BACKLOG`] and the schedule was rebased.
    pub overruns: AtomicU64,
}

/// The channels of one vehicle.
pub struct VehicleIo {
    /// Requests from the links.
    pub inbox: mpsc::Receiver<VehicleCommand>,
    /// Latest state.
    pub snapshot: watch::Sender<Snapshot>,
    /// Commander events.
    pub events: mpsc::Sender<Event>,
}

/// A vehicle with its channels, as one tick thread holds it.
pub struct VehicleSlot {
    vehicle: Vehicle,
    io: VehicleIo,
    /// Wall time of the latest offboard setpoint.
    offboard_seen: Option<Instant>,
}

impl VehicleSlot {
    /// `vehicle` talking through `io`.
    pub fn new(vehicle: Vehicle, io: VehicleIo) -> Self {
        Self {
            vehicle,
            io,
            offboard_seen: None,
        }
    }

    /// Applies the queued commands, then runs one tick.
    fn tick(&mut self, now: Instant) {
        while let Ok(cmd) = self.io.inbox.try_recv() {
            let answer = match cmd.request {
                VehicleRequest::Commander(request) => {
                    if matches!(request, Request::OffboardSetpoint { .. } | Request::OffboardAttitude(_)) {
                        self.offboard_seen = Some(now);
                    }
                    VehicleReply::Outcome(self.vehicle.apply(request))
                }
                VehicleRequest::SetParam { name, value } => VehicleReply::Param {
                    result: self.vehicle.set_param(&name, value),
                    table: Box::new(self.vehicle.params().clone()),
                },
            };
            if let Some(reply) = cmd.reply {
                // The link task may have stopped at shutdown; nothing waits then.
                let _ = reply.to.send((reply.token, answer));
            }
        }
        let loss = Duration::from_secs_f64(self.vehicle.offboard_loss_s().max(0.0));
        if self.offboard_seen.is_some_and(|seen| now.duration_since(seen) < loss) {
            self.vehicle.refresh_offboard();
        }
        let out = self.vehicle.step();
        self.io.snapshot.send_replace(out.snapshot);
        for e in out.events {
            // Events are announcements; a full queue drops them rather than stall the tick.
            let _ = self.io.events.try_send(e);
        }
    }
}

/// Runs the vehicles of `group` at `dt` and `pace` until `stop` is set.
pub fn run_group(mut group: Vec<VehicleSlot>, dt: Duration, pace: Pace, stop: &AtomicBool, stats: &SchedulerStats) {
    let period = pace.tick_period(dt);
    let mut base = Instant::now();
    let mut next: u64 = 0;
    let mut report = (base, 0_u64);
    while !stop.load(Ordering::Relaxed) {
        let mut now = Instant::now();
        if let Some(period) = period {
            let deadline = base + period.mul_f64(next as f64);
            if deadline > now {
                std::thread::sleep(deadline - now);
                now = Instant::now();
            } else if now - deadline > MAX_BACKLOG {
                stats.overruns.fetch_add(1, Ordering::Relaxed);
                base = now;
                next = 0;
            }
        }
        for slot in &mut group {
            slot.tick(now);
        }
        stats.ticks.fetch_add(group.len() as u64, Ordering::Relaxed);
        next += 1;
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tick_period_scales_with_the_speedup() {
        let dt = Duration::from_millis(1);
        assert_eq!(Pace::Speedup(1.0).tick_period(dt), Some(dt));
        assert_eq!(Pace::Speedup(20.0).tick_period(dt), Some(Duration::from_micros(50)));
        assert_eq!(Pace::Speedup(0.1).tick_period(dt), Some(Duration::from_millis(10)));
        assert_eq!(Pace::Max.tick_period(dt), None);
    }

    #[test]
    fn speedup_parses_numbers_in_range_and_max() {
        assert_eq!("20".parse::<Pace>(), Ok(Pace::Speedup(20.0)));
        assert_eq!("MAX".parse::<Pace>(), Ok(Pace::Max));
        assert_eq!("0.1".parse::<Pace>(), Ok(Pace::Speedup(0.1)));
        for bad in ["0", "1001", "fast", "NaN", "-2"] {
            let e = bad.parse::<Pace>().unwrap_err();
            assert!(e.contains(bad) && e.contains("or max"), "{e}");
        }
    }
}
