//! The tick thread's side of a ULog file: the pure [`Recorder`] encodes each tick into a buffer,
//! and whole buffers go to the log writer thread ([`LogSender`]) every [`SHIP_PERIOD`] of wall
//! time or [`SHIP_BYTES`], whichever comes first; so after a `kill -9` everything older than
//! `SHIP_PERIOD` + the writer's flush period is on disk. A buffer the writer's full queue cannot
//! take is dropped (autopilot only; `sim` and `fly` wait) and the gap is logged as a dropout.

use std::time::{Duration, Instant};

use super::flight_log::{LogSender, UlogTarget};
use crate::lockstep::TickView;
use crate::params::{ParamDef, ParamTable, ParamType};
use crate::ulog::encoder::Encoder;
#[cfg(test)]
use crate::ulog::Topic;
use crate::ulog::{micros, LogInfo, ParamValue, Recorder};

/// Longest wall time encoded bytes wait on the tick thread.
pub const SHIP_PERIOD: Duration = Duration::from_millis(50);
/// Ticks between two looks at the wall clock (at 1 kHz real time: 16 ms).
const CLOCK_EVERY: u64 = 16;
/// Capacity of a new buffer [bytes]; buffers grow to what `SHIP_PERIOD` holds (a few KiB at
/// the default profile in real time, up to `SHIP_BYTES` flat out) and are reused.
const FIRST_CAPACITY: usize = 1 << 12;
/// Buffer size that is shipped at once [bytes].
pub const SHIP_BYTES: usize = 1 << 18;

/// Parameter `def` at `value` as ULog stores it.
pub fn param_value(def: &ParamDef, value: f64) -> ParamValue {
    match def.kind {
        ParamType::Int32 => ParamValue::Int(value as i32),
        ParamType::Real32 => ParamValue::Float(value as f32),
    }
}

/// Every parameter of `table` as ULog stores it.
pub fn log_params(table: &ParamTable) -> Vec<(String, ParamValue)> {
    (0..table.len())
        .filter_map(|i| table.get(i))
        .map(|(def, value)| (def.name.to_string(), param_value(def, value)))
        .collect()
}

/// A ULog file being written from the tick thread.
#[derive(Debug)]
pub struct UlogStream {
    recorder: Recorder,
    buf: Vec<u8>,
    sender: LogSender,
    /// Wait for room in the writer's queue instead of dropping.
    wait: bool,
    open: bool,
    shipped_at: Instant,
    /// Log time of the first record lost since the last shipped buffer [µs].
    lost_since_us: Option<u64>,
    /// Log time of the first tick in the buffer [µs].
    buf_start_us: Option<u64>,
    /// Ticks recorded.
    ticks: u64,
}

impl UlogStream {
    /// A stream of `recorder`'s records to `sender`; with `wait`, nothing is ever dropped.
    pub fn new(recorder: Recorder, sender: LogSender, wait: bool) -> Self {
        Self {
            recorder,
            buf: Vec::with_capacity(FIRST_CAPACITY),
            sender,
            wait,
            open: false,
            shipped_at: Instant::now(),
            lost_since_us: None,
            buf_start_us: None,
            ticks: 0,
        }
    }

    /// True while a file is open.
    pub fn is_open(&self) -> bool {
        self.open
    }

    /// Opens `target` at log time `t_s` [s] and writes the definitions (info, every parameter).
    pub fn open(&mut self, target: UlogTarget, t_s: f64, info: &LogInfo, params: &[(String, ParamValue)]) {
        if self.open {
            self.close();
        }
        self.buf.clear();
        self.lost_since_us = None;
        self.open = self.sender.open_ulog(target, self.wait);
        self.recorder.begin(&mut self.buf, micros(t_s), info, params);
        if !self.ship() && self.open {
            // A file without its definitions is unreadable: close it; the next tick tries again.
            self.sender.close_ulog(false);
            self.open = false;
        }
    }

    /// Records one tick.
    pub fn record(&mut self, view: &TickView) {
        if !self.open {
            return;
        }
        self.buf_start_us.get_or_insert(micros(view.t_s));
        self.recorder.record(&mut self.buf, view);
        // The clock is read every CLOCK_EVERY ticks only (it costs as much as a record).
        self.ticks = self.ticks.wrapping_add(1);
        if self.buf.len() >= SHIP_BYTES || (self.ticks % CLOCK_EVERY == 0 && self.shipped_at.elapsed() >= SHIP_PERIOD) {
            self.ship();
        }
    }

    /// Logs a parameter change.
    pub fn param_changed(&mut self, name: &str, value: ParamValue) {
        if self.open {
            self.recorder.param_changed(&mut self.buf, name, value);
        }
    }

    /// Hands the buffer to the writer; false when the writer's full queue dropped it. After lost
    /// buffers, the first one that gets through starts with a dropout message spanning the lost
    /// log time.
    pub fn ship(&mut self) -> bool {
        self.shipped_at = Instant::now();
        if self.buf.is_empty() {
            return true;
        }
        let start_us = self.buf_start_us.take();
        if let (Some(lost), Some(start)) = (self.lost_since_us, start_us) {
            let mut gap = Vec::with_capacity(5);
            Encoder::new(&mut gap).dropout(start.saturating_sub(lost) / 1000);
            self.buf.splice(0..0, gap);
        }
        let fresh = self.sender.buffer(FIRST_CAPACITY);
        let bytes = std::mem::replace(&mut self.buf, fresh);
        if self.sender.ulog(bytes, self.wait) {
            self.lost_since_us = None;
            return true;
        }
        // The lost bytes may have held subscriptions: announce them again.
        self.recorder.forget_subscriptions();
        if let Some(start) = start_us {
            self.lost_since_us.get_or_insert(start);
        }
        false
    }

    /// Ships what is left and closes the file.
    pub fn close(&mut self) {
        if self.open {
            self.ship();
            self.sender.close_ulog(self.wait);
            self.open = false;
        }
    }
}

impl Drop for UlogStream {
    fn drop(&mut self) {
        self.close();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::{ControllerKind, VehicleState};
    use crate::math::Vec3;
    use crate::runtime::flight_log::detached;
    use crate::ulog::{Profile, RecorderSetup};

    fn recorder() -> Recorder {
        Recorder::new(RecorderSetup {
            profile: Profile::Full,
            rotors: 4,
            omega_max_rad_s: 1000.0,
            thrust_max_n: 40.0,
            torque_max_b: Vec3::new(2.0, 2.0, 1.0),
            believed_mass_kg: 1.5,
            true_mass_kg: 1.5,
            dt_s: 1e-3,
        })
    }

    fn tick(stream: &mut UlogStream, t_s: f64) {
        let state = VehicleState::at_rest(t_s, Vec3::zeros());
        stream.record(&TickView::resting(&state));
    }

    /// The (type, payload) of every message after the 16-byte file header.
    fn messages(bytes: &[u8]) -> Vec<(u8, Vec<u8>)> {
        let (mut out, mut at) = (Vec::new(), 16);
        while at + 3 <= bytes.len() {
            let len = usize::from(u16::from_le_bytes([bytes[at], bytes[at + 1]]));
            out.push((bytes[at + 2], bytes[at + 3..at + 3 + len].to_vec()));
            at += 3 + len;
        }
        assert_eq!(at, bytes.len(), "whole messages only");
        out
    }

    #[test]
    fn a_full_queue_drops_whole_buffers_and_logs_the_gap_as_a_dropout() {
        // Room for the open, the definitions and one buffer of data.
        let (sender, mut take) = detached(3);
        let mut stream = UlogStream::new(recorder(), sender, false);
        let info = LogInfo::new("quad_x", ControllerKind::Geometric, None);
        stream.open(UlogTarget::File("x.ulg".into()), 0.0, &info, &[]);
        tick(&mut stream, 0.0);
        stream.ship();
        for k in 1..=250 {
            tick(&mut stream, k as f64 * 1e-3);
            if k % 50 == 0 {
                stream.ship(); // the queue is full: dropped
            }
        }
        let mut written = take();
        // The queue has room again: the next buffer starts with the gap.
        tick(&mut stream, 0.251);
        stream.ship();
        written.extend(take());
        let msgs = messages(&written);
        let dropouts: Vec<u16> = msgs
            .iter()
            .filter(|(kind, _)| *kind == b'O')
            .map(|(_, p)| u16::from_le_bytes([p[0], p[1]]))
            .collect();
        assert_eq!(dropouts, vec![250], "ticks 1 to 250 ms were lost");
        let attitude_subscriptions = msgs
            .iter()
            .filter(|(kind, p)| *kind == b'A' && p[1..3] == Topic::VehicleAttitude.msg_id().to_le_bytes())
            .count();
        assert_eq!(attitude_subscriptions, 2, "subscribed again after the loss");
        assert!(stream.sender.dropped() >= 5);
    }
}
