//! `rotorpilot run --log DIR`: `DIR/flight.tlog` (every MAVLink frame sent or received on the
//! links, each preceded by its 8-byte big-endian wall-clock time in µs since the Unix epoch: the
//! format pymavlink's mavlogdump and MAVExplorer read) and `DIR/run.csv` (one row per 1 kHz tick,
//! the columns of `rotorpilot sim`). A dedicated writer thread owns the files; the tick thread and
//! the links hand it records through a bounded queue without ever waiting (a full queue drops
//! the record and counts it). Files are flushed at least every [`FLUSH_PERIOD`].

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{sync_channel, Receiver, RecvTimeoutError, SyncSender};
use std::sync::Arc;
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use crate::control::VehicleState;
use crate::flight::CoreStep;
use crate::lockstep::{Exit, Observer, Tick};
use crate::math::Vec3;
use crate::sim::run_csv::{RunCsv, RunRow};
use crate::sitl::SimPlant;

/// Longest time a record waits in a buffer before it reaches the file.
pub const FLUSH_PERIOD: Duration = Duration::from_millis(100);
/// Records queued for the writer; 1 s of ticks plus telemetry.
const QUEUE: usize = 4096;

/// One tick for `run.csv`.
#[derive(Debug, Clone)]
pub struct TickLog {
    /// Simulated time [s].
    pub t_s: f64,
    /// State the controller saw.
    pub state: VehicleState,
    /// Reference position [m].
    pub ref_w: Vec3,
    /// Flight-core outputs (None while the motors are off).
    pub step: Option<CoreStep>,
    /// True motor speeds [rad/s].
    pub motor_speeds: Vec<f64>,
    /// True scripted external force, world NED [N].
    pub true_force_w: Vec3,
    /// True scripted external torque, body FRD [N·m].
    pub true_torque_b: Vec3,
}

impl TickLog {
    /// The owned copy of `row`, for the writer thread.
    pub fn of(row: &RunRow) -> Self {
        Self {
            t_s: row.t_s,
            state: *row.state,
            ref_w: row.ref_w,
            step: row.step.copied(),
            motor_speeds: row.motor_speeds.to_vec(),
            true_force_w: row.true_force_w,
            true_torque_b: row.true_torque_b,
        }
    }

    /// The row it writes.
    fn row(&self) -> RunRow<'_> {
        RunRow {
            t_s: self.t_s,
            state: &self.state,
            ref_w: self.ref_w,
            step: self.step.as_ref(),
            motor_speeds: &self.motor_speeds,
            true_force_w: self.true_force_w,
            true_torque_b: self.true_torque_b,
        }
    }
}

enum Record {
    Tick(Box<TickLog>),
    Frame(u64, Vec<u8>),
}

/// Where the tick thread and the links send records.
#[derive(Clone)]
pub struct LogSender {
    tx: SyncSender<Record>,
    dropped: Arc<AtomicU64>,
}

impl std::fmt::Debug for LogSender {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LogSender").field("dropped", &self.dropped()).finish()
    }
}

impl LogSender {
    /// Queues a tick row.
    pub fn tick(&self, t: TickLog) {
        if self.tx.try_send(Record::Tick(Box::new(t))).is_err() {
            self.dropped.fetch_add(1, Ordering::Relaxed);
        }
    }

    /// Queues one MAVLink frame for the tlog, stamped now.
    pub fn frame(&self, bytes: &[u8]) {
        let t_us = SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .map(|d| d.as_micros() as u64)
            .unwrap_or(0);
        if self.tx.try_send(Record::Frame(t_us, bytes.to_vec())).is_err() {
            self.dropped.fetch_add(1, Ordering::Relaxed);
        }
    }

    /// Records dropped because the writer fell behind.
    pub fn dropped(&self) -> u64 {
        self.dropped.load(Ordering::Relaxed)
    }
}

/// Queues every lockstep tick as a `run.csv` row; never stops the run.
impl<R> Observer<R> for LogSender {
    fn observe(&mut self, tick: &Tick<R>, plant: &SimPlant) -> Option<Exit> {
        self.tick(TickLog::of(&RunRow::of(tick, plant)));
        None
    }
}

/// Creates `dir`, opens the files and starts the writer thread; the thread ends (after a final
/// flush) when every [`LogSender`] is dropped.
pub fn start(dir: &Path, rotors: usize) -> std::io::Result<(LogSender, std::thread::JoinHandle<()>)> {
    std::fs::create_dir_all(dir)?;
    let csv = RunCsv::create(&dir.join("run.csv"), rotors)?;
    let tlog = std::io::BufWriter::new(std::fs::File::create(dir.join("flight.tlog"))?);
    let (tx, rx) = sync_channel(QUEUE);
    let dir: PathBuf = dir.to_path_buf();
    let handle = std::thread::Builder::new()
        .name("rotorpilot-log".into())
        .spawn(move || write_loop(rx, csv, tlog, &dir))?;
    Ok((
        LogSender {
            tx,
            dropped: Arc::new(AtomicU64::new(0)),
        },
        handle,
    ))
}

fn write_loop(rx: Receiver<Record>, mut csv: RunCsv, mut tlog: std::io::BufWriter<std::fs::File>, dir: &Path) {
    let mut last_flush = Instant::now();
    let mut failed = false;
    loop {
        let record = rx.recv_timeout(FLUSH_PERIOD / 2);
        let result = match &record {
            Ok(Record::Tick(t)) => csv.row(&t.row()),
            Ok(Record::Frame(t_us, bytes)) => tlog.write_all(&t_us.to_be_bytes()).and_then(|()| tlog.write_all(bytes)),
            Err(RecvTimeoutError::Timeout) => Ok(()),
            Err(RecvTimeoutError::Disconnected) => break,
        };
        if last_flush.elapsed() >= FLUSH_PERIOD {
            last_flush = Instant::now();
            let flushed = csv.flush().and_then(|()| tlog.flush());
            if let Err(e) = flushed {
                if !failed {
                    tracing::error!("log {}: {e}", dir.display());
                    failed = true;
                }
            }
        }
        if let Err(e) = result {
            if !failed {
                tracing::error!("log {}: {e}", dir.display());
                failed = true;
            }
        }
    }
    let _ = csv.flush();
    let _ = tlog.flush();
}
