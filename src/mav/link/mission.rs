//! The mission protocol of the link against the vehicle's stored plans (mission, fence, rally):
//! uploads go through the link's [`MissionTransfer`](crate::mav::mission_xfer::MissionTransfer);
//! a complete upload is validated, handed to the vehicle (as the mission, the geofence or the
//! rally points), and stored and ACKed once the vehicle took it; downloads are answered from the
//! [`PlanStore`](crate::mav::plan_store::PlanStore); a clear empties both, per type.

use std::hash::Hash;

use mavlink::dialects::common::{MavMessage, MavMissionResult, MavMissionType, MISSION_ITEM_INT_DATA};

use super::{LinkKind, LinkMachine, Now, Pending, ToVehicle, VehicleReply, VehicleRequest, WARNING};
use crate::commander::Request;
use crate::mav::ingest::MissionStep;
use crate::mav::mission_items::{parse_mission, ItemError};
use crate::mav::mission_xfer::{Completed, Ids};
use crate::mav::plan_items::{parse_fence, parse_rally};
use crate::mav::plan_store::{plan_name, PLAN_TYPES};
use crate::mav::telemetry::status_text;
use crate::navigation::{Geofence, Home, Mission, RallyPoints};

/// The commander request that puts plan `mission_type` of `items` in force, or why not.
fn plan_request(
    mission_type: MavMissionType,
    items: &[MISSION_ITEM_INT_DATA],
    home: &Home,
) -> Result<Request, ItemError> {
    Ok(match mission_type {
        MavMissionType::MAV_MISSION_TYPE_FENCE => Request::SetGeofence(parse_fence(items, home)?),
        MavMissionType::MAV_MISSION_TYPE_RALLY => Request::SetRallyPoints(parse_rally(items, home)?),
        _ => Request::SetMission(parse_mission(items, home)?),
    })
}

/// The commander request that empties plan `mission_type`.
fn empty_plan(mission_type: MavMissionType) -> Request {
    match mission_type {
        MavMissionType::MAV_MISSION_TYPE_FENCE => Request::SetGeofence(Geofence::default()),
        MavMissionType::MAV_MISSION_TYPE_RALLY => Request::SetRallyPoints(RallyPoints::default()),
        _ => Request::SetMission(Mission::default()),
    }
}

impl<A: Copy + Eq + Hash> LinkMachine<A> {
    /// One mission-protocol step from `from` (MAVLink ids `ids`).
    pub(super) fn mission(&mut self, now: Now, link: LinkKind, from: A, ids: Ids, step: MissionStep) {
        let Some(port) = self.ports.iter_mut().find(|p| p.kind == link) else {
            return;
        };
        let (out, completed) = match step {
            MissionStep::Count(m) => port.transfer.on_count(from, ids, &m, now.wall_s),
            MissionStep::Item(m) => port.transfer.on_item(from, &m, now.wall_s),
            MissionStep::Clear(t) => port.transfer.on_clear(from, ids, t),
            MissionStep::RequestList(t) => (vec![(from, self.plans.download_count(ids, t))], None),
            MissionStep::RequestItem { seq, mission_type } => {
                (vec![(from, self.plans.download_item(ids, mission_type, seq))], None)
            }
        };
        self.send_all(now, link, out);
        match completed {
            Some(Completed::Items(mission_type, items)) => {
                match plan_request(mission_type, &items, &self.snapshot.home) {
                    Ok(request) => {
                        let token = self.expect(Pending::Mission {
                            link,
                            mission_type,
                            items,
                        });
                        self.to_vehicle.push_back(ToVehicle {
                            token: Some(token),
                            request: VehicleRequest::Commander(request),
                        });
                    }
                    Err(e) => {
                        let why = format!("{} item {} refused: {:?}", plan_name(mission_type), e.seq, e.result);
                        self.send(now, link, from, &status_text(WARNING, &why));
                        self.finish_upload(now, link, e.result, 0);
                    }
                }
            }
            Some(Completed::Cleared(cleared)) => {
                for t in PLAN_TYPES
                    .into_iter()
                    .filter(|t| cleared == *t || cleared == MavMissionType::MAV_MISSION_TYPE_ALL)
                {
                    self.to_vehicle.push_back(ToVehicle {
                        token: None,
                        request: VehicleRequest::Commander(empty_plan(t)),
                    });
                    self.plans.set(t, Vec::new());
                }
            }
            None => {}
        }
    }

    /// The vehicle's answer to a validated upload of plan `mission_type`: stored and ACCEPTED
    /// with the plan's id once it took the plan, MISSION_ERROR when it could not be reached.
    pub(super) fn mission_taken(
        &mut self,
        now: Now,
        link: LinkKind,
        mission_type: MavMissionType,
        items: Vec<MISSION_ITEM_INT_DATA>,
        reply: VehicleReply,
    ) {
        let (result, id) = match reply {
            VehicleReply::Busy => (MavMissionResult::MAV_MISSION_ERROR, 0),
            _ => {
                self.plans.set(mission_type, items);
                (MavMissionResult::MAV_MISSION_ACCEPTED, self.plans.id(mission_type))
            }
        };
        self.finish_upload(now, link, result, id);
    }

    /// The upload's MISSION_ACK with `result` and `opaque_id`.
    fn finish_upload(&mut self, now: Now, link: LinkKind, result: MavMissionResult, opaque_id: u32) {
        let out = self
            .port(link)
            .map(|p| p.transfer.finish(result, opaque_id))
            .unwrap_or_default();
        self.send_all(now, link, out);
    }

    /// Every (destination, message) of `out` on `link`.
    pub(super) fn send_all(&mut self, now: Now, link: LinkKind, out: Vec<(A, MavMessage)>) {
        for (to, msg) in out {
            self.send(now, link, to, &msg);
        }
    }
}
