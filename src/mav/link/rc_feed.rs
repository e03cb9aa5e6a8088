//! The RC receiver of an ArduCopter-faced vehicle at the link (docs/ardupilot.md §8): overrides
//! (RC_CHANNELS_OVERRIDE, and MANUAL_CONTROL as Copter reads it) go to the receiver, whose stick
//! channels feed the commander's manual input every [`STICKS_PERIOD_S`] of simulated time, as
//! SITL's receiver feeds ArduCopter; RC_CHANNELS reports the channels; and the boot mode
//! STABILIZE is asked for until the commander flies it. Pure: time and the vehicle's state are
//! values, the commander requests are returned.

use mavlink::dialects::ardupilotmega::{MavMessage, RC_CHANNELS_OVERRIDE_DATA};

use crate::commander::{FlightMode, LandedState, Request};
use crate::guidance::Sticks;
use crate::mav::ardupilot::copter_rc::CopterReceiver;
use crate::mav::stream_messages::time_boot_ms;
use crate::telemetry::Snapshot;

/// How often the receiver's sticks reach the commander (SITL's RC input rate, 50 Hz) [s].
pub const STICKS_PERIOD_S: f64 = 0.02;
/// How often STABILIZE is asked for at boot until the commander flies it [s].
const BOOT_RETRY_S: f64 = 1.0;

/// The receiver, when its sticks are next due and the boot mode's progress.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(super) struct RcFeed {
    receiver: CopterReceiver,
    next_sticks_s: f64,
    /// When STABILIZE is next asked for at boot; `None` once booted (STABILIZE flown, another
    /// mode asked for or the vehicle armed).
    next_boot_s: Option<f64>,
}

/// Whether `state` is off the ground.
fn in_air(state: &Snapshot) -> bool {
    state.landed != LandedState::OnGround
}

impl RcFeed {
    /// A receiver at rest, its first sticks due at once, the boot mode still to ask for.
    pub fn new() -> Self {
        Self {
            next_boot_s: Some(0.0),
            ..Self::default()
        }
    }

    /// RC_CHANNELS_OVERRIDE addressed to the vehicle at `t_s` [s]: the sticks for the commander
    /// at once.
    pub fn handle_override(&mut self, o: &RC_CHANNELS_OVERRIDE_DATA, t_s: f64, state: &Snapshot) -> Request {
        self.receiver.handle_override(o, t_s);
        self.sticks(t_s, state)
    }

    /// MANUAL_CONTROL's `sticks` at `t_s` [s], overrides of the stick channels: the sticks for
    /// the commander at once.
    pub fn handle_sticks(&mut self, sticks: Sticks, t_s: f64, state: &Snapshot) -> Request {
        self.receiver.handle_sticks(sticks, t_s);
        self.sticks(t_s, state)
    }

    /// The throttle stick the vehicle in `state` flies at `t_s` [s] [0, 1].
    pub fn throttle(&self, t_s: f64, state: &Snapshot) -> f64 {
        self.receiver.sticks(t_s, in_air(state)).throttle
    }

    /// RC_CHANNELS at `t_s` [s] for the vehicle in `state`.
    pub fn rc_channels(&self, t_s: f64, state: &Snapshot) -> MavMessage {
        self.receiver.rc_channels(t_s, time_boot_ms(state))
    }

    /// Each duty pass at `t_s` [s], the vehicle in `state`, `asked` whether a ground station
    /// asked for a mode: the sticks when due (50 Hz of simulated time, whatever the passes'
    /// phase), and STABILIZE once a second at boot until the commander flies it, a mode is
    /// asked for or the vehicle arms.
    pub fn duty(&mut self, t_s: f64, state: &Snapshot, asked: bool) -> Vec<Request> {
        let mut requests = Vec::new();
        if t_s >= self.next_sticks_s {
            let next_s = self.next_sticks_s + STICKS_PERIOD_S;
            self.next_sticks_s = if next_s > t_s { next_s } else { t_s + STICKS_PERIOD_S };
            requests.push(self.sticks(t_s, state));
        }
        if let Some(next_s) = self.next_boot_s {
            if state.armed || state.mode == FlightMode::Stabilized || asked {
                self.next_boot_s = None;
            } else if t_s >= next_s && state.mode == FlightMode::Loiter {
                self.next_boot_s = Some(t_s + BOOT_RETRY_S);
                requests.push(Request::SetMode(FlightMode::Stabilized));
            }
        }
        requests
    }

    /// The receiver's sticks at `t_s` [s] as a manual-input request.
    fn sticks(&self, t_s: f64, state: &Snapshot) -> Request {
        Request::ManualControl(self.receiver.sticks(t_s, in_air(state)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::guidance::Home;

    #[test]
    fn sticks_at_50_hz_and_stabilize_asked_for_until_flown() {
        let mut feed = RcFeed::new();
        let mut state = Snapshot::initial(Home::default());
        state.mode = FlightMode::Loiter;
        let mut sticks = 0;
        let mut boots = 0;
        for k in 0..200 {
            for r in feed.duty(f64::from(k) * 0.005, &state, false) {
                match r {
                    Request::ManualControl(_) => sticks += 1,
                    Request::SetMode(FlightMode::Stabilized) => boots += 1,
                    other => panic!("{other:?}"),
                }
            }
        }
        assert_eq!((sticks, boots), (50, 1), "1 s: 50 samples, STABILIZE once");
        state.mode = FlightMode::Stabilized;
        feed.duty(1.0, &state, false);
        state.mode = FlightMode::Loiter;
        assert!(feed
            .duty(2.5, &state, false)
            .iter()
            .all(|r| matches!(r, Request::ManualControl(_))));
    }
}
