//! What MAVLink FTP reads from: the in-memory [`Vfs`] with the flight logs of a [`LogStore`]
//! mounted at [`LOG_DIR`], where PX4 keeps them: `LOG_DIR/YYYY-MM-DD/HH_MM_SS.ulg`, one directory
//! per date, each log read from the store at the offset asked (never whole). The logs are
//! read-only for clients (the Vfs refuses writes there, FileProtected). The vehicle's parameters
//! are kept here too, for `@PARAM/param.pck` (`param_file.rs`). Pure.

use super::param_pck::PackedParam;
use super::payload::{ErrorCode, ENOTDIR};
use super::vfs::{normalize, Entry, Vfs, LOG_DIR};
use crate::mav::crc32::crc32_part;
use crate::mav::logs::{log_dir_and_file, parse_log_name, LogFile, LogStore, LogStoreError, MemLogStore};

/// Bytes read at a time for a log's CRC.
const CRC_CHUNK: usize = 64 * 1024;

/// The served files: the Vfs and the log store.
#[derive(Debug)]
pub struct Storage {
    /// Metadata and the scratch area.
    pub vfs: Vfs,
    /// The flight logs.
    pub logs: Box<dyn LogStore>,
    /// Every parameter of the vehicle in wire order (name, value, default), as the link last
    /// learned them: what `@PARAM/param.pck` packs when it is opened.
    pub params: Vec<PackedParam>,
}

impl Default for Storage {
    fn default() -> Self {
        Self::new(Vfs::default(), Box::new(MemLogStore::default()))
    }
}

/// Where a normalised path points inside [`LOG_DIR`].
enum InLogs<'a> {
    /// The log directory itself.
    Root,
    /// A date directory, a log, or anything else below it (the part after `LOG_DIR/`).
    Below(&'a str),
}

fn in_logs(norm: &str) -> Option<InLogs<'_>> {
    match norm.strip_prefix(LOG_DIR)? {
        "" => Some(InLogs::Root),
        rest => rest.strip_prefix('/').map(InLogs::Below),
    }
}

fn store_error(e: LogStoreError) -> ErrorCode {
    match e {
        LogStoreError::NotFound(_) => ErrorCode::FileNotFound,
        LogStoreError::Io { .. } => ErrorCode::Fail,
    }
}

impl Storage {
    /// `vfs` with the logs of `logs` mounted at [`LOG_DIR`].
    pub fn new(vfs: Vfs, logs: Box<dyn LogStore>) -> Self {
        Self {
            vfs,
            logs,
            params: Vec::new(),
        }
    }

    fn logs(&mut self) -> Result<Vec<LogFile>, ErrorCode> {
        self.logs.list().map_err(store_error)
    }

    /// The log a path below [`LOG_DIR`] names, when it exists.
    fn log(&mut self, below: &str) -> Result<LogFile, ErrorCode> {
        let utc_s = parse_log_name(below).ok_or(ErrorCode::FileNotFound)?;
        let logs = self.logs()?;
        logs.into_iter()
            .find(|l| l.utc_s == utc_s)
            .ok_or(ErrorCode::FileNotFound)
    }

    /// The entries of the directory at `path`, in name order.
    pub fn list(&mut self, path: &str) -> Result<Vec<Entry>, ErrorCode> {
        let norm = normalize(path)?;
        let below = match in_logs(&norm) {
            None => return self.vfs.list(&norm),
            Some(InLogs::Root) => None,
            Some(InLogs::Below(below)) => Some(below),
        };
        let logs = self.logs()?;
        let mut entries = Vec::new();
        for log in &logs {
            let (date, file) = log_dir_and_file(log.utc_s);
            match below {
                None => entries.push(Entry::Dir(date)),
                Some(dir) if dir == date => entries.push(Entry::File(file, log.size as usize)),
                Some(other) if parse_log_name(other) == Some(log.utc_s) => return Err(ErrorCode::FailErrno(ENOTDIR)),
                Some(_) => {}
            }
        }
        entries.dedup();
        if below.is_some() && entries.is_empty() {
            return Err(ErrorCode::FileNotFound);
        }
        Ok(entries)
    }

    /// The size of the file at `path` [bytes]; FileNotFound for a directory or nothing.
    pub fn size(&mut self, path: &str) -> Result<u64, ErrorCode> {
        let norm = normalize(path)?;
        match in_logs(&norm) {
            None => Ok(self.vfs.read(&norm)?.len() as u64),
            Some(InLogs::Root) => Err(ErrorCode::FileNotFound),
            Some(InLogs::Below(below)) => Ok(self.log(below)?.size),
        }
    }

    /// Up to `max` bytes of the file at `path` from `offset`; Eof at or past its end.
    pub fn read_at(&mut self, path: &str, offset: u32, max: usize) -> Result<Vec<u8>, ErrorCode> {
        let norm = normalize(path)?;
        let below = match in_logs(&norm) {
            None => {
                let bytes = self.vfs.read(&norm)?;
                let start = offset as usize;
                if start >= bytes.len() {
                    return Err(ErrorCode::Eof);
                }
                return Ok(bytes[start..(start + max).min(bytes.len())].to_vec());
            }
            Some(InLogs::Root) => return Err(ErrorCode::FileNotFound),
            Some(InLogs::Below(below)) => below,
        };
        let utc_s = parse_log_name(below).ok_or(ErrorCode::FileNotFound)?;
        // One byte more than asked tells the end of the file from a read of nothing.
        let mut buf = vec![0u8; max + 1];
        let n = self
            .logs
            .read_at(utc_s, u64::from(offset), &mut buf)
            .map_err(store_error)?;
        if n == 0 {
            return Err(ErrorCode::Eof);
        }
        buf.truncate(n.min(max));
        Ok(buf)
    }

    /// CRC-32 of the file at `path` ([`crc32_part`] from 0, as PX4's CalcFileCRC32).
    pub fn crc32(&mut self, path: &str) -> Result<u32, ErrorCode> {
        let norm = normalize(path)?;
        let Some(InLogs::Below(below)) = in_logs(&norm) else {
            return self.vfs.crc32(&norm);
        };
        let utc_s = self.log(below)?.utc_s;
        let (mut crc, mut offset, mut buf) = (0, 0u64, vec![0u8; CRC_CHUNK]);
        loop {
            let n = self.logs.read_at(utc_s, offset, &mut buf).map_err(store_error)?;
            if n == 0 {
                return Ok(crc);
            }
            crc = crc32_part(&buf[..n], crc);
            offset += n as u64;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn storage() -> Storage {
        let mut logs = MemLogStore::default();
        logs.insert(1_767_261_600, (0..=255u8).cycle().take(1000).collect()); // 2026-01-01 10:00:00
        logs.insert(1_767_353_400, vec![7; 3]); // 2026-01-02 11:30:00
        logs.insert(1_767_355_200, vec![8; 5]); // 2026-01-02 12:00:00
        Storage::new(Vfs::default(), Box::new(logs))
    }

    #[test]
    fn logs_are_listed_by_date_as_px4_lays_them_out() {
        let mut s = storage();
        assert_eq!(
            s.list("/fs/microsd").unwrap(),
            vec![Entry::Dir("log".into())],
            "the mount point shows in its parent"
        );
        assert_eq!(
            s.list("/fs/microsd/log/").unwrap(),
            vec![Entry::Dir("2026-01-01".into()), Entry::Dir("2026-01-02".into())]
        );
        assert_eq!(
            s.list("/fs/microsd/log/2026-01-02").unwrap(),
            vec![
                Entry::File("11_30_00.ulg".into(), 3),
                Entry::File("12_00_00.ulg".into(), 5)
            ]
        );
        assert_eq!(s.list("/fs/microsd/log/2026-01-03"), Err(ErrorCode::FileNotFound));
        assert_eq!(
            s.list("/fs/microsd/log/2026-01-02/11_30_00.ulg"),
            Err(ErrorCode::FailErrno(ENOTDIR))
        );
        assert_eq!(Storage::default().list("/fs/microsd/log"), Ok(vec![]));
    }

    #[test]
    fn logs_read_at_any_offset_and_their_crc_covers_the_whole_file() {
        let mut s = storage();
        let path = "/fs/microsd/log/2026-01-01/10_00_00.ulg";
        assert_eq!(s.size(path), Ok(1000));
        assert_eq!(s.read_at(path, 998, 239), Ok(vec![230, 231]));
        assert_eq!(s.read_at(path, 300, 0), Ok(vec![]));
        assert_eq!(s.read_at(path, 1000, 239), Err(ErrorCode::Eof));
        let whole: Vec<u8> = (0..=255u8).cycle().take(1000).collect();
        assert_eq!(s.crc32(path), Ok(crc32_part(&whole, 0)));
        for missing in [
            "/fs/microsd/log/2026-01-01/10_00_01.ulg",
            "/fs/microsd/log/x",
            "/fs/microsd/log",
        ] {
            assert_eq!(s.size(missing), Err(ErrorCode::FileNotFound), "{missing}");
            assert!(s.read_at(missing, 0, 10).is_err(), "{missing}");
        }
        assert_eq!(s.size("/fs/microsd/log/2026-01-01"), Err(ErrorCode::FileNotFound));
    }
}
