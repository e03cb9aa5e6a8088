//! A complete plan upload turned into the commander request that puts it in force, under the
//! vehicle's personality (docs/ardupilot.md §6): PX4's checks, or ArduCopter's (its mission read
//! by Copter's rules, its fence and rally plans checked and stored as Copter stores them). Pure.

use mavlink::dialects::ardupilotmega::{MavMissionType, MISSION_ITEM_INT_DATA};

use crate::commander::Request;
use crate::guidance::{Geofence, Home, Mission, RallyPoints, RallyRule};
use crate::mav::ardupilot::copter_mission::{flown_items, link_seq};
use crate::mav::ardupilot::copter_plans::{check_fence, check_rally, stored_fence, stored_rally, PlanRefusal};
use crate::mav::identity::Personality;
use crate::mav::mission_items::{parse_mission, ItemError, MissionRules};
use crate::mav::plan_items::{parse_fence, parse_rally};

/// The commander request that puts plan `mission_type` of `items` in force with the items as
/// the vehicle stores them, or why not (the refused item by its uploaded seq, and ArduCopter's
/// warning). ArduCopter's mission flies items 1.. (item 0 is home, stored but neither flown nor
/// checked) read by Copter's rules; its fence and rally plans are checked and stored as Copter
/// does (`copter_plans`), its rally points chosen by Copter's rule.
pub(super) fn plan_request(
    personality: Personality,
    mission_type: MavMissionType,
    items: Vec<MISSION_ITEM_INT_DATA>,
    home: &Home,
) -> Result<(Request, Vec<MISSION_ITEM_INT_DATA>), PlanRefusal> {
    let shared = |error: ItemError| PlanRefusal { error, text: None };
    let copter = personality == Personality::ArduPilot;
    Ok(match mission_type {
        MavMissionType::MAV_MISSION_TYPE_FENCE if copter => {
            check_fence(&items)?;
            let stored = stored_fence(&items);
            (
                Request::SetGeofence(parse_fence(&stored, home).map_err(shared)?),
                stored,
            )
        }
        MavMissionType::MAV_MISSION_TYPE_RALLY if copter => {
            check_rally(&items)?;
            let stored = stored_rally(&items);
            let rally = RallyPoints {
                rule: RallyRule::COPTER,
                ..parse_rally(&stored, home).map_err(shared)?
            };
            (Request::SetRallyPoints(rally), stored)
        }
        MavMissionType::MAV_MISSION_TYPE_FENCE => {
            (Request::SetGeofence(parse_fence(&items, home).map_err(shared)?), items)
        }
        MavMissionType::MAV_MISSION_TYPE_RALLY => (
            Request::SetRallyPoints(parse_rally(&items, home).map_err(shared)?),
            items,
        ),
        _ if copter => {
            let flown = parse_mission(&flown_items(&items), home, MissionRules::COPTER).map_err(|e| ItemError {
                seq: link_seq(e.seq),
                ..e
            });
            (Request::SetMission(flown.map_err(shared)?), items)
        }
        _ => (
            Request::SetMission(parse_mission(&items, home, MissionRules::PX4).map_err(shared)?),
            items,
        ),
    })
}

/// The mission plan's type.
pub(super) const MISSION: MavMissionType = MavMissionType::MAV_MISSION_TYPE_MISSION;

/// The commander request that empties plan `mission_type`.
pub(super) fn empty_plan(mission_type: MavMissionType) -> Request {
    match mission_type {
        MavMissionType::MAV_MISSION_TYPE_FENCE => Request::SetGeofence(Geofence::default()),
        MavMissionType::MAV_MISSION_TYPE_RALLY => Request::SetRallyPoints(RallyPoints::default()),
        _ => Request::SetMission(Mission::default()),
    }
}
