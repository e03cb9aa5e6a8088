//! The MAVLink shell (SERIAL_CONTROL, msg 126, device SERIAL_CONTROL_DEV_SHELL) as QGroundControl's
//! MAVLink console and MAVSDK's shell plugin use it: the client sends bytes with the RESPOND
//! flag, the vehicle answers in SERIAL_CONTROL frames of at most 70 bytes flagged REPLY,
//! addressed to the client's system and component, as PX4 does; a frame without RESPOND closes
//! the shell. Each complete line is echoed (as NuttX's nsh echoes what is typed), run, answered
//! and followed by the prompt `nsh> `. Pure.
//!
//! # Layout
//! - `mod.rs`: [`LineBuffer`], [`frames`], [`PROMPT`].
//! - `commands.rs`: [`run`], the interpreter: `help`, `ver`, `param`, `commander status`,
//!   `listener`.

mod commands;

use mavlink::dialects::common::{MavMessage, SerialControlDev, SerialControlFlag, SERIAL_CONTROL_DATA};

pub use commands::{param_set_text, run, Context, Outcome};

/// What the shell prints when it waits for a line (NuttX's nsh).
pub const PROMPT: &str = "nsh> ";
/// Data bytes of one SERIAL_CONTROL frame.
pub const FRAME_DATA: usize = 70;
/// Longest line kept [bytes]; longer input is cut (nsh's line buffer is bounded too).
pub const LINE_MAX: usize = 256;

/// Bytes typed by one client until a line ends.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct LineBuffer {
    pending: Vec<u8>,
}

impl LineBuffer {
    /// `bytes` appended; every line they complete (`\n` or `\r` ends one; `\r\n` is one end).
    pub fn push(&mut self, bytes: &[u8]) -> Vec<String> {
        let mut lines = Vec::new();
        for &b in bytes {
            match b {
                b'\n' if self.pending == b"\r" => self.pending.clear(),
                b'\n' | b'\r' => {
                    let line = String::from_utf8_lossy(&self.pending).trim().to_string();
                    lines.push(line);
                    self.pending.clear();
                    if b == b'\r' {
                        self.pending.push(b'\r');
                    }
                }
                _ => {
                    if self.pending == b"\r" {
                        self.pending.clear();
                    }
                    if self.pending.len() < LINE_MAX {
                        self.pending.push(b);
                    }
                }
            }
        }
        lines
    }
}

/// `text` as SERIAL_CONTROL replies to `ids` (system, component): REPLY flag, the shell device,
/// at most [`FRAME_DATA`] bytes each.
pub fn frames(ids: (u8, u8), text: &str) -> Vec<MavMessage> {
    text.as_bytes()
        .chunks(FRAME_DATA)
        .map(|chunk| {
            let mut data = [0u8; FRAME_DATA];
            data[..chunk.len()].copy_from_slice(chunk);
            MavMessage::SERIAL_CONTROL(SERIAL_CONTROL_DATA {
                baudrate: 0,
                timeout: 0,
                device: SerialControlDev::SERIAL_CONTROL_DEV_SHELL,
                flags: SerialControlFlag::SERIAL_CONTROL_FLAG_REPLY,
                count: chunk.len() as u8,
                data,
                target_system: ids.0,
                target_component: ids.1,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_end_at_newline_or_return_and_are_trimmed() {
        let mut b = LineBuffer::default();
        assert!(b.push(b"par").is_empty());
        assert_eq!(b.push(b"am show\r\nver all\n\n"), vec!["param show", "ver all", ""]);
        assert_eq!(b.push(b"help\r"), vec!["help"]);
        assert_eq!(b.push(b"\nx\n"), vec!["x"], "\\r\\n is one line end");
        assert_eq!(b.push(&[b'a'; 1000]).len(), 0);
        assert_eq!(b.push(b"\n")[0].len(), LINE_MAX);
    }

    #[test]
    fn replies_are_cut_into_70_byte_frames_for_the_client() {
        let text = "x".repeat(150);
        let f = frames((255, 190), &text);
        assert_eq!(f.len(), 3);
        let MavMessage::SERIAL_CONTROL(last) = &f[2] else {
            panic!()
        };
        assert_eq!((last.count, last.target_system, last.target_component), (10, 255, 190));
        assert_eq!(last.flags, SerialControlFlag::SERIAL_CONTROL_FLAG_REPLY);
        assert_eq!(last.device, SerialControlDev::SERIAL_CONTROL_DEV_SHELL);
    }
}
