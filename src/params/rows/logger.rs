//! The flight logs: when `rotorpilot run` writes a ULog file (PX4's `SDLOG_MODE`).

use crate::params::ParamDef;
use crate::ulog::LogMode;

/// When to log (index 129, after the mission group).
pub(super) static LOGGER: &[ParamDef] = &[row!(
    "SDLOG_MODE",
    Int32,
    [-1.0, 4.0],
    "",
    Logger,
    "When run writes its ULog flight logs (read at start, as PX4 reads it at boot; PX4's 3, while RC AUX1 > 30 %, is refused: no RC here)",
    action LogMode log_mode
)];
