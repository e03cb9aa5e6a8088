//! The in-memory part of the file system MAVLink FTP serves: read-only files the vehicle
//! publishes (component metadata under `/etc/extras`), the empty [`LOG_DIR`] where the flight
//! logs are mounted (`storage.rs`), and a writable scratch area under [`SCRATCH_ROOT`] (PX4 allows
//! writes only below `/fs/microsd/`) bounded in file bytes ([`SCRATCH_LIMIT_BYTES`]), in entries
//! ([`SCRATCH_ENTRY_LIMIT`] files and directories) and in the bytes of their paths
//! ([`SCRATCH_NAME_LIMIT_BYTES`]): past any bound a write or a create is refused with FailErrno
//! ENOSPC, as PX4 answers on a full card, so no client can grow the vehicle's memory. Paths are normalised before use: empty and `.` components are dropped, a
//! relative path starts at `/`, and a `..` component is refused (FileProtected), so no request
//! reaches anything but these nodes. Errors are the NAK codes the server sends. Pure.

use std::collections::{BTreeMap, BTreeSet};

use thiserror::Error;

use super::payload::{ErrorCode, EINVAL, EISDIR, ENOSPC, ENOTDIR, ENOTEMPTY};
use crate::mav::crc32::crc32_part;

/// The writable area: everything strictly below it except [`LOG_DIR`].
pub const SCRATCH_ROOT: &str = "/fs/microsd";
/// Where the flight logs are mounted (read-only for clients).
pub const LOG_DIR: &str = "/fs/microsd/log";
/// Bytes the scratch files may hold together, by default.
pub const SCRATCH_LIMIT_BYTES: usize = 1 << 20;
/// Files and directories the scratch area may hold together.
pub const SCRATCH_ENTRY_LIMIT: usize = 1024;
/// Bytes the paths of the scratch files and directories may take together.
pub const SCRATCH_NAME_LIMIT_BYTES: usize = 64 << 10;

/// One entry of a directory listing.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Entry {
    /// A directory and its name.
    Dir(String),
    /// A file, its name and size [bytes].
    File(String, usize),
}

/// A file the runtime could not publish.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum PublishError {
    /// Not a path a file can have (empty, `..`, the root).
    #[error("cannot publish {0:?}: not a file path")]
    InvalidPath(String),
    /// Inside the clients' scratch area.
    #[error("cannot publish {0:?}: inside the writable scratch area")]
    Scratch(String),
    /// A directory is there.
    #[error("cannot publish {0:?}: a directory is there")]
    Directory(String),
    /// Inside [`LOG_DIR`], whose files are the log store's.
    #[error("cannot publish {0:?}: the log directory shows the log store")]
    Logs(String),
}

/// `raw` as an absolute path without empty or `.` components; FileProtected for `..`.
pub fn normalize(raw: &str) -> Result<String, ErrorCode> {
    let mut parts = Vec::new();
    for part in raw.split('/') {
        match part {
            "" | "." => {}
            ".." => return Err(ErrorCode::FileProtected),
            p => parts.push(p),
        }
    }
    Ok(format!("/{}", parts.join("/")))
}

/// True when clients may write at the normalised `path`.
pub fn writable(path: &str) -> bool {
    let below = |root: &str| path.strip_prefix(root).is_some_and(|rest| rest.starts_with('/'));
    below(SCRATCH_ROOT) && path != LOG_DIR && !below(LOG_DIR)
}

/// The parent of a normalised path (`/` for a top-level one).
fn parent(path: &str) -> &str {
    match path.rfind('/') {
        Some(0) | None => "/",
        Some(i) => &path[..i],
    }
}

/// The in-memory file system.
#[derive(Debug, Clone, PartialEq)]
pub struct Vfs {
    /// Every file by normalised path.
    files: BTreeMap<String, Vec<u8>>,
    /// Directories that exist without files in them (made by clients, or fixed ones).
    dirs: BTreeSet<String>,
    /// Bytes the scratch files may hold together.
    scratch_limit: usize,
    /// Entries (files and directories) the scratch area may hold.
    entry_limit: usize,
    /// Bytes the paths of the scratch entries may take together.
    name_limit: usize,
}

impl Default for Vfs {
    fn default() -> Self {
        Self::new(SCRATCH_LIMIT_BYTES)
    }
}

impl Vfs {
    /// An empty file system with the scratch root and the log directory, the scratch area
    /// bounded to `scratch_limit` bytes.
    pub fn new(scratch_limit: usize) -> Self {
        Self {
            files: BTreeMap::new(),
            dirs: [SCRATCH_ROOT.to_string(), LOG_DIR.to_string()].into(),
            scratch_limit,
            entry_limit: SCRATCH_ENTRY_LIMIT,
            name_limit: SCRATCH_NAME_LIMIT_BYTES,
        }
    }

    /// This file system with at most `entries` scratch entries whose paths take at most
    /// `name_bytes` bytes together.
    pub fn with_entry_limits(mut self, entries: usize, name_bytes: usize) -> Self {
        self.entry_limit = entries;
        self.name_limit = name_bytes;
        self
    }

    /// Publishes a read-only file at `path` (replacing one there): component metadata.
    pub fn publish(&mut self, path: &str, bytes: Vec<u8>) -> Result<(), PublishError> {
        let invalid = || PublishError::InvalidPath(path.to_string());
        let norm = normalize(path).map_err(|_| invalid())?;
        if norm == "/" {
            return Err(invalid());
        }
        if writable(&norm) {
            return Err(PublishError::Scratch(path.to_string()));
        }
        if norm.starts_with(&format!("{LOG_DIR}/")) {
            return Err(PublishError::Logs(path.to_string()));
        }
        if self.is_dir(&norm) {
            return Err(PublishError::Directory(path.to_string()));
        }
        self.files.insert(norm, bytes);
        Ok(())
    }

    /// True when a directory is at the normalised `path`.
    pub fn is_dir(&self, path: &str) -> bool {
        if path == "/" || self.dirs.contains(path) {
            return true;
        }
        let prefix = format!("{path}/");
        let under = |key: Option<&String>| key.is_some_and(|k| k.starts_with(&prefix));
        under(self.files.range(prefix.clone()..).next().map(|(k, _)| k))
            || under(self.dirs.range(prefix.clone()..).next())
    }

    /// The bytes of the file at `path`; FileNotFound when no file is there.
    pub fn read(&self, path: &str) -> Result<&[u8], ErrorCode> {
        let norm = normalize(path)?;
        self.files.get(&norm).map(Vec::as_slice).ok_or(ErrorCode::FileNotFound)
    }

    /// CRC-32 of the file at `path` ([`crc32_part`] from 0, as PX4's CalcFileCRC32).
    pub fn crc32(&self, path: &str) -> Result<u32, ErrorCode> {
        Ok(crc32_part(self.read(path)?, 0))
    }

    /// The entries of the directory at `path`, in name order.
    pub fn list(&self, path: &str) -> Result<Vec<Entry>, ErrorCode> {
        let norm = normalize(path)?;
        if !self.is_dir(&norm) {
            return Err(if self.files.contains_key(&norm) {
                ErrorCode::FailErrno(ENOTDIR)
            } else {
                ErrorCode::FileNotFound
            });
        }
        let prefix = if norm == "/" {
            "/".to_string()
        } else {
            format!("{norm}/")
        };
        let mut entries: BTreeMap<&str, Entry> = BTreeMap::new();
        let keys = self.files.keys().chain(self.dirs.iter());
        for key in keys.filter(|k| k.starts_with(&prefix)) {
            let rest = &key[prefix.len()..];
            let name = rest.split('/').next().unwrap_or(rest);
            let entry = match self.files.get(key) {
                Some(bytes) if name == rest => Entry::File(name.to_string(), bytes.len()),
                _ => Entry::Dir(name.to_string()),
            };
            entries.entry(name).or_insert(entry);
        }
        Ok(entries.into_values().collect())
    }

    /// Bytes the scratch files hold.
    pub fn scratch_used(&self) -> usize {
        self.files
            .iter()
            .filter(|(k, _)| writable(k))
            .map(|(_, v)| v.len())
            .sum()
    }

    /// The scratch entries (files and directories made by clients) and the bytes of their paths.
    pub fn scratch_entries(&self) -> (usize, usize) {
        let files = self.files.keys().filter(|k| writable(k));
        let dirs = self.dirs.iter().filter(|k| writable(k));
        files.chain(dirs).fold((0, 0), |(n, bytes), k| (n + 1, bytes + k.len()))
    }

    /// FailErrno ENOSPC unless `more` entries whose paths take `name_bytes` more bytes fit.
    fn entries_fit(&self, more: usize, name_bytes: usize) -> Result<(), ErrorCode> {
        let (n, bytes) = self.scratch_entries();
        if n + more > self.entry_limit || bytes + name_bytes > self.name_limit {
            return Err(ErrorCode::FailErrno(ENOSPC));
        }
        Ok(())
    }

    /// `path` normalised when clients may write there, else FileProtected.
    fn writable_path(path: &str) -> Result<String, ErrorCode> {
        let norm = normalize(path)?;
        if writable(&norm) {
            Ok(norm)
        } else {
            Err(ErrorCode::FileProtected)
        }
    }

    /// Opens `path` for writing: creates it when missing (its directory must exist), empties it
    /// when `truncate` (CreateFile) or keeps it (OpenFileWO); returns the normalised path.
    pub fn open_write(&mut self, path: &str, truncate: bool) -> Result<String, ErrorCode> {
        let norm = Self::writable_path(path)?;
        if self.is_dir(&norm) {
            return Err(ErrorCode::FailErrno(EISDIR));
        }
        if !self.is_dir(parent(&norm)) {
            return Err(ErrorCode::FileNotFound);
        }
        if !self.files.contains_key(&norm) {
            self.entries_fit(1, norm.len())?;
        }
        let file = self.files.entry(norm.clone()).or_default();
        if truncate {
            file.clear();
        }
        Ok(norm)
    }

    /// Resizes the scratch file at `norm` to `len` bytes (zero-filled), within the byte limit.
    fn resize(&mut self, norm: &str, len: usize) -> Result<&mut Vec<u8>, ErrorCode> {
        let used = self.scratch_used();
        let old = self.files.get(norm).ok_or(ErrorCode::FileNotFound)?.len();
        if len > old && used - old + len > self.scratch_limit {
            return Err(ErrorCode::FailErrno(ENOSPC));
        }
        let file = self.files.get_mut(norm).ok_or(ErrorCode::FileNotFound)?;
        file.resize(len, 0);
        Ok(file)
    }

    /// Writes `data` at `offset` of the scratch file at `path` (zero-filled up to it).
    pub fn write(&mut self, path: &str, offset: usize, data: &[u8]) -> Result<usize, ErrorCode> {
        let norm = Self::writable_path(path)?;
        let old = self.files.get(&norm).ok_or(ErrorCode::FileNotFound)?.len();
        let end = offset.checked_add(data.len()).ok_or(ErrorCode::FailErrno(EINVAL))?;
        let file = self.resize(&norm, end.max(old))?;
        file[offset..end].copy_from_slice(data);
        Ok(data.len())
    }

    /// Truncates (or zero-extends) the scratch file at `path` to `len` bytes.
    pub fn truncate(&mut self, path: &str, len: usize) -> Result<(), ErrorCode> {
        let norm = Self::writable_path(path)?;
        if self.is_dir(&norm) {
            return Err(ErrorCode::FailErrno(EISDIR));
        }
        self.resize(&norm, len).map(|_| ())
    }

    /// Removes the scratch file at `path`.
    pub fn remove_file(&mut self, path: &str) -> Result<(), ErrorCode> {
        let norm = Self::writable_path(path)?;
        if self.files.remove(&norm).is_some() {
            Ok(())
        } else if self.is_dir(&norm) {
            Err(ErrorCode::FailErrno(EISDIR))
        } else {
            Err(ErrorCode::FileNotFound)
        }
    }

    /// Creates the scratch directory `path` (its parent must exist).
    pub fn create_dir(&mut self, path: &str) -> Result<(), ErrorCode> {
        let norm = Self::writable_path(path)?;
        if self.is_dir(&norm) || self.files.contains_key(&norm) {
            return Err(ErrorCode::FileExists);
        }
        if !self.is_dir(parent(&norm)) {
            return Err(ErrorCode::FileNotFound);
        }
        self.entries_fit(1, norm.len())?;
        self.dirs.insert(norm);
        Ok(())
    }

    /// Removes the empty scratch directory `path`.
    pub fn remove_dir(&mut self, path: &str) -> Result<(), ErrorCode> {
        let norm = Self::writable_path(path)?;
        if !self.is_dir(&norm) {
            return Err(if self.files.contains_key(&norm) {
                ErrorCode::FailErrno(ENOTDIR)
            } else {
                ErrorCode::FileNotFound
            });
        }
        if !self.list(&norm)?.is_empty() {
            return Err(ErrorCode::FailErrno(ENOTEMPTY));
        }
        self.dirs.remove(&norm);
        Ok(())
    }

    /// Renames the scratch file or directory `from` to `to` (a file there is replaced).
    pub fn rename(&mut self, from: &str, to: &str) -> Result<(), ErrorCode> {
        let (from, to) = (Self::writable_path(from)?, Self::writable_path(to)?);
        let is_file = self.files.contains_key(&from);
        if !is_file && !self.is_dir(&from) {
            return Err(ErrorCode::FileNotFound);
        }
        if !self.is_dir(parent(&to)) {
            return Err(ErrorCode::FileNotFound);
        }
        if to.starts_with(&format!("{from}/")) {
            return Err(ErrorCode::FailErrno(EINVAL));
        }
        if self.is_dir(&to) {
            return Err(ErrorCode::FailErrno(EISDIR));
        }
        // A longer name costs its extra bytes in every entry moved.
        let prefix = format!("{from}/");
        let moving = 1 + if is_file {
            0
        } else {
            let below = |k: &&String| k.starts_with(&prefix);
            self.files.keys().filter(below).count() + self.dirs.iter().filter(below).count()
        };
        let replaced = self.files.get(&to).map_or(0, |_| to.len());
        let longer = to.len().saturating_sub(from.len()) * moving;
        self.entries_fit(0, longer.saturating_sub(replaced))?;
        if is_file {
            if let Some(bytes) = self.files.remove(&from) {
                self.files.insert(to, bytes);
            }
            return Ok(());
        }
        let moved = |k: &String| format!("{to}{}", &k[from.len()..]);
        let files: Vec<String> = self.files.keys().filter(|k| k.starts_with(&prefix)).cloned().collect();
        for k in files {
            if let Some(v) = self.files.remove(&k) {
                self.files.insert(moved(&k), v);
            }
        }
        let dirs: Vec<String> = self
            .dirs
            .iter()
            .filter(|k| **k == from || k.starts_with(&prefix))
            .cloned()
            .collect();
        for k in dirs {
            self.dirs.remove(&k);
            self.dirs.insert(moved(&k));
        }
        Ok(())
    }
}

#[cfg(test)]
#[path = "vfs_tests.rs"]
mod tests;
