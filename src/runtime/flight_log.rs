//! The log writer thread: it owns the files of `run --log DIR` (`DIR/flight.tlog` and the ULog
//! of each flight), of `sim --out` and of `fly --log`, so the tick thread and the links never
//! wait on a disk. They hand it records through a bounded queue: tlog frames (each stored after
//! its 8-byte big-endian wall-clock time in µs since the Unix epoch, the format pymavlink's
//! mavlogdump and MAVExplorer read) and ULog bytes for the file currently open. A sender that must
//! not block (the autopilot) drops what a full queue cannot take and counts it; a run that must
//! keep everything (`sim`, `fly`) waits instead. Files are flushed at least every
//! [`FLUSH_PERIOD`].

use std::io::Write;
use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{sync_channel, Receiver, RecvTimeoutError, SyncSender, TrySendError};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

/// Longest time a record waits in a buffer before it reaches the file.
pub const FLUSH_PERIOD: Duration = Duration::from_millis(100);
/// Records queued for the writer.
const QUEUE: usize = 4096;
/// Emptied ULog buffers kept for reuse (a fresh one costs its page faults again).
const SPARE_BUFFERS: usize = 4;

/// Emptied ULog buffers the writer hands back to the tick thread.
type Spares = Arc<Mutex<Vec<Vec<u8>>>>;

type File = std::io::BufWriter<std::fs::File>;

enum Record {
    Frame(u64, Vec<u8>),
    /// Create the ULog file (and its directory) and make it the current one.
    Open(PathBuf),
    /// Bytes of the current ULog file.
    Ulog(Vec<u8>),
    /// Close the current ULog file.
    Close,
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

    /// Opens the ULog file `path`, waiting for room when `wait`.
    pub fn open_ulog(&self, path: PathBuf, wait: bool) -> bool {
        self.send(Record::Open(path), wait)
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

/// The writer thread; [`LogWriter::finish`] waits for it and returns its first error.
#[derive(Debug)]
pub struct LogWriter {
    handle: std::thread::JoinHandle<Result<(), String>>,
}

impl LogWriter {
    /// Waits until every [`LogSender`] is dropped and the files are flushed; the first error
    /// (file and cause), if any.
    pub fn finish(self) -> Result<(), String> {
        self.handle
            .join()
            .unwrap_or_else(|_| Err("log writer thread panicked".into()))
    }
}

/// Starts the writer thread, with a tlog at `tlog` when given (created now).
pub fn start(tlog: Option<PathBuf>) -> std::io::Result<(LogSender, LogWriter)> {
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
        .spawn(move || write_loop(rx, tlog, &returned))?;
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

fn write_loop(rx: Receiver<Record>, mut tlog: Option<(File, PathBuf)>, spares: &Spares) -> Result<(), String> {
    let mut ulog: Option<(File, PathBuf)> = None;
    let mut last_flush = Instant::now();
    let mut first_error: Option<String> = None;
    let mut fail = |path: &PathBuf, e: std::io::Error| {
        if first_error.is_none() {
            let text = format!("{}: {e}", path.display());
            tracing::error!("log {text}");
            first_error = Some(text);
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
                if let Some((mut f, old)) = ulog.take() {
                    if let Err(e) = f.flush() {
                        fail(&old, e);
                    }
                }
                match create(&path) {
                    Ok(f) => ulog = Some((f, path)),
                    Err(e) => fail(&path, e),
                }
            }
            Ok(Record::Ulog(mut bytes)) => {
                if let Some((f, path)) = &mut ulog {
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
                if let Some((mut f, path)) = ulog.take() {
                    if let Err(e) = f.flush() {
                        fail(&path, e);
                    }
                }
            }
            Err(RecvTimeoutError::Timeout) => {}
            Err(RecvTimeoutError::Disconnected) => break,
        }
        if last_flush.elapsed() >= FLUSH_PERIOD {
            last_flush = Instant::now();
            for (f, path) in [&mut tlog, &mut ulog].into_iter().flatten() {
                if let Err(e) = f.flush() {
                    fail(path, e);
                }
            }
        }
    }
    for (f, path) in [&mut tlog, &mut ulog].into_iter().flatten() {
        if let Err(e) = f.flush() {
            fail(path, e);
        }
    }
    first_error.map_or(Ok(()), Err)
}
