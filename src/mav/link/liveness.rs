//! The liveness of what clients stream (docs/mavlink.md §6, §11.2): one rule for GCS heartbeats,
//! offboard setpoints and sticks ([`silent_for`]), judged where the stream arrives — the link for
//! network clients ([`LinkMachine`](super::LinkMachine)), a test harness for in-process ones —
//! and never again by the commander, which only runs the reaction to
//! [`Request::StreamLost`](crate::commander::Request::StreamLost). Pure.

use crate::commander::{CommanderParams, InputStream};

/// Silent for `loss_s` [s] since `heard` (wall, simulated time [s]) in wall time *and* in
/// simulated time, both of one reading (`wall_s`, `sim_s`) [s]: a client sending in wall time is
/// not lost just because simulated time runs faster (`--speedup`), nor one pacing itself in
/// simulated time because it runs slower.
pub fn silent_for(wall_s: f64, sim_s: f64, heard: (f64, f64), loss_s: f64) -> bool {
    wall_s - heard.0 >= loss_s && sim_s - heard.1 >= loss_s
}

/// When each input stream (offboard setpoints, sticks) was last heard, until it is declared lost.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StreamLiveness {
    /// Wall and simulated time [s] of each stream's latest message.
    heard: [Option<(f64, f64)>; 2],
}

impl StreamLiveness {
    /// A message of `stream` arrived at wall time `wall_s` and simulated time `sim_s` [s].
    pub fn heard(&mut self, stream: InputStream, wall_s: f64, sim_s: f64) {
        self.heard[stream as usize] = Some((wall_s, sim_s));
    }

    /// The streams silent for their loss time (`COM_OF_LOSS_T`, `COM_RC_LOSS_T` of `params`)
    /// at (`wall_s`, `sim_s`) [s], each reported once per loss: it is alive again with its next
    /// message.
    pub fn lost(&mut self, wall_s: f64, sim_s: f64, params: &CommanderParams) -> Vec<InputStream> {
        let mut lost = Vec::new();
        for (stream, loss_s) in [
            (InputStream::Offboard, params.offboard_loss_s),
            (InputStream::ManualControl, params.manual.loss_s),
        ] {
            let heard = &mut self.heard[stream as usize];
            if heard.is_some_and(|heard| silent_for(wall_s, sim_s, heard, loss_s)) {
                *heard = None;
                lost.push(stream);
            }
        }
        lost
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn silence_counts_in_both_clocks_of_one_reading() {
        assert!(
            !silent_for(10.0, 0.5, (0.0, 0.0), 1.0),
            "simulated time behind: not yet"
        );
        assert!(!silent_for(0.5, 10.0, (0.0, 0.0), 1.0), "wall time behind: not yet");
        assert!(silent_for(1.0, 1.0, (0.0, 0.0), 1.0));
    }

    #[test]
    fn a_stream_is_reported_lost_once_and_lives_again_with_its_next_message() {
        let p = CommanderParams::default();
        let mut s = StreamLiveness::default();
        assert!(s.lost(100.0, 100.0, &p).is_empty(), "never heard: never lost");
        s.heard(InputStream::Offboard, 0.0, 0.0);
        s.heard(InputStream::ManualControl, 0.0, 0.0);
        let within = p.offboard_loss_s.min(p.manual.loss_s) * 0.9;
        assert!(s.lost(within, within, &p).is_empty());
        let offboard_s = p.offboard_loss_s;
        let sticks_s = p.manual.loss_s;
        let first = offboard_s.min(sticks_s);
        let both = offboard_s.max(sticks_s);
        assert_eq!(s.lost(first, first, &p).len(), 1);
        assert_eq!(s.lost(both, both, &p).len(), 1, "the other one");
        assert!(s.lost(both + 1.0, both + 1.0, &p).is_empty(), "once per loss");
        s.heard(InputStream::Offboard, both + 2.0, both + 2.0);
        assert_eq!(
            s.lost(both + 2.0 + offboard_s, both + 2.0 + offboard_s, &p),
            vec![InputStream::Offboard]
        );
    }
}
