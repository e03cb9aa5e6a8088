//! The log writer thread: it owns the files of `run --log DIR` (`DIR/flight.tlog` and the ULog
//! of each flight), of `sim --out` and of `fly --log`, so the tick thread and the links never
//! wait on a disk. They hand it records through a bounded queue: tlog frames (each stored after
//! its 8-byte big-endian wall-clock time in µs since the Unix epoch, the format pymavlink's
//! mavlogdump and MAVExplorer read) and ULog bytes for the file currently open. A sender that must
//! not block (the autopilot) drops what a full queue cannot take and counts it; a run that must
//! keep everything (`sim`, `fly`) waits instead. Files are flushed at least every
//! [`FLUSH_PERIOD`]. Each flight log begun is announced as PX4's logger announces it
//! ("[logger] ./log/YYYY-MM-DD/HH_MM_SS.ulg") through the [`Announce`] it was given.

use std::io::Write;
use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{sync_channel, Receiver, RecvTimeoutError, SyncSender, TrySendError};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use super::log_store::LogDir;
use crate::mav::logs::logger_announcement;

/// Longest time a record waits in a buffer before it reaches the file.
pub const FLUSH_PERIOD: Duration = Duration::from_millis(100);
/// Records queued for the writer.
const QUEUE: usize = 4096;
/// Emptied ULog buffers kept for reuse (a fresh one costs its page faults again).
const SPARE_BUFFERS: usize = 4;

/// Where the writer says that a flight log has begun (the text of an information STATUSTEXT).
pub type Announce = Box<dyn Fn(String) + Send>;

/// Emptied ULog buffers the writer hands back to the tick thread.
type Spares = Arc<Mutex<Vec<Vec<u8>>>>;

type File = std::io::BufWriter<std::fs::File>;

enum Record {
    Frame(u64, Vec<u8>),
    /// Create the ULog file (and its directory) and make it the current one.
    Open(PathBuf),
    /// Begin the flight log of wall time `at` in the log directory and make it the current one.
    OpenFlight(SystemTime),
    /// Bytes of the current ULog file.
    Ulog(Vec<u8>),
    /// Close the current ULog file.
    Close,
}

/// Where a ULog file goes.
#[derive(Debug, Clone, PartialEq)]
pub enum UlogTarget {
    /// This file (created with its directory).
    File(PathBuf),
    /// The next flight log of the writer's log directory, armed at this wall time
    /// ([`LogDir::begin`]: PX4's name, marked as being written until closed).
    Flight(SystemTime),
}

/// Where the tick thread and the links send records.
#[derive(Clone)]
pub struct LogSender {
    tx: SyncSender<Record>,
    dropped: Arc<AtomicU64>,
    spares: Spares,
}

impl std::fmt::Debug for LogSender {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LogSender").field("dropped", &self.dropped()).finish()
    }
}

impl LogSender {
    fn try_send(&self, record: Record) -> bool {
        match self.tx.try_send(record) {
            Ok(()) => true,
            Err(TrySendError::Full(_) | TrySendError::Disconnected(_)) => {
                self.dropped.fetch_add(1, Ordering::Relaxed);
                false
            }
        }
    }

    /// Queues one MAVLink frame for the tlog, stamped now.
    pub fn frame(&self, bytes: &[u8]) {
        let t_us = SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .map(|d| d.as_micros() as u64)
            .unwrap_or(0);
        self.try_send(Record::Frame(t_us, bytes.to_vec()));
    }

    /// Appends a logged string at `level` (MAVLink severity), log time `t_s` [s], to the open
    /// ULog file, if any (a STATUSTEXT the links said).
    pub fn logged_string(&self, level: u8, t_s: f64, text: &str) {
        let mut bytes = Vec::with_capacity(12 + text.len());
        crate::ulog::encoder::Encoder::new(&mut bytes).logged_string(level, crate::ulog::micros(t_s), text);
        self.try_send(Record::Ulog(bytes));
    }

    /// Opens the ULog file `target`, waiting for room when `wait`.
    pub fn open_ulog(&self, target: UlogTarget, wait: bool) -> bool {
        let record = match target {
            UlogTarget::File(path) => Record::Open(path),
            UlogTarget::Flight(at) => Record::OpenFlight(at),
        };
        self.send(record, wait)
    }

    /// Queues bytes of the open ULog file, waiting for room when `wait`; false when dropped.
    pub fn ulog(&self, bytes: Vec<u8>, wait: bool) -> bool {
        self.send(Record::Ulog(bytes), wait)
    }

    /// Closes the open ULog file.
    pub fn close_ulog(&self, wait: bool) -> bool {
        self.send(Record::Close, wait)
    }

    fn send(&self, record: Record, wait: bool) -> bool {
        if wait {
            self.tx.send(record).is_ok()
        } else {
            self.try_send(record)
        }
    }

    /// An empty buffer of at least `capacity` bytes: one the writer has emptied, or a new one.
    pub fn buffer(&self, capacity: usize) -> Vec<u8> {
        let spare = self.spares.lock().ok().and_then(|mut s| s.pop());
        spare.unwrap_or_else(|| Vec::with_capacity(capacity))
    }

    /// Records dropped because the writer fell behind.
    pub fn dropped(&self) -> u64 {
        self.dropped.load(Ordering::Relaxed)
    }
}

/// A sender with no writer: its queue holds `capacity` records that `take` returns as the ULog
/// bytes queued (for tests of what a full queue does).
#[cfg(test)]
pub(crate) fn detached(capacity: usize) -> (LogSender, impl FnMut() -> Vec<u8>) {
    let (tx, rx) = sync_channel(capacity);
    let sender = LogSender {
        tx,
        dropped: Arc::new(AtomicU64::new(0)),
        spares: Spares::default(),
    };
    let take = move || {
        let mut bytes = Vec::new();
        while let Ok(record) = rx.try_recv() {
            if let Record::Ulog(b) = record {
                bytes.extend(b);
            }
        }
        bytes
    };
    (sender, take)
}

/// The first file the writer could not write, and why.
#[derive(Debug, thiserror::Error)]
#[error("{}: {source}", path.display())]
pub struct LogWriteError {
    /// The file.
    pub path: PathBuf,
    /// Cause.
    pub source: std::io::Error,
}

/// The writer thread; [`LogWriter::finish`] waits for it and returns its first error.
#[derive(Debug)]
pub struct LogWriter {
    handle: std::thread::JoinHandle<Result<(), LogWriteError>>,
}

impl LogWriter {
    /// Waits until every [`LogSender`] is dropped and the files are flushed; the first error
    /// (file and cause), if any.
    pub fn finish(self) -> Result<(), LogWriteError> {
        self.handle.join().unwrap_or_else(|_| {
            Err(LogWriteError {
                path: PathBuf::new(),
                source: std::io::Error::other("log writer thread panicked"),
            })
        })
    }
}

/// Starts the writer thread, with a tlog at `tlog` when given (created now) and the flight logs
/// in `flights`, each one begun said to `announce`.
pub fn start(
    tlog: Option<PathBuf>,
    flights: Option<LogDir>,
    announce: Option<Announce>,
) -> std::io::Result<(LogSender, LogWriter)> {
    let tlog = match tlog {
        Some(path) => {
            if let Some(dir) = path.parent() {
                std::fs::create_dir_all(dir)?;
            }
            Some((std::io::BufWriter::new(std::fs::File::create(&path)?), path))
        }
        None => None,
    };
    let (tx, rx) = sync_channel(QUEUE);
    let spares = Spares::default();
    let returned = spares.clone();
    let handle = std::thread::Builder::new()
        .name("rotorpilot-log".into())
        .spawn(move || write_loop(rx, tlog, flights, announce, &returned))?;
    let sender = LogSender {
        tx,
        dropped: Arc::new(AtomicU64::new(0)),
        spares,
    };
    Ok((sender, LogWriter { handle }))
}

/// Creates `path` and its directory.
fn create(path: &PathBuf) -> std::io::Result<File> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)?;
    }
    Ok(std::io::BufWriter::with_capacity(1 << 18, std::fs::File::create(path)?))
}

/// The ULog file being written: the file, its path, and its time when it is a flight log.
type Current = Option<(File, PathBuf, Option<u32>)>;

/// Flushes and closes the current file; a flight log is then no longer being written.
fn close(ulog: &mut Current, flights: Option<&LogDir>) -> Result<(), (PathBuf, std::io::Error)> {
    let Some((mut f, path, flight)) = ulog.take() else {
        return Ok(());
    };
    let flushed = f.flush();
    drop(f);
    if let (Some(dir), Some(utc_s)) = (flights, flight) {
        dir.end(utc_s);
    }
    flushed.map_err(|e| (path, e))
}

fn write_loop(
    rx: Receiver<Record>,
    mut tlog: Option<(File, PathBuf)>,
    flights: Option<LogDir>,
    announce: Option<Announce>,
    spares: &Spares,
) -> Result<(), LogWriteError> {
    let mut ulog: Current = None;
    let mut last_flush = Instant::now();
    let mut first_error: Option<LogWriteError> = None;
    let mut fail = |path: &PathBuf, source: std::io::Error| {
        if first_error.is_none() {
            let e = LogWriteError {
                path: path.clone(),
                source,
            };
            tracing::error!("log {e}");
            first_error = Some(e);
        }
    };
    loop {
        match rx.recv_timeout(FLUSH_PERIOD / 2) {
            Ok(Record::Frame(t_us, bytes)) => {
                if let Some((f, path)) = &mut tlog {
                    if let Err(e) = f.write_all(&t_us.to_be_bytes()).and_then(|()| f.write_all(&bytes)) {
                        fail(path, e);
                    }
                }
            }
            Ok(Record::Open(path)) => {
                if let Err((old, e)) = close(&mut ulog, flights.as_ref()) {
                    fail(&old, e);
                }
                match create(&path) {
                    Ok(f) => ulog = Some((f, path, None)),
                    Err(e) => fail(&path, e),
                }
            }
            Ok(Record::OpenFlight(at)) => {
                if let Err((old, e)) = close(&mut ulog, flights.as_ref()) {
                    fail(&old, e);
                }
                if let Some(dir) = &flights {
                    match dir.begin(at) {
                        Ok(new) => {
                            tracing::info!("flight log {}", new.path.display());
                            if let Some(say) = &announce {
                                say(logger_announcement(new.utc_s));
                            }
                            let file = std::io::BufWriter::with_capacity(1 << 18, new.file);
                            ulog = Some((file, new.path, Some(new.utc_s)));
                        }
                        Err(e) => fail(&dir.root().to_path_buf(), e),
                    }
                }
            }
            Ok(Record::Ulog(mut bytes)) => {
                if let Some((f, path, _)) = &mut ulog {
                    if let Err(e) = f.write_all(&bytes) {
                        fail(path, e);
                    }
                }
                bytes.clear();
                if let Ok(mut pool) = spares.lock() {
                    if pool.len() < SPARE_BUFFERS {
                        pool.push(bytes);
                    }
                }
            }
            Ok(Record::Close) => {
                if let Err((path, e)) = close(&mut ulog, flights.as_ref()) {
                    fail(&path, e);
                }
            }
            Err(RecvTimeoutError::Timeout) => {}
            Err(RecvTimeoutError::Disconnected) => break,
        }
        if last_flush.elapsed() >= FLUSH_PERIOD {
            last_flush = Instant::now();
            let current = ulog.as_mut().map(|(f, path, _)| (f, &*path));
            for (f, path) in [tlog.as_mut().map(|(f, p)| (f, &*p)), current].into_iter().flatten() {
                if let Err(e) = f.flush() {
                    fail(path, e);
                }
            }
        }
    }
    if let Some((f, path)) = &mut tlog {
        if let Err(e) = f.flush() {
            fail(path, e);
        }
    }
    if let Err((path, e)) = close(&mut ulog, flights.as_ref()) {
        fail(&path, e);
    }
    first_error.map_or(Ok(()), Err)
}
