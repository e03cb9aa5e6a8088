//! `@PARAM/param.pck` as a file an FTP session holds open: opened for reading, the packed
//! parameters as they were at the open (a snapshot, so that a parameter set during the download
//! cannot change bytes already sent or shift later ones); opened for writing (CreateFile,
//! OpenFileWO), the bytes of an upload, which is read and applied when its session is terminated.
//! Pure.

use super::param_pck::{encode, PackedParam, Query};
use super::payload::{ErrorCode, DATA_MAX, EINVAL, ENOSPC};

/// Largest upload [bytes]: the header gives the file's length in 16 bits.
pub const UPLOAD_MAX_BYTES: usize = u16::MAX as usize;

/// The packed parameter file of one session.
#[derive(Debug, Clone, PartialEq)]
pub enum ParamFile {
    /// A download: the whole file as it was at the open.
    Snapshot(Vec<u8>),
    /// An upload: the bytes written, from offset 0 without a gap.
    Upload(Vec<u8>),
}

impl ParamFile {
    /// The packed file of `params` (the vehicle's, in wire order) as `path`'s query asks for it,
    /// padded for reads of one FTP frame; FailErrno EINVAL for a query that asks for nothing.
    pub fn open_read(path: &str, params: &[PackedParam]) -> Result<Self, ErrorCode> {
        encode(params, Query::of(path), DATA_MAX)
            .map(Self::Snapshot)
            .map_err(|_| ErrorCode::FailErrno(EINVAL))
    }

    /// Size of the file [bytes].
    pub fn size(&self) -> usize {
        match self {
            Self::Snapshot(bytes) | Self::Upload(bytes) => bytes.len(),
        }
    }

    /// Up to `max` bytes from `offset` of a download; Eof at or past its end; an upload is not
    /// read (FailErrno EINVAL, as PX4).
    pub fn read(&self, offset: u32, max: usize) -> Result<Vec<u8>, ErrorCode> {
        let Self::Snapshot(bytes) = self else {
            return Err(ErrorCode::FailErrno(EINVAL));
        };
        let start = offset as usize;
        if start >= bytes.len() {
            return Err(ErrorCode::Eof);
        }
        Ok(bytes[start..(start + max).min(bytes.len())].to_vec())
    }

    /// Writes `data` at `offset` of an upload; returns the bytes written. A repeated chunk is
    /// written again; one past the end would leave a gap (FailErrno EINVAL), one past
    /// [`UPLOAD_MAX_BYTES`] is FailErrno ENOSPC; a download is FileProtected.
    pub fn write(&mut self, offset: u32, data: &[u8]) -> Result<usize, ErrorCode> {
        let Self::Upload(bytes) = self else {
            return Err(ErrorCode::FileProtected);
        };
        let start = offset as usize;
        if start > bytes.len() {
            return Err(ErrorCode::FailErrno(EINVAL));
        }
        let end = start + data.len();
        if end > UPLOAD_MAX_BYTES {
            return Err(ErrorCode::FailErrno(ENOSPC));
        }
        bytes.resize(end.max(bytes.len()), 0);
        bytes[start..end].copy_from_slice(data);
        Ok(data.len())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mav::ftp::param_pck::PackedValue;

    #[test]
    fn a_download_reads_the_snapshot_and_refuses_writes() {
        let one = [PackedParam {
            name: "MPC_Z_P".into(),
            value: PackedValue::Float(1.0),
            default: PackedValue::Float(1.0),
        }];
        let mut file = ParamFile::open_read("@PARAM/param.pck", &one).unwrap();
        assert_eq!(file.size(), 6 + 2 + 7 + 4);
        assert_eq!(file.read(0, 2), Ok(vec![0x1B, 0x67]));
        assert_eq!(file.read(15, 239), Ok(1f32.to_le_bytes().to_vec()));
        assert_eq!(file.read(19, 239), Err(ErrorCode::Eof));
        assert_eq!(file.write(0, b"x"), Err(ErrorCode::FileProtected));
        assert_eq!(
            ParamFile::open_read("@PARAM/param.pck?start=1", &one),
            Err(ErrorCode::FailErrno(EINVAL))
        );
    }

    #[test]
    fn an_upload_grows_without_gaps_and_within_its_bound() {
        let mut file = ParamFile::Upload(Vec::new());
        assert_eq!(file.write(0, b"abcd"), Ok(4));
        assert_eq!(file.write(0, b"abcd"), Ok(4), "a repeated chunk");
        assert_eq!(file.write(4, b"ef"), Ok(2));
        assert_eq!(file.write(7, b"g"), Err(ErrorCode::FailErrno(EINVAL)), "a gap");
        assert_eq!(file, ParamFile::Upload(b"abcdef".to_vec()));
        assert_eq!(file.read(0, 10), Err(ErrorCode::FailErrno(EINVAL)));
        let at = (UPLOAD_MAX_BYTES - 6) as u32;
        let mut full = ParamFile::Upload(vec![0; UPLOAD_MAX_BYTES - 6]);
        assert_eq!(full.write(at, &[1; 6]), Ok(6));
        assert_eq!(full.write(at + 6, &[1]), Err(ErrorCode::FailErrno(ENOSPC)));
    }
}
