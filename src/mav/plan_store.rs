//! The stored plans of the mission protocol, one per MAV_MISSION_TYPE (mission, fence, rally),
//! as uploaded, and the stateless downloads answered from them (docs/mavlink.md §7). A plan changes
//! only when the vehicle took a validated upload of its type, or on a clear. Pure.

use mavlink::dialects::common::{
    MavMessage, MavMissionResult, MavMissionType, MISSION_COUNT_DATA, MISSION_ITEM_INT_DATA,
};

use super::mission_xfer::{mission_ack, Ids};

/// The plans a vehicle stores, by type.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PlanStore {
    mission: Vec<MISSION_ITEM_INT_DATA>,
    fence: Vec<MISSION_ITEM_INT_DATA>,
    rally: Vec<MISSION_ITEM_INT_DATA>,
}

/// The plan types a vehicle stores, in MAV_MISSION_TYPE order (what MAV_MISSION_TYPE_ALL names).
pub const PLAN_TYPES: [MavMissionType; 3] = [
    MavMissionType::MAV_MISSION_TYPE_MISSION,
    MavMissionType::MAV_MISSION_TYPE_FENCE,
    MavMissionType::MAV_MISSION_TYPE_RALLY,
];

/// A stored plan type's name for announcements: `Mission`, `Fence`, `Rally`.
pub fn plan_name(mission_type: MavMissionType) -> &'static str {
    match mission_type {
        MavMissionType::MAV_MISSION_TYPE_FENCE => "Fence",
        MavMissionType::MAV_MISSION_TYPE_RALLY => "Rally",
        _ => "Mission",
    }
}

impl PlanStore {
    /// The items of plan `mission_type` (none for a type not stored).
    pub fn items(&self, mission_type: MavMissionType) -> &[MISSION_ITEM_INT_DATA] {
        match mission_type {
            MavMissionType::MAV_MISSION_TYPE_MISSION => &self.mission,
            MavMissionType::MAV_MISSION_TYPE_FENCE => &self.fence,
            MavMissionType::MAV_MISSION_TYPE_RALLY => &self.rally,
            _ => &[],
        }
    }

    /// Replaces plan `mission_type` (a type not stored is ignored).
    pub fn set(&mut self, mission_type: MavMissionType, items: Vec<MISSION_ITEM_INT_DATA>) {
        match mission_type {
            MavMissionType::MAV_MISSION_TYPE_MISSION => self.mission = items,
            MavMissionType::MAV_MISSION_TYPE_FENCE => self.fence = items,
            MavMissionType::MAV_MISSION_TYPE_RALLY => self.rally = items,
            _ => {}
        }
    }

    /// MISSION_COUNT of plan `mission_type` for a download, addressed to `ids`.
    pub fn download_count(&self, ids: Ids, mission_type: MavMissionType) -> MavMessage {
        MavMessage::MISSION_COUNT(MISSION_COUNT_DATA {
            count: self.items(mission_type).len() as u16,
            target_system: ids.0,
            target_component: ids.1,
            mission_type,
            opaque_id: 0,
        })
    }

    /// Item `seq` of plan `mission_type` addressed to `ids`, or a MISSION_ACK(INVALID_SEQUENCE)
    /// of that type.
    pub fn download_item(&self, ids: Ids, mission_type: MavMissionType, seq: u16) -> MavMessage {
        match self.items(mission_type).get(usize::from(seq)) {
            Some(item) => MavMessage::MISSION_ITEM_INT(MISSION_ITEM_INT_DATA {
                target_system: ids.0,
                target_component: ids.1,
                mission_type,
                ..item.clone()
            }),
            None => mission_ack(ids, mission_type, MavMissionResult::MAV_MISSION_INVALID_SEQUENCE),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mavlink::dialects::common::MavCmd;

    const GCS: Ids = (255, 190);
    const MISSION: MavMissionType = MavMissionType::MAV_MISSION_TYPE_MISSION;
    const FENCE: MavMissionType = MavMissionType::MAV_MISSION_TYPE_FENCE;
    const RALLY: MavMissionType = MavMissionType::MAV_MISSION_TYPE_RALLY;

    fn item(seq: u16, command: MavCmd) -> MISSION_ITEM_INT_DATA {
        MISSION_ITEM_INT_DATA {
            seq,
            command,
            ..Default::default()
        }
    }

    /// The mission_type of a download reply and its count, seq or result.
    fn typed(msg: &MavMessage) -> Option<(MavMissionType, u32)> {
        match msg {
            MavMessage::MISSION_ACK(a) => Some((a.mission_type, a.mavtype as u32)),
            MavMessage::MISSION_COUNT(c) => Some((c.mission_type, u32::from(c.count))),
            MavMessage::MISSION_ITEM_INT(i) => Some((i.mission_type, u32::from(i.seq))),
            _ => None,
        }
    }

    #[test]
    fn each_plan_downloads_from_its_own_store_with_its_own_type() {
        let mut store = PlanStore::default();
        store.set(
            MISSION,
            vec![item(0, MavCmd::MAV_CMD_NAV_WAYPOINT), item(1, MavCmd::MAV_CMD_NAV_LAND)],
        );
        store.set(RALLY, vec![item(0, MavCmd::MAV_CMD_NAV_RALLY_POINT)]);
        assert_eq!(typed(&store.download_count(GCS, MISSION)), Some((MISSION, 2)));
        assert_eq!(
            typed(&store.download_count(GCS, FENCE)),
            Some((FENCE, 0)),
            "none stored"
        );
        assert_eq!(typed(&store.download_count(GCS, RALLY)), Some((RALLY, 1)));
        let rally0 = store.download_item(GCS, RALLY, 0);
        assert!(
            matches!(rally0, MavMessage::MISSION_ITEM_INT(ref i) if i.command == MavCmd::MAV_CMD_NAV_RALLY_POINT && i.target_system == 255)
        );
        assert_eq!(typed(&rally0), Some((RALLY, 0)));
        let invalid = MavMissionResult::MAV_MISSION_INVALID_SEQUENCE as u32;
        assert_eq!(typed(&store.download_item(GCS, RALLY, 1)), Some((RALLY, invalid)));
        assert_eq!(typed(&store.download_item(GCS, FENCE, 0)), Some((FENCE, invalid)));
        // A stored item answers with the type asked for, whatever it was uploaded with.
        let stray = MISSION_ITEM_INT_DATA {
            mission_type: FENCE,
            ..item(0, MavCmd::MAV_CMD_NAV_WAYPOINT)
        };
        store.set(MISSION, vec![stray]);
        assert_eq!(typed(&store.download_item(GCS, MISSION, 0)), Some((MISSION, 0)));
        store.set(
            MavMissionType::MAV_MISSION_TYPE_ALL,
            vec![item(0, MavCmd::MAV_CMD_NAV_LAND)],
        );
        assert!(store.items(MavMissionType::MAV_MISSION_TYPE_ALL).is_empty());
        assert_eq!(
            (plan_name(FENCE), plan_name(RALLY), plan_name(MISSION)),
            ("Fence", "Rally", "Mission")
        );
    }
}
