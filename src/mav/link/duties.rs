//! What time brings, every [`DUTY_PERIOD_S`] of wall time: expired peers forgotten, mission
//! items re-requested, GCS link loss, the offboard stream's liveness in wall time, heartbeats
//! and telemetry streams; parameter lists at their own pace. Commander events become announcements here too.

use std::hash::Hash;

use mavlink::dialects::ardupilotmega::MavMessage;

use super::liveness::silent_for;
use super::{LinkKind, LinkMachine, Now, ToVehicle, VehicleRequest, CRITICAL, INFO, WARNING};
use crate::commander::{Event, LinkLossAction, Request};
use crate::mav::ardupilot::copter_modes::copter_heartbeat;
use crate::mav::identity::{heartbeat, Personality};
use crate::mav::signing::unix_us_from_timestamp;
use crate::mav::stream_messages::{message, status_text, system_time, TelemetryStream};

/// How often the link looks at what is due (wall time) [s].
pub const DUTY_PERIOD_S: f64 = 0.005;
/// Heartbeat period, in wall time and in simulated time [s].
pub const HEARTBEAT_PERIOD_S: f64 = 1.0;

impl<A: Copy + Eq + Hash> LinkMachine<A> {
    /// The message announcing `event` (a reached item is remembered for MISSION_CURRENT).
    pub(super) fn announcement(&mut self, event: &Event) -> MavMessage {
        match event {
            Event::MissionItemReached(seq) => self.plans.handle_reached(*seq),
            Event::MissionCurrent(seq) => self.plans.mission_current(&self.snapshot, *seq),
            Event::Failsafe(_, text) | Event::Notice { text, critical: true } => status_text(CRITICAL, text),
            Event::Navigation { text, warning: true } => status_text(WARNING, text),
            other => status_text(INFO, &other.describe()),
        }
    }

    /// Everything due by `now`.
    pub fn handle_timeout(&mut self, now: Now) {
        // What the link holds is read only when a parameter may be sent (not on every pass).
        if self.parameters.has_work() {
            let held = self.link_params();
            let lists = self.parameters.stream_lists(now.wall_s, &self.params, &held);
            self.carry_out(now, lists);
            let changed = self.parameters.announce_changed(now.wall_s, &self.params, &held);
            self.carry_out(now, changed);
        }
        let bursts = self.files.stream_bursts(now.wall_s);
        self.carry_out(now, bursts);
        let logs = self.logs.stream(now.wall_s, self.files.log_store());
        self.carry_out(now, logs);
        if now.wall_s < self.next_duty_s {
            return;
        }
        self.next_duty_s = now.wall_s + DUTY_PERIOD_S;
        if self.identity.personality == Personality::ArduPilot {
            if let Some(text) = self.armed_notices.handle_state(&self.snapshot) {
                self.broadcast(now, &status_text(INFO, text));
            }
            if let Some(text) = self.prearm_notices.handle_state(now.sim_s, &self.snapshot) {
                self.broadcast(now, &status_text(CRITICAL, &text));
            }
            if let Some((severity, text)) = self.copter_failsafes.handle_state(&self.snapshot) {
                self.broadcast(now, &status_text(severity, &text));
            }
            let asked = self.mode_shown.asked().is_some();
            let requests = self.rc.duty(now.sim_s, &self.snapshot, asked);
            self.ask_commander(now, requests);
        }
        self.check_streams(now);
        for k in 0..self.ports.len() {
            let link = self.ports[k].kind;
            let gone = self.ports[k].expire(now.wall_s);
            self.forget_peers(link, &gone);
            let targets = self.ports[k].targets();
            let uploads = self.plans.tick(now.wall_s, link);
            self.carry_out(now, uploads);
            if link == LinkKind::Gcs {
                self.check_link_loss(now, k);
            }
            self.heartbeat(now, k, &targets);
            // Rates count simulated time; each stream goes out at most once per duty pass,
            // which caps it at 200 Hz of wall time when simulated time runs fast.
            for stream in self.ports[k].streams.due(now.sim_s) {
                if let Some(out) = self.stream_message(now, stream) {
                    for to in &targets {
                        self.send(now, link, *to, &out);
                    }
                }
            }
        }
    }

    /// `stream`'s message now (streamed or asked for): from the snapshot, except SYSTEM_TIME,
    /// which comes from the wall clock the signing clock counts; `None` when there is none.
    pub(super) fn stream_message(&self, now: Now, stream: TelemetryStream) -> Option<MavMessage> {
        match stream {
            TelemetryStream::SystemTime => Some(system_time(
                unix_us_from_timestamp(self.keys.now(now.wall_s)),
                &self.snapshot,
            )),
            TelemetryStream::RcChannels if self.identity.personality == Personality::ArduPilot => {
                Some(self.rc.rc_channels(now.sim_s, &self.snapshot))
            }
            TelemetryStream::MissionCurrent => {
                Some(self.plans.mission_current(&self.snapshot, self.snapshot.mission_seq))
            }
            _ => message(stream, &self.snapshot),
        }
    }

    /// At least 1 Hz in wall time (MAVSDK drops a silent link after 3 s) and 1 Hz in simulated
    /// time (scripts pacing themselves in simulated time see the same rate at any speed-up),
    /// plus one right after arm, disarm or a mode change.
    fn heartbeat(&mut self, now: Now, k: usize, targets: &[A]) {
        let port = &mut self.ports[k];
        let state = (
            self.snapshot.armed,
            self.snapshot.mode,
            self.mode_shown.shown(&self.snapshot),
        );
        let (wall_due, sim_due) = port.next_heartbeat;
        let changed = port.last_state.is_some_and(|s| s != state);
        if now.wall_s < wall_due && now.sim_s < sim_due && !changed {
            return;
        }
        port.next_heartbeat = (now.wall_s + HEARTBEAT_PERIOD_S, now.sim_s + HEARTBEAT_PERIOD_S);
        port.last_state = Some(state);
        let link = port.kind;
        let hb = match self.identity.personality {
            Personality::Px4 => heartbeat(&self.identity, state.0, state.1),
            Personality::ArduPilot => copter_heartbeat(
                &self.identity,
                &self.snapshot,
                &self.mode_shown,
                self.copter_failsafes.active(),
            ),
        };
        for to in targets {
            self.send(now, link, *to, &hb);
        }
    }

    /// GCS link loss: after a ground station's HEARTBEAT was heard, `COM_DL_LOSS_T` of silence
    /// ([`silent_for`]: in simulated time *and* in wall time) runs `NAV_DLL_ACT` once per loss (the commander's
    /// reaction comes back as an [`Event::Failsafe`] through [`LinkMachine::handle_event`]). A ground station
    /// pacing itself in simulated time sees the same failsafe at any speed-up; one sending in
    /// wall time does not trip it just because simulated time runs faster.
    fn check_link_loss(&mut self, now: Now, k: usize) {
        let commander = &self.params.current().commander;
        let (loss_s, action) = (commander.link_loss_s, commander.link_loss_action);
        let port = &mut self.ports[k];
        let Some(heard) = port.gcs_heard else {
            return;
        };
        if !silent_for(now.wall_s, now.sim_s, heard, loss_s) {
            port.link_lost = false;
            self.copter_gcs_failsafe(now, false);
            return;
        }
        if port.link_lost || action == LinkLossAction::Disabled {
            return;
        }
        port.link_lost = true;
        self.copter_gcs_failsafe(now, true);
        // No answer is awaited: the commander announces its reaction as an event.
        self.to_vehicle.push_back(ToVehicle {
            token: None,
            request: VehicleRequest::Commander(Request::GcsLinkLost),
        });
    }

    /// The ArduCopter personality's GCS failsafe: said when the ground station is `lost` (with
    /// `NAV_DLL_ACT` set, Copter's `FS_GCS_ENABLE`) and when it is heard again.
    fn copter_gcs_failsafe(&mut self, now: Now, lost: bool) {
        if self.identity.personality != Personality::ArduPilot {
            return;
        }
        if let Some((severity, text)) = self.copter_failsafes.handle_gcs(lost) {
            self.broadcast(now, &status_text(severity, &text));
        }
    }

    /// `requests` to the commander, no answer awaited; stick samples are heard as the stick
    /// stream.
    pub(super) fn ask_commander(&mut self, now: Now, requests: impl IntoIterator<Item = Request>) {
        for request in requests {
            if let Some(stream) = request.input_stream() {
                self.streams.heard(stream, now.wall_s, now.sim_s);
            }
            self.to_vehicle.push_back(ToVehicle {
                token: None,
                request: VehicleRequest::Commander(request),
            });
        }
    }

    /// A stream's loss ([`StreamLiveness::lost`]): the commander runs the reaction
    /// ([`Request::StreamLost`]).
    fn check_streams(&mut self, now: Now) {
        let commander = self.params.current().commander;
        for stream in self.streams.lost(now.wall_s, now.sim_s, &commander) {
            self.to_vehicle.push_back(ToVehicle {
                token: None,
                request: VehicleRequest::Commander(Request::StreamLost(stream)),
            });
        }
    }
}
