//! Flight logs in PX4's ULog format: what `rotorpilot run --log`, `sim --out` and `fly --log`
//! write, PX4 Flight Review, PlotJuggler and pyulog read, and `rotorpilot estimate` replays.
//! Pure: bytes are built in memory; the runtime writes them to files off the tick thread.
//!
//! # Layout
//!
//! - [`encoder`]: the file header and each ULog message as bytes.
//! - [`topics`]: the logged topics, their PX4 names and fields, and this project's own.
//! - [`profile`]: how often each topic is logged (default and full profiles).
//! - [`recorder`]: one flight log: definitions, then each tick's due records, strings, changes.
//! - [`mode`]: when `run` writes a flight log (PX4's `SDLOG_MODE`).
//!
//! Reading a ULog back (`estimate`) is `estimation::ulog_log`'s, with px4-ulog's parser.

pub mod encoder;
pub mod log_mode;
pub mod profile;
pub mod recorder;
pub mod topics;

pub use encoder::ParamValue;
pub use log_mode::{LogMode, LogSchedule};
pub use profile::Profile;
pub use recorder::{micros, LogInfo, Recorder, RecorderSetup};
pub use topics::Topic;
