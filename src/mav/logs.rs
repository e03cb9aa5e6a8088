//! The MAVLink log protocol as PX4 answers it with an empty log directory: LOG_REQUEST_LIST gets
//! one LOG_ENTRY with `num_logs` 0 (PX4's `MavlinkLogHandler` "return an empty list"), so
//! MAVSDK's `LogFiles.get_entries` (NO_LOGFILES) and MAVProxy's `log list` end at once instead
//! of waiting for entries. This vehicle writes no on-board logs yet (its flight logs are the
//! runtime's `--log` files); LOG_REQUEST_DATA and LOG_REQUEST_END name no log and get nothing,
//! as PX4 ignores a request for a log it does not have. Pure.

use mavlink::dialects::common::{MavMessage, LOG_ENTRY_DATA};

/// The answer to LOG_REQUEST_LIST: the empty list.
pub fn log_list() -> MavMessage {
    MavMessage::LOG_ENTRY(LOG_ENTRY_DATA {
        time_utc: 0,
        size: 0,
        id: 0,
        num_logs: 0,
        last_log_num: 0,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_list_is_one_empty_entry() {
        let MavMessage::LOG_ENTRY(e) = log_list() else {
            panic!("not a LOG_ENTRY")
        };
        assert_eq!((e.num_logs, e.last_log_num, e.id, e.size), (0, 0, 0, 0));
    }
}
