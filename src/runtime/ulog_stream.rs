//! The tick thread's side of a ULog file: the pure [`Recorder`] encodes each tick into a buffer,
//! and whole buffers go to the log writer thread ([`LogSender`]) every [`SHIP_PERIOD`] of wall
//! time or [`SHIP_BYTES`], whichever comes first; so after a `kill -9` everything older than
//! `SHIP_PERIOD` + the writer's flush period is on disk. A buffer the writer's full queue cannot
//! take is dropped (autopilot only; `sim` and `fly` wait) and the gap is logged as a dropout.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use super::flight_log::LogSender;
use crate::lockstep::TickView;
use crate::params::{ParamDef, ParamTable, ParamType};
use crate::ulog::{micros, LogInfo, ParamValue, Recorder};

/// Longest wall time encoded bytes wait on the tick thread.
pub const SHIP_PERIOD: Duration = Duration::from_millis(50);
/// Ticks between two looks at the wall clock (at 1 kHz real time: 16 ms).
const CLOCK_EVERY: u64 = 16;
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
    last_t_us: u64,
    /// Ticks recorded.
    ticks: u64,
}

impl UlogStream {
    /// A stream of `recorder`'s records to `sender`; with `wait`, nothing is ever dropped.
    pub fn new(recorder: Recorder, sender: LogSender, wait: bool) -> Self {
        Self {
            recorder,
            buf: Vec::with_capacity(SHIP_BYTES + (1 << 12)),
            sender,
            wait,
            open: false,
            shipped_at: Instant::now(),
            lost_since_us: None,
            last_t_us: 0,
            ticks: 0,
        }
    }

    /// True while a file is open.
    pub fn is_open(&self) -> bool {
        self.open
    }

    /// Opens `path` at log time `t_s` [s] and writes the definitions (info, every parameter).
    pub fn open(&mut self, path: PathBuf, t_s: f64, info: &LogInfo, params: &[(String, ParamValue)]) {
        if self.open {
            self.close();
        }
        self.buf.clear();
        self.lost_since_us = None;
        self.open = self.sender.open_ulog(path, self.wait);
        self.recorder.begin(&mut self.buf, micros(t_s), info, params);
        self.ship();
    }

    /// Records one tick.
    pub fn record(&mut self, view: &TickView) {
        if !self.open {
            return;
        }
        self.last_t_us = micros(view.t_s);
        if let Some(since) = self.lost_since_us.take() {
            let ms = self.last_t_us.saturating_sub(since) / 1000;
            crate::ulog::encoder::Encoder::new(&mut self.buf).dropout(ms);
        }
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

    /// Logs a string at `level` (MAVLink severity) at log time `t_s` [s].
    pub fn message(&mut self, level: u8, t_s: f64, text: &str) {
        if self.open {
            self.recorder.message(&mut self.buf, level, micros(t_s), text);
        }
    }

    /// Hands the buffer to the writer.
    pub fn ship(&mut self) {
        self.shipped_at = Instant::now();
        if self.buf.is_empty() {
            return;
        }
        let fresh = self.sender.buffer(SHIP_BYTES + (1 << 12));
        let bytes = std::mem::replace(&mut self.buf, fresh);
        if !self.sender.ulog(bytes, self.wait) {
            // The lost bytes may have held subscriptions: announce them again.
            self.recorder.forget_subscriptions();
            self.lost_since_us.get_or_insert(self.last_t_us);
        }
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
