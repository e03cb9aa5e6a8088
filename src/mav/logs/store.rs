//! The flight logs the vehicle serves, behind a small interface the link uses for the log
//! protocol and MAVLink FTP alike: list them, read bytes at an offset, erase them. The runtime
//! implements it over `--log DIR`'s `log/` directory (`runtime::log_store`), where logs can be
//! tens of MB and are never held in memory; [`MemLogStore`] holds them in memory for tests and
//! for a vehicle without `--log` (no logs). A log is known by its UTC time (its name,
//! [`log_name`](super::log_name)); the one being written is listed with the size it has, and
//! erasing never removes it. Pure.

use std::collections::BTreeMap;

use thiserror::Error;

use super::name::log_name;

/// One log: its time and size.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub struct LogFile {
    /// UTC time at arming [s since 1970]; also its name ([`log_name`]).
    pub utc_s: u32,
    /// Size now [bytes].
    pub size: u64,
}

/// Why the store could not answer.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum LogStoreError {
    /// No log of that time.
    #[error("no log {0}")]
    NotFound(String),
    /// The storage failed (a file system error, with the path).
    #[error("log store {path}: {message}")]
    Io {
        /// What could not be read or removed.
        path: String,
        /// The error.
        message: String,
    },
}

/// Where the vehicle's flight logs are kept.
pub trait LogStore: Send + std::fmt::Debug {
    /// Every log, oldest first.
    fn list(&mut self) -> Result<Vec<LogFile>, LogStoreError>;

    /// Reads bytes of the log of `utc_s` from `offset` [bytes] into `buf`; how many were read
    /// (0 at or past its end).
    fn read_at(&mut self, utc_s: u32, offset: u64, buf: &mut [u8]) -> Result<usize, LogStoreError>;

    /// Deletes every log but the one being written.
    fn erase(&mut self) -> Result<(), LogStoreError>;
}

/// Logs in memory.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct MemLogStore {
    logs: BTreeMap<u32, Vec<u8>>,
    writing: Option<u32>,
}

impl MemLogStore {
    /// Adds (or replaces) the log of `utc_s` with `bytes`.
    pub fn insert(&mut self, utc_s: u32, bytes: Vec<u8>) {
        self.logs.insert(utc_s, bytes);
    }

    /// Marks the log of `utc_s` as being written (`None`: none is).
    pub fn set_writing(&mut self, utc_s: Option<u32>) {
        self.writing = utc_s;
    }
}

/// Logs from (UTC time [s since 1970], bytes) pairs; none being written.
impl FromIterator<(u32, Vec<u8>)> for MemLogStore {
    fn from_iter<I: IntoIterator<Item = (u32, Vec<u8>)>>(logs: I) -> Self {
        Self {
            logs: logs.into_iter().collect(),
            writing: None,
        }
    }
}

impl LogStore for MemLogStore {
    fn list(&mut self) -> Result<Vec<LogFile>, LogStoreError> {
        Ok(self
            .logs
            .iter()
            .map(|(utc_s, bytes)| LogFile {
                utc_s: *utc_s,
                size: bytes.len() as u64,
            })
            .collect())
    }

    fn read_at(&mut self, utc_s: u32, offset: u64, buf: &mut [u8]) -> Result<usize, LogStoreError> {
        let bytes = self
            .logs
            .get(&utc_s)
            .ok_or_else(|| LogStoreError::NotFound(log_name(utc_s)))?;
        let start = usize::try_from(offset).unwrap_or(usize::MAX).min(bytes.len());
        let n = buf.len().min(bytes.len() - start);
        buf[..n].copy_from_slice(&bytes[start..start + n]);
        Ok(n)
    }

    fn erase(&mut self) -> Result<(), LogStoreError> {
        let writing = self.writing;
        self.logs.retain(|utc_s, _| Some(*utc_s) == writing);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn memory_logs_list_read_and_erase_all_but_the_one_being_written() {
        let mut store = MemLogStore::from_iter([(20, vec![4, 5]), (10, vec![1, 2, 3])]);
        store.insert(30, vec![6]);
        let sizes: Vec<_> = store.list().unwrap().iter().map(|l| (l.utc_s, l.size)).collect();
        assert_eq!(sizes, vec![(10, 3), (20, 2), (30, 1)], "oldest first");
        let mut buf = [0u8; 4];
        assert_eq!(store.read_at(10, 1, &mut buf), Ok(2));
        assert_eq!(&buf[..2], &[2, 3]);
        assert_eq!(store.read_at(10, 3, &mut buf), Ok(0));
        assert_eq!(store.read_at(10, u64::MAX, &mut buf), Ok(0));
        assert!(matches!(
            store.read_at(11, 0, &mut buf),
            Err(LogStoreError::NotFound(_))
        ));
        store.set_writing(Some(30));
        store.erase().unwrap();
        assert_eq!(store.list().unwrap(), vec![LogFile { utc_s: 30, size: 1 }]);
    }
}
