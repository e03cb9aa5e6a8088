//! The vehicle's flight logs and the MAVLink log protocol (LOG_REQUEST_LIST, LOG_REQUEST_DATA,
//! LOG_REQUEST_END, LOG_ERASE) as PX4 serves them. Pure.
//!
//! # Layout
//! - `name.rs`: PX4's log names (`YYYY-MM-DD/HH_MM_SS.ulg`, UTC), the times they stand for, and
//!   the logger's announcement of a new log.
//! - `store.rs`: [`LogStore`], the interface to the logs (list, read at an offset, erase), and
//!   [`MemLogStore`], logs in memory.
//! - `server.rs`: [`LogServer`], one link's log protocol state: requests in, LOG_ENTRY and
//!   LOG_DATA out one at a time.

mod name;
mod server;
mod store;

pub use name::{log_dir_and_file, log_name, logger_announcement, parse_log_name};
pub use server::{LogRequest, LogServer, LOG_DATA_LEN};
pub use store::{LogFile, LogStore, LogStoreError, MemLogStore};
