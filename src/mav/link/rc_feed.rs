//! The RC receiver of an ArduCopter-faced vehicle at the link (docs/ardupilot.md §4): overrides
//! (RC_CHANNELS_OVERRIDE, and MANUAL_CONTROL as Copter reads it) go to the receiver, whose stick
//! channels feed the commander's manual input every [`STICKS_PERIOD_S`] of simulated time, as
//! SITL's receiver feeds ArduCopter; RC_CHANNELS reports the channels; and the boot mode
//! STABILIZE is asked for once the commander can fly it.

use std::hash::Hash;

use mavlink::dialects::ardupilotmega::{MavMessage, RC_CHANNELS_OVERRIDE_DATA};

use super::{LinkMachine, Now, ToVehicle, VehicleRequest};
use crate::commander::{FlightMode, InputStream, LandedState, Request};
use crate::guidance::Sticks;
use crate::mav::ardupilot::copter_rc::CopterReceiver;
use crate::mav::stream_messages::time_boot_ms;

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

impl RcFeed {
    /// A receiver at rest, its first sticks due at once, the boot mode still to ask for.
    pub fn new() -> Self {
        Self {
            next_boot_s: Some(0.0),
            ..Self::default()
        }
    }
}

impl<A: Copy + Eq + Hash> LinkMachine<A> {
    /// RC_CHANNELS_OVERRIDE addressed to the vehicle: the receiver takes it, the commander gets
    /// the sticks at once.
    pub(super) fn rc_override(&mut self, now: Now, o: &RC_CHANNELS_OVERRIDE_DATA) {
        self.rc.receiver.handle_override(o, now.sim_s);
        self.feed_sticks(now);
    }

    /// MANUAL_CONTROL to an ArduCopter-faced vehicle: overrides of the stick channels.
    pub(super) fn rc_manual_control(&mut self, now: Now, sticks: Sticks) {
        self.rc.receiver.handle_sticks(sticks, now.sim_s);
        self.feed_sticks(now);
    }

    /// The throttle stick the vehicle flies at `now` [0, 1].
    pub(super) fn rc_throttle(&self, now: Now) -> f64 {
        self.rc.receiver.sticks(now.sim_s, self.in_air()).throttle
    }

    /// RC_CHANNELS at `now`.
    pub(super) fn rc_channels(&self, now: Now) -> MavMessage {
        self.rc.receiver.rc_channels(now.sim_s, time_boot_ms(&self.snapshot))
    }

    /// Each duty pass: the sticks when due, and STABILIZE asked for at boot (once a second,
    /// until the commander flies it, a ground station asked for a mode or the vehicle armed).
    pub(super) fn rc_duty(&mut self, now: Now) {
        if now.sim_s >= self.rc.next_sticks_s {
            // At 50 Hz of simulated time, whatever the duty passes' phase; restarted after a gap.
            let next_s = self.rc.next_sticks_s + STICKS_PERIOD_S;
            self.rc.next_sticks_s = if next_s > now.sim_s {
                next_s
            } else {
                now.sim_s + STICKS_PERIOD_S
            };
            self.feed_sticks(now);
        }
        let Some(next_s) = self.rc.next_boot_s else {
            return;
        };
        let s = &self.snapshot;
        if s.armed || s.mode == FlightMode::Stabilized || self.mode_shown.asked().is_some() {
            self.rc.next_boot_s = None;
        } else if now.sim_s >= next_s && s.mode == FlightMode::Loiter {
            self.rc.next_boot_s = Some(now.sim_s + BOOT_RETRY_S);
            self.to_commander(Request::SetMode(FlightMode::Stabilized));
        }
    }

    /// Whether the vehicle is off the ground, as its latest state says.
    fn in_air(&self) -> bool {
        self.snapshot.landed != LandedState::OnGround
    }

    /// The receiver's sticks to the commander's manual input, heard as a stick stream.
    fn feed_sticks(&mut self, now: Now) {
        let sticks = self.rc.receiver.sticks(now.sim_s, self.in_air());
        self.to_commander(Request::ManualControl(sticks));
        self.streams.heard(InputStream::ManualControl, now.wall_s, now.sim_s);
    }

    /// `request` to the commander, no answer awaited.
    fn to_commander(&mut self, request: Request) {
        self.to_vehicle.push_back(ToVehicle {
            token: None,
            request: VehicleRequest::Commander(request),
        });
    }
}
