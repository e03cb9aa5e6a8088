//! MAVLink FTP (FILE_TRANSFER_PROTOCOL, msg 110) as PX4 serves it, over an in-memory file
//! system. Pure.
//!
//! # Layout
//! - `payload.rs`: [`Payload`] (the 251-byte payload), [`Opcode`], [`ErrorCode`].
//! - `vfs.rs`: [`Vfs`], the served files: read-only metadata and logs, a bounded scratch area.
//! - `server.rs`: [`FtpServer`], one link's sessions, replies, retransmissions and bursts.

mod payload;
mod server;
mod vfs;

pub use payload::{ErrorCode, Opcode, Payload, DATA_MAX, PAYLOAD_LEN};
pub use server::{FtpServer, MAX_SESSIONS, SESSION_IDLE_S};
pub use vfs::{normalize, writable, Entry, PublishError, Vfs, LOG_DIR, SCRATCH_LIMIT_BYTES, SCRATCH_ROOT};
