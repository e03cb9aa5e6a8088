//! MAVLink FTP (FILE_TRANSFER_PROTOCOL, msg 110) as PX4 serves it (or with sessions numbered as
//! ArduPilot numbers them), over an in-memory file system with the flight logs mounted from a log
//! store and the parameters as `@PARAM/param.pck`. Pure.
//!
//! # Layout
//! - `payload.rs`: [`Payload`] (the 251-byte payload), [`Opcode`], [`ErrorCode`].
//! - `vfs.rs`: [`Vfs`], the files in memory: read-only metadata, a bounded scratch area.
//! - `storage.rs`: [`Storage`], what is served: the Vfs and the logs of a
//!   [`LogStore`](crate::mav::logs::LogStore) at [`LOG_DIR`].
//! - `param_pck.rs`: ArduPilot's packed parameter format ([`encode`], [`decode`],
//!   [`parse_upload`]).
//! - `param_file.rs`: [`ParamFile`], `@PARAM/param.pck` as a session holds it (snapshot, upload).
//! - `session_rule.rs`: [`SessionRule`], how sessions are numbered: PX4's way (the server's
//!   slot) or ArduPilot's (the client's number, one file open at a time).
//! - `server.rs`: [`FtpServer`], one link's sessions, replies, retransmissions and bursts.

mod param_file;
mod param_pck;
mod payload;
mod server;
mod session_rule;
mod storage;
mod vfs;

pub use param_file::{ParamFile, UPLOAD_MAX_BYTES};
pub use param_pck::{
    decode, encode, is_param_path, parse_upload, PackedEntry, PackedFile, PackedParam, PackedValue, PckError, Query,
    MAGIC, MAGIC_WITH_DEFAULTS, PARAM_FILE,
};
pub use payload::{ErrorCode, Opcode, Payload, DATA_MAX, EINVAL, PAYLOAD_LEN};
pub use server::{FtpServer, ParamUpload, MAX_SESSIONS, SESSION_IDLE_S};
pub use session_rule::{SessionRule, ARDUPILOT_TAKEOVER_S};
pub use storage::Storage;
pub use vfs::{
    normalize, writable, Entry, PublishError, Vfs, LOG_DIR, SCRATCH_ENTRY_LIMIT, SCRATCH_LIMIT_BYTES,
    SCRATCH_NAME_LIMIT_BYTES, SCRATCH_ROOT,
};
