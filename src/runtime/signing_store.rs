//! The signing key file of `--signing-key FILE` and the timestamp kept beside it
//! (`FILE.timestamp`), and the wall clock of signing (docs/mavlink.md §10). Runtime layer: files and
//! `SystemTime`; the signing rules are `mav::signing`'s.

use std::io::Write;
use std::path::{Path, PathBuf};

use thiserror::Error;

use crate::mav::signing::{timestamp_from_unix_us, KeyError, SigningKey};

/// Why the key or timestamp file could not be read.
#[derive(Debug, Error)]
pub enum SigningFileError {
    /// The key file exists but cannot be read.
    #[error("--signing-key {path}: {source}")]
    Read {
        /// File.
        path: String,
        /// Cause.
        source: std::io::Error,
    },
    /// The key file holds no usable key.
    #[error("--signing-key {path}: {source}")]
    Key {
        /// File.
        path: String,
        /// Cause.
        source: KeyError,
    },
    /// The timestamp file is not a decimal number.
    #[error(
        "--signing-key: {path} should hold one decimal signing timestamp (10 µs units since 2015), found {found:?}"
    )]
    Timestamp {
        /// File.
        path: String,
        /// What it holds (at most 40 characters).
        found: String,
    },
}

/// The signing timestamp of the wall clock now [10 µs since 2015-01-01 UTC].
pub fn signing_now() -> u64 {
    let unix_us = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_micros());
    timestamp_from_unix_us(unix_us)
}

/// Where the key and its timestamp live.
#[derive(Debug, Clone)]
pub struct SigningStore {
    key_path: PathBuf,
}

impl SigningStore {
    /// The store of key file `key_path` (it need not exist yet: SETUP_SIGNING creates it).
    pub fn new(key_path: PathBuf) -> Self {
        Self { key_path }
    }

    /// The timestamp file beside the key.
    pub fn timestamp_path(&self) -> PathBuf {
        let mut name = self.key_path.clone().into_os_string();
        name.push(".timestamp");
        PathBuf::from(name)
    }

    /// The key (`None` when the file does not exist) and the persisted timestamp (0 when none).
    pub fn load(&self) -> Result<(Option<SigningKey>, u64), SigningFileError> {
        let shown = |p: &Path| p.display().to_string();
        let key = match std::fs::read(&self.key_path) {
            Ok(bytes) => Some(
                SigningKey::from_file_contents(&bytes).map_err(|source| SigningFileError::Key {
                    path: shown(&self.key_path),
                    source,
                })?,
            ),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
            Err(source) => {
                return Err(SigningFileError::Read {
                    path: shown(&self.key_path),
                    source,
                })
            }
        };
        let ts_path = self.timestamp_path();
        let timestamp = match std::fs::read_to_string(&ts_path) {
            Ok(text) => text.trim().parse::<u64>().map_err(|_| SigningFileError::Timestamp {
                path: shown(&ts_path),
                found: text.chars().take(40).collect(),
            })?,
            Err(_) => 0,
        };
        Ok((key, timestamp))
    }

    /// Writes `key` as 32 bytes readable by the owner only, or removes the file when signing
    /// was turned off (`None`).
    pub fn save_key(&self, key: Option<&SigningKey>) -> std::io::Result<()> {
        match key {
            Some(key) => write_private(&self.key_path, key.bytes()),
            None => match std::fs::remove_file(&self.key_path) {
                Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(e),
                _ => Ok(()),
            },
        }
    }

    /// Persists `timestamp` [10 µs] (written beside, then renamed over the old one).
    pub fn save_timestamp(&self, timestamp: u64) -> std::io::Result<()> {
        write_private(&self.timestamp_path(), format!("{timestamp}\n").as_bytes())
    }
}

/// Writes `bytes` to a sibling temporary file (mode 0600 on Unix), syncs it and renames it over
/// `path`, so a crash leaves either the old or the new content.
fn write_private(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".tmp");
    let tmp = PathBuf::from(tmp);
    let mut options = std::fs::OpenOptions::new();
    options.write(true).create(true).truncate(true);
    #[cfg(unix)]
    std::os::unix::fs::OpenOptionsExt::mode(&mut options, 0o600);
    let mut file = options.open(&tmp)?;
    file.write_all(bytes)?;
    file.sync_all()?;
    std::fs::rename(&tmp, path)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("rotorpilot-signing-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn a_missing_key_is_none_and_a_saved_one_loads_back_with_its_timestamp() {
        let d = dir("roundtrip");
        let store = SigningStore::new(d.join("key.bin"));
        assert_eq!(store.load().unwrap(), (None, 0));
        let key = SigningKey::from_bytes([5; 32]);
        store.save_key(Some(&key)).unwrap();
        store.save_timestamp(123_456).unwrap();
        assert_eq!(store.load().unwrap(), (Some(key), 123_456));
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            let mode = std::fs::metadata(d.join("key.bin")).unwrap().permissions().mode();
            assert_eq!(mode & 0o077, 0, "key readable by others: {mode:o}");
        }
        store.save_key(None).unwrap();
        assert_eq!(store.load().unwrap().0, None);
    }

    #[test]
    fn bad_files_name_the_file() {
        let d = dir("bad");
        let store = SigningStore::new(d.join("key"));
        std::fs::write(d.join("key"), b"").unwrap();
        let e = store.load().unwrap_err().to_string();
        assert!(e.contains("key") && e.contains("empty"), "{e}");
        std::fs::write(d.join("key"), b"passphrase\n").unwrap();
        std::fs::write(d.join("key.timestamp"), b"soon").unwrap();
        let e = store.load().unwrap_err().to_string();
        assert!(e.contains("key.timestamp") && e.contains("soon"), "{e}");
    }

    #[test]
    fn the_clock_is_past_2025() {
        // 2025-01-01 is 10 years (3653 days) after the signing epoch.
        assert!(signing_now() > 3653 * 86_400 * 100_000);
    }
}
