//! Idempotent command retransmissions (mavlink.md §3.1): a COMMAND_LONG/INT repeated within
//! [`DUPLICATE_WINDOW_S`] (same sender, command and seven parameters bit for bit) gets the
//! cached result and is not executed again; a repeat arriving while the first is still being
//! executed is dropped. Only ACCEPTED results are remembered: a refusal changed nothing, so a
//! repeat is simply judged again, and one sent after the state changed (OFFBOARD once setpoints
//! stream, failure injection once `SYS_FAILURE_EN` is set) gets the current answer.
//! Pure: the caller passes the time.

use std::collections::HashMap;

use mavlink::dialects::common::{MavResult, COMMAND_LONG_DATA};
use mavlink::MavHeader;

/// How long a result is remembered [s].
pub const DUPLICATE_WINDOW_S: f64 = 3.0;

/// Identity of one command transmission.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct CommandKey {
    sender: (u32, u8),
    command: u32,
    params: [u32; 7],
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
    /// Looks `key` up at time `now_s` [s]; a new key is recorded as in progress.
    pub fn check(&mut self, key: CommandKey, now_s: f64) -> Seen {
        self.entries.retain(|_, (t, _)| now_s - *t < DUPLICATE_WINDOW_S);
        match self.entries.get(&key) {
            Some((_, Some(result))) => Seen::Answered(*result),
            Some((_, None)) => Seen::InProgress,
            None => {
                self.entries.insert(key, (now_s, None));
                Seen::New
            }
        }
    }

    /// Records the result of `key`: kept when ACCEPTED, forgotten for a refusal.
    pub fn answered(&mut self, key: CommandKey, result: MavResult, now_s: f64) {
        if result == MavResult::MAV_RESULT_ACCEPTED {
            self.entries.insert(key, (now_s, Some(result)));
        } else {
            self.entries.remove(&key);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mavlink::dialects::common::MavCmd;

    #[test]
    fn repeats_get_the_cached_result_until_the_window_ends() {
        let sender = MavHeader {
            system_id: 245,
            component_id: 190,
            sequence: 0,
        };
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
}
