//! The flight logs of `rotorpilot run --log DIR` on disk: `DIR/log/YYYY-MM-DD/HH_MM_SS.ulg` (PX4's
//! layout and names, UTC at arming), served to the link by [`LogDir`], the runtime's
//! [`LogStore`]: listed from the directory at each request, read at an offset with positioned
//! reads (a log is never loaded whole), erased file by file. Files below `DIR/log` that do not
//! follow the layout are not logs: never listed, served or erased. Logs present when the process
//! starts are served too. A directory that does not exist yet holds no logs; the first log
//! creates it ([`LogDir::at`], the per-user default of `run` without `--log`).
//!
//! The ULog writer calls [`LogDir::begin`] at arming (the file is created and marked as being
//! written: listed with the size it has, never erased) and [`LogDir::end`] once it has written
//! and closed it. Runtime layer: files, the wall clock.

use std::fs::File;
use std::io;
use std::os::unix::fs::FileExt;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::{SystemTime, UNIX_EPOCH};

use crate::mav::logs::{log_dir_and_file, log_name, parse_log_name, LogFile, LogStore, LogStoreError};

/// A log file just created by [`LogDir::begin`].
#[derive(Debug)]
pub struct NewLog {
    /// Its path, `DIR/log/YYYY-MM-DD/HH_MM_SS.ulg`.
    pub path: PathBuf,
    /// The file, open for writing and empty.
    pub file: File,
    /// Its time [s since 1970 UTC], to hand back to [`LogDir::end`].
    pub utc_s: u32,
}

/// What every handle of one log directory shares.
#[derive(Debug)]
struct Shared {
    root: PathBuf,
    /// The log being written.
    writing: Mutex<Option<u32>>,
}

/// The log directory `DIR/log`; clones share which log is being written.
#[derive(Debug)]
pub struct LogDir {
    shared: Arc<Shared>,
    /// The log last read and its open file (positioned reads need no seek).
    open: Option<(u32, File)>,
}

impl Clone for LogDir {
    fn clone(&self) -> Self {
        Self {
            shared: self.shared.clone(),
            open: None,
        }
    }
}

fn io_error(path: &Path, e: &io::Error) -> LogStoreError {
    LogStoreError::Io {
        path: path.display().to_string(),
        message: e.to_string(),
    }
}

impl LogDir {
    /// The log directory at `root` (`DIR/log`), created when missing.
    pub fn open(root: &Path) -> io::Result<Self> {
        std::fs::create_dir_all(root)?;
        Ok(Self::at(root))
    }

    /// The log directory at `root` (`DIR/log`), created with its first log.
    pub fn at(root: &Path) -> Self {
        Self {
            shared: Arc::new(Shared {
                root: root.to_path_buf(),
                writing: Mutex::new(None),
            }),
            open: None,
        }
    }

    /// The directory.
    pub fn root(&self) -> &Path {
        &self.shared.root
    }

    /// Where the log of `utc_s` [s since 1970 UTC] is.
    pub fn path_of(&self, utc_s: u32) -> PathBuf {
        self.shared.root.join(log_name(utc_s))
    }

    /// The log being written, by its time.
    pub fn writing(&self) -> Option<u32> {
        *self.shared.writing.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Creates the log of wall time `at` (its date directory too) and marks it as being written.
    /// A second arming within the same second takes the next free second, so no log is
    /// overwritten. Fails before 1970 and after 2106 (no PX4 name exists).
    pub fn begin(&self, at: SystemTime) -> io::Result<NewLog> {
        let out_of_range = || io::Error::new(io::ErrorKind::InvalidInput, "log time outside 1970 … 2106");
        let secs = at.duration_since(UNIX_EPOCH).map_err(|_| out_of_range())?.as_secs();
        let mut utc_s = u32::try_from(secs).map_err(|_| out_of_range())?;
        // Held while the file is created, so an erase never sees it unmarked.
        let mut writing = self.shared.writing.lock().unwrap_or_else(PoisonError::into_inner);
        loop {
            let (date, _) = log_dir_and_file(utc_s);
            std::fs::create_dir_all(self.shared.root.join(date))?;
            let path = self.path_of(utc_s);
            match File::options().write(true).create_new(true).open(&path) {
                Ok(file) => {
                    *writing = Some(utc_s);
                    return Ok(NewLog { path, file, utc_s });
                }
                Err(e) if e.kind() == io::ErrorKind::AlreadyExists => {
                    utc_s = utc_s.checked_add(1).ok_or_else(out_of_range)?;
                }
                Err(e) => return Err(e),
            }
        }
    }

    /// The log of `utc_s` is written and closed: from now on it is a log like the others.
    pub fn end(&self, utc_s: u32) {
        let mut writing = self.shared.writing.lock().unwrap_or_else(PoisonError::into_inner);
        if *writing == Some(utc_s) {
            *writing = None;
        }
    }
}

impl LogStore for LogDir {
    fn list(&mut self) -> Result<Vec<LogFile>, LogStoreError> {
        let root = &self.shared.root;
        let dates = match std::fs::read_dir(root) {
            Ok(dates) => dates,
            // Not created yet: no log has begun.
            Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(Vec::new()),
            Err(e) => return Err(io_error(root, &e)),
        };
        let mut logs = Vec::new();
        for date in dates.flatten() {
            // A date directory that vanished or cannot be read has no logs to show.
            let Ok(files) = std::fs::read_dir(date.path()) else {
                continue;
            };
            for file in files.flatten() {
                let name = format!(
                    "{}/{}",
                    date.file_name().to_string_lossy(),
                    file.file_name().to_string_lossy()
                );
                let Some(utc_s) = parse_log_name(&name) else {
                    continue;
                };
                match file.metadata() {
                    Ok(meta) if meta.is_file() => logs.push(LogFile {
                        utc_s,
                        size: meta.len(),
                    }),
                    _ => {}
                }
            }
        }
        logs.sort();
        Ok(logs)
    }

    fn read_at(&mut self, utc_s: u32, offset: u64, buf: &mut [u8]) -> Result<usize, LogStoreError> {
        let path = self.path_of(utc_s);
        let file = match self.open.take() {
            Some((open_s, file)) if open_s == utc_s => file,
            _ => File::open(&path).map_err(|e| match e.kind() {
                io::ErrorKind::NotFound => LogStoreError::NotFound(log_name(utc_s)),
                _ => io_error(&path, &e),
            })?,
        };
        let mut n = 0;
        while n < buf.len() {
            match file.read_at(&mut buf[n..], offset + n as u64) {
                Ok(0) => break,
                Ok(k) => n += k,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(e) => return Err(io_error(&path, &e)),
            }
        }
        self.open = Some((utc_s, file));
        Ok(n)
    }

    fn erase(&mut self) -> Result<(), LogStoreError> {
        self.open = None;
        // Held throughout, so a log begun meanwhile is marked before it can be listed here.
        let shared = self.shared.clone();
        let guard = shared.writing.lock().unwrap_or_else(PoisonError::into_inner);
        let writing = *guard;
        let mut first_error = None;
        for log in self.list()? {
            if Some(log.utc_s) == writing {
                continue;
            }
            let path = self.path_of(log.utc_s);
            if let Err(e) = std::fs::remove_file(&path) {
                first_error.get_or_insert(io_error(&path, &e));
            }
            if let Some(dir) = path.parent() {
                // Only an empty date directory goes (the one being written into stays).
                let _ = std::fs::remove_dir(dir);
            }
        }
        first_error.map_or(Ok(()), Err)
    }
}

#[cfg(test)]
#[path = "log_store_tests.rs"]
mod tests;
