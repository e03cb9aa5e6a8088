//! MAVLink FTP (FILE_TRANSFER_PROTOCOL, msg 110) as PX4 serves it, over an in-memory file
//! system with the flight logs mounted from a log store. Pure.
//!
//! # Layout
//! - `payload.rs`: [`Payload`] (the 251-byte payload), [`Opcode`], [`ErrorCode`].
//! - `vfs.rs`: [`Vfs`], the files in memory: read-only metadata, a bounded scratch area.
//! - `storage.rs`: [`Storage`], what is served: the Vfs and the logs of a
//!   [`LogStore`](crate::mav::logs::LogStore) at [`LOG_DIR`].
//! - `server.rs`: [`FtpServer`], one link's sessions, replies, retransmissions and bursts.

mod payload;
mod server;
mod storage;
mod vfs;

pub use payload::{ErrorCode, Opcode, Payload, DATA_MAX, PAYLOAD_LEN};
pub use server::{FtpServer, MAX_SESSIONS, SESSION_IDLE_S};
pub use storage::Storage;
pub use vfs::{normalize, writable, Entry, PublishError, Vfs, LOG_DIR, SCRATCH_LIMIT_BYTES, SCRATCH_ROOT};
