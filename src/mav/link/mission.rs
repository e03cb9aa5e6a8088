//! The mission protocol of the link against the vehicle's stored mission: uploads go through
//! the link's [`MissionTransfer`](crate::mav::mission_xfer::MissionTransfer); a complete upload
//! is validated, handed to the vehicle, and stored and ACKed once the vehicle took it; downloads
//! are answered from the store; a clear empties both.

use std::hash::Hash;

use mavlink::dialects::common::{MavMessage, MavMissionResult, MISSION_ITEM_INT_DATA};

use super::{LinkKind, LinkMachine, Now, Pending, ToVehicle, VehicleReply, VehicleRequest, WARNING};
use crate::commander::Request;
use crate::mav::ingest::MissionStep;
use crate::mav::mission_items::parse_mission;
use crate::mav::mission_xfer::{download_count, download_item, Completed, Ids};
use crate::mav::telemetry::status_text;
use crate::navigation::Mission;

impl<A: Copy + Eq + Hash> LinkMachine<A> {
    /// One mission-protocol step from `from` (MAVLink ids `ids`).
    pub(super) fn mission(&mut self, now: Now, link: LinkKind, from: A, ids: Ids, step: MissionStep) {
        let Some(port) = self.ports.iter_mut().find(|p| p.kind == link) else {
            return;
        };
        let (out, completed) = match step {
            MissionStep::Count(m) => port.transfer.on_count(from, ids, &m, now.wall_s),
            MissionStep::Item(m) => port.transfer.on_item(from, &m, now.wall_s),
            MissionStep::Clear => port.transfer.on_clear(from, ids),
            MissionStep::RequestList(t) => (vec![(from, download_count(ids, t, &self.mission_store))], None),
            MissionStep::RequestItem { seq, mission_type } => (
                vec![(from, download_item(ids, mission_type, seq, &self.mission_store))],
                None,
            ),
        };
        self.send_all(now, link, out);
        match completed {
            Some(Completed::Items(items)) => match parse_mission(&items, &self.snapshot.home) {
                Ok(mission) => {
                    let token = self.expect(Pending::Mission { link, items });
                    self.to_vehicle.push_back(ToVehicle {
                        token: Some(token),
                        request: VehicleRequest::Commander(Request::SetMission(mission)),
                    });
                }
                Err(e) => {
                    let why = format!("Mission item {} refused: {:?}", e.seq, e.result);
                    self.send(now, link, from, &status_text(WARNING, &why));
                    self.finish_upload(now, link, e.result);
                }
            },
            Some(Completed::Cleared) => {
                self.to_vehicle.push_back(ToVehicle {
                    token: None,
                    request: VehicleRequest::Commander(Request::SetMission(Mission::default())),
                });
                self.mission_store.clear();
            }
            None => {}
        }
    }

    /// The vehicle's answer to a validated upload: stored and ACCEPTED once it took the
    /// mission, MISSION_ERROR when it could not be reached.
    pub(super) fn mission_taken(
        &mut self,
        now: Now,
        link: LinkKind,
        items: Vec<MISSION_ITEM_INT_DATA>,
        reply: VehicleReply,
    ) {
        let result = match reply {
            VehicleReply::Busy => MavMissionResult::MAV_MISSION_ERROR,
            _ => {
                self.mission_store = items;
                MavMissionResult::MAV_MISSION_ACCEPTED
            }
        };
        self.finish_upload(now, link, result);
    }

    /// The upload's MISSION_ACK with `result`.
    fn finish_upload(&mut self, now: Now, link: LinkKind, result: MavMissionResult) {
        let out = self.port(link).map(|p| p.transfer.finish(result)).unwrap_or_default();
        self.send_all(now, link, out);
    }

    /// Every (destination, message) of `out` on `link`.
    pub(super) fn send_all(&mut self, now: Now, link: LinkKind, out: Vec<(A, MavMessage)>) {
        for (to, msg) in out {
            self.send(now, link, to, &msg);
        }
    }
}
