//! Idempotent command retransmissions (docs/mavlink.md §3.1): a COMMAND_LONG/INT that changes state,
//! repeated within [`DUPLICATE_WINDOW_S`] (same sender, command and seven parameters bit for
//! bit), gets the cached result and is not executed again; a repeat arriving while the first is
//! still being executed is dropped. Only ACCEPTED results are remembered: a refusal changed
//! nothing, so a repeat is simply judged again, and one sent after the state changed (OFFBOARD
//! once setpoints stream, failure injection once `SYS_FAILURE_EN` is set) gets the current answer.
//!
//! Commands that only ask for information ([`is_information_request`]: REQUEST_MESSAGE,
//! GET_HOME_POSITION, …) bypass the cache: answering one again costs nothing and changes
//! nothing, and a client asking twice (MAVSDK asks for AUTOPILOT_VERSION twice, 0.5 s apart)
//! wants the message each time, not a bare ACK. Pure: the caller passes the time.

use std::collections::HashMap;

use mavlink::dialects::ardupilotmega::{MavCmd, MavResult, COMMAND_LONG_DATA};
use mavlink::MavHeader;

/// How long a result is remembered [s].
pub const DUPLICATE_WINDOW_S: f64 = 3.0;
/// Most commands remembered at once (a flood of distinct commands forgets the oldest first).
pub const MAX_REMEMBERED: usize = 1024;

/// True for commands that only ask for information and have no side effect: each
/// transmission is answered in full (the ACK and the requested message), never from the cache.
/// Every other command may change state, so its retransmissions are answered from the cache.
// Most of the dedicated REQUEST_* commands are deprecated for REQUEST_MESSAGE; clients still send them.
#[allow(deprecated)]
pub fn is_information_request(command: MavCmd) -> bool {
    matches!(
        command,
        MavCmd::MAV_CMD_REQUEST_MESSAGE
            | MavCmd::MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES
            | MavCmd::MAV_CMD_REQUEST_PROTOCOL_VERSION
            | MavCmd::MAV_CMD_GET_HOME_POSITION
            | MavCmd::MAV_CMD_GET_MESSAGE_INTERVAL
            | MavCmd::MAV_CMD_REQUEST_CAMERA_INFORMATION
            | MavCmd::MAV_CMD_REQUEST_CAMERA_SETTINGS
            | MavCmd::MAV_CMD_REQUEST_STORAGE_INFORMATION
            | MavCmd::MAV_CMD_REQUEST_CAMERA_CAPTURE_STATUS
            | MavCmd::MAV_CMD_REQUEST_CAMERA_IMAGE_CAPTURE
            | MavCmd::MAV_CMD_REQUEST_FLIGHT_INFORMATION
            | MavCmd::MAV_CMD_REQUEST_VIDEO_STREAM_INFORMATION
            | MavCmd::MAV_CMD_REQUEST_VIDEO_STREAM_STATUS
    )
}

/// Identity of one command transmission.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct CommandKey {
    sender: (u32, u8),
    command: u32,
    params: [u32; 7],
    /// An information request ([`is_information_request`]): never cached.
    information: bool,
}

impl CommandKey {
    /// Key of `cmd` from `sender`.
    pub fn new(sender: &MavHeader, cmd: &COMMAND_LONG_DATA) -> Self {
        let p = [
            cmd.param1, cmd.param2, cmd.param3, cmd.param4, cmd.param5, cmd.param6, cmd.param7,
        ];
        Self {
            sender: (sender.system_id, sender.component_id),
            command: cmd.command as u32,
            params: p.map(f32::to_bits),
            information: is_information_request(cmd.command),
        }
    }
}

/// What to do with an incoming command.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Seen {
    /// First transmission: execute it.
    New,
    /// Still being executed: drop the repeat.
    InProgress,
    /// Answered already: send this result again.
    Answered(MavResult),
}

/// Results of recent commands.
#[derive(Debug, Default)]
pub struct DuplicateCache {
    entries: HashMap<CommandKey, (f64, Option<MavResult>)>,
}

impl DuplicateCache {
    /// Looks `key` up at time `now_s` [s]; a new key is recorded as in progress. An
    /// information request is always [`Seen::New`] and never recorded.
    pub fn check(&mut self, key: CommandKey, now_s: f64) -> Seen {
        self.entries.retain(|_, (t, _)| now_s - *t < DUPLICATE_WINDOW_S);
        if key.information {
            return Seen::New;
        }
        match self.entries.get(&key) {
            Some((_, Some(result))) => Seen::Answered(*result),
            Some((_, None)) => Seen::InProgress,
            None => {
                if self.entries.len() >= MAX_REMEMBERED {
                    let oldest = self
                        .entries
                        .iter()
                        .min_by(|a, b| a.1 .0.total_cmp(&b.1 .0))
                        .map(|(k, _)| *k);
                    if let Some(oldest) = oldest {
                        self.entries.remove(&oldest);
                    }
                }
                self.entries.insert(key, (now_s, None));
                Seen::New
            }
        }
    }

    /// Records the result of `key`: kept when ACCEPTED, forgotten for a refusal (and for an
    /// information request, which is answered afresh every time).
    pub fn answered(&mut self, key: CommandKey, result: MavResult, now_s: f64) {
        if result == MavResult::MAV_RESULT_ACCEPTED && !key.information {
            self.entries.insert(key, (now_s, Some(result)));
        } else {
            self.entries.remove(&key);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mavlink::dialects::ardupilotmega::MavCmd;

    /// A second ground station (MAVSDK's system id).
    fn sender() -> MavHeader {
        MavHeader {
            system_id: 245,
            ..crate::mav::gcs::gcs_header(0)
        }
    }

    #[test]
    fn repeats_get_the_cached_result_until_the_window_ends() {
        let sender = sender();
        let cmd = COMMAND_LONG_DATA {
            command: MavCmd::MAV_CMD_COMPONENT_ARM_DISARM,
            param1: 1.0,
            param2: f32::NAN,
            ..Default::default()
        };
        let key = CommandKey::new(&sender, &cmd);
        let mut cache = DuplicateCache::default();
        assert_eq!(cache.check(key, 0.0), Seen::New);
        assert_eq!(cache.check(key, 0.1), Seen::InProgress);
        cache.answered(key, MavResult::MAV_RESULT_ACCEPTED, 0.2);
        assert_eq!(cache.check(key, 0.5), Seen::Answered(MavResult::MAV_RESULT_ACCEPTED));
        let other = CommandKey::new(&sender, &COMMAND_LONG_DATA { param1: 0.0, ..cmd });
        assert_eq!(cache.check(other, 0.5), Seen::New);
        assert_eq!(cache.check(key, 3.3), Seen::New, "forgotten after the window");
        cache.answered(key, MavResult::MAV_RESULT_TEMPORARILY_REJECTED, 3.4);
        assert_eq!(cache.check(key, 3.5), Seen::New, "a temporary refusal may be retried");
        cache.answered(key, MavResult::MAV_RESULT_DENIED, 3.6);
        assert_eq!(cache.check(key, 3.7), Seen::New, "so may a denial, judged again");
    }

    #[test]
    fn a_flood_of_distinct_commands_is_remembered_up_to_a_bound() {
        let sender = sender();
        let mut cache = DuplicateCache::default();
        for k in 0..10_000u32 {
            let cmd = COMMAND_LONG_DATA {
                command: MavCmd::MAV_CMD_DO_SET_SERVO,
                param1: k as f32,
                ..Default::default()
            };
            assert_eq!(
                cache.check(CommandKey::new(&sender, &cmd), 1e-4 * f64::from(k)),
                Seen::New
            );
            assert!(cache.entries.len() <= MAX_REMEMBERED);
        }
        // The newest are the ones kept.
        let last = COMMAND_LONG_DATA {
            command: MavCmd::MAV_CMD_DO_SET_SERVO,
            param1: 9_999.0,
            ..Default::default()
        };
        assert_eq!(cache.check(CommandKey::new(&sender, &last), 1.0), Seen::InProgress);
    }

    #[test]
    #[allow(deprecated)]
    fn information_requests_are_answered_every_time() {
        let sender = sender();
        let version = COMMAND_LONG_DATA {
            command: MavCmd::MAV_CMD_REQUEST_MESSAGE,
            param1: 148.0,
            ..Default::default()
        };
        let mut cache = DuplicateCache::default();
        let key = CommandKey::new(&sender, &version);
        assert_eq!(cache.check(key, 0.0), Seen::New);
        assert_eq!(cache.check(key, 0.1), Seen::New, "a repeat in progress is answered too");
        cache.answered(key, MavResult::MAV_RESULT_ACCEPTED, 0.2);
        assert_eq!(cache.check(key, 0.7), Seen::New, "MAVSDK's second ask, 0.5 s later");
        // (command, only asks for information)
        let commands = [
            (MavCmd::MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES, true),
            (MavCmd::MAV_CMD_GET_HOME_POSITION, true),
            (MavCmd::MAV_CMD_GET_MESSAGE_INTERVAL, true),
            (MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL, false),
            (MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, false),
            (MavCmd::MAV_CMD_NAV_TAKEOFF, false),
            (MavCmd::MAV_CMD_DO_SET_MODE, false),
        ];
        for (command, information) in commands {
            assert_eq!(is_information_request(command), information, "{command:?}");
            if information {
                let key = CommandKey::new(&sender, &COMMAND_LONG_DATA { command, ..version });
                cache.answered(key, MavResult::MAV_RESULT_ACCEPTED, 1.0);
                assert_eq!(cache.check(key, 1.1), Seen::New, "{command:?}");
            }
        }
        let interval = CommandKey::new(
            &sender,
            &COMMAND_LONG_DATA {
                command: MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL,
                ..version
            },
        );
        assert_eq!(cache.check(interval, 2.0), Seen::New);
        cache.answered(interval, MavResult::MAV_RESULT_ACCEPTED, 2.0);
        assert_eq!(
            cache.check(interval, 2.5),
            Seen::Answered(MavResult::MAV_RESULT_ACCEPTED),
            "a command that changes state is still answered from the cache"
        );
    }
}
