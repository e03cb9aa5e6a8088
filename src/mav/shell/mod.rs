//! The MAVLink shell (SERIAL_CONTROL, msg 126, device SERIAL_CONTROL_DEV_SHELL) as QGroundControl's
//! MAVLink console and MAVSDK's shell plugin use it: the client sends bytes with the RESPOND
//! flag, the vehicle answers in SERIAL_CONTROL frames of at most 70 bytes flagged REPLY,
//! addressed to the client's system and component, as PX4 does; a frame without RESPOND closes
//! the shell. As PX4 SITL's remote `pxh` (`Pxh::run_remote_pxh`, which the MAVLink shell runs on
//! POSIX): every byte typed is echoed as it arrives (bytes up to 3, Ctrl-C among them, are
//! dropped), a line end prints a newline, the line runs, and the prompt `pxh> ` follows its
//! answer. Nothing is printed before the first line: a client that wants the prompt at once sends
//! an empty line (`\npxh> `). Pure.
//!
//! # Layout
//! - `mod.rs`: [`LineBuffer`], [`Typed`], [`frames`], [`PROMPT`].
//! - `commands.rs`: [`run`], the interpreter: `help`, `ver`, `param`, `commander status`,
//!   `listener`.

mod commands;

use mavlink::dialects::ardupilotmega::{MavMessage, SerialControlDev, SerialControlFlag, SERIAL_CONTROL_DATA};

pub use commands::{param_set_text, run, Context, ShellOutcome};

/// What the shell prints when it waits for a line (PX4 SITL's `pxh`; NuttX boards say `nsh> `).
pub const PROMPT: &str = "pxh> ";
/// Data bytes of one SERIAL_CONTROL frame.
pub const FRAME_DATA: usize = 70;
/// Longest line kept [bytes]; longer input is cut.
pub const LINE_MAX: usize = 256;

/// Bytes typed by one client until a line ends.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct LineBuffer {
    pending: Vec<u8>,
}

/// What typed bytes do, in order.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Typed {
    /// Bytes to echo back as they are (the shell's echo of what is typed).
    Echo(String),
    /// A complete line (trimmed) to run.
    Line(String),
}

impl LineBuffer {
    /// `bytes` appended: their echo and every line they complete, in order (`\n` or `\r` ends
    /// a line; `\r\n` is one end; bytes up to 3 are dropped, as `pxh` drops them).
    pub fn push(&mut self, bytes: &[u8]) -> Vec<Typed> {
        let mut out = Vec::new();
        let mut echo = Vec::new();
        let flush = |echo: &mut Vec<u8>, out: &mut Vec<Typed>| {
            if !echo.is_empty() {
                out.push(Typed::Echo(String::from_utf8_lossy(echo).into_owned()));
                echo.clear();
            }
        };
        for &b in bytes {
            match b {
                b'\n' if self.pending == b"\r" => self.pending.clear(),
                b'\n' | b'\r' => {
                    flush(&mut echo, &mut out);
                    let line = String::from_utf8_lossy(&self.pending).trim().to_string();
                    out.push(Typed::Line(line));
                    self.pending.clear();
                    if b == b'\r' {
                        self.pending.push(b'\r');
                    }
                }
                0..=3 => {}
                _ => {
                    if self.pending == b"\r" {
                        self.pending.clear();
                    }
                    echo.push(b);
                    if self.pending.len() < LINE_MAX {
                        self.pending.push(b);
                    }
                }
            }
        }
        flush(&mut echo, &mut out);
        out
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

    /// The lines of `typed`.
    fn lines(typed: Vec<Typed>) -> Vec<String> {
        typed
            .into_iter()
            .filter_map(|t| match t {
                Typed::Line(l) => Some(l),
                Typed::Echo(_) => None,
            })
            .collect()
    }

    #[test]
    fn lines_end_at_newline_or_return_and_are_trimmed() {
        let mut b = LineBuffer::default();
        assert!(lines(b.push(b"par")).is_empty());
        assert_eq!(
            lines(b.push(b"am show\r\nver all\n\n")),
            vec!["param show", "ver all", ""]
        );
        assert_eq!(lines(b.push(b"help\r")), vec!["help"]);
        assert_eq!(lines(b.push(b"\nx\n")), vec!["x"], "\\r\\n is one line end");
        assert_eq!(lines(b.push(&[b'a'; 1000])).len(), 0);
        assert_eq!(lines(b.push(b"\n"))[0].len(), LINE_MAX);
    }

    #[test]
    fn what_is_typed_is_echoed_as_it_arrives_and_control_bytes_are_dropped() {
        let mut b = LineBuffer::default();
        assert_eq!(b.push(b"ver"), vec![Typed::Echo("ver".into())]);
        assert_eq!(
            b.push(b" all\n\x03he\x01lp\r\n"),
            vec![
                Typed::Echo(" all".into()),
                Typed::Line("ver all".into()),
                Typed::Echo("help".into()),
                Typed::Line("help".into()),
            ]
        );
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
