//! The stored plans of the mission protocol, one per MAV_MISSION_TYPE (mission, fence, rally),
//! as uploaded, with their ids, and the stateless downloads answered from them
//! (docs/mavlink.md §7). A plan changes only when the vehicle took a validated upload of its
//! type, or on a clear.
//!
//! A plan's id is PX4's (`MavlinkMissionManager::crc32_for_mission_item`): [`crc32_part`] chained
//! from 0 over each item's packed 32-byte `CrcMissionItem_t` in upload order, 0 for no plan. It
//! goes out as `opaque_id` in the upload's final MISSION_ACK and in MISSION_COUNT of a download,
//! and as `mission_id` / `fence_id` / `rally_points_id` in MISSION_CURRENT.
//!
//! ArduCopter's face (docs/ardupilot.md §6) downloads its mission with the home slot: item 0 is
//! the vehicle's home whatever was uploaded there, the count is at least 1 (home alone), and an
//! item is answered in the form it was asked for (MISSION_REQUEST → MISSION_ITEM). Pure.

use mavlink::dialects::ardupilotmega::{
    MavMessage, MavMissionResult, MavMissionType, MISSION_COUNT_DATA, MISSION_ITEM_INT_DATA,
};

use super::ardupilot::copter_mission::{current_flag, home_item, item_float};
use super::crc32::crc32_part;
use super::identity::Personality;
use super::mission_xfer::{mission_ack, Ids};
use crate::guidance::Home;

/// The plans a vehicle stores, by type, each with its id.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PlanStore {
    mission: Vec<MISSION_ITEM_INT_DATA>,
    fence: Vec<MISSION_ITEM_INT_DATA>,
    rally: Vec<MISSION_ITEM_INT_DATA>,
    ids: PlanIds,
    /// Whose face the downloads show (PX4's or ArduCopter's).
    personality: Personality,
    /// The seq of the navigation item ArduCopter's mission is at (`None` before it started),
    /// which its downloads' `current` flag compares with.
    nav_seq: Option<u16>,
}

/// The ids of the stored plans (0: none stored).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct PlanIds {
    /// The mission's.
    pub mission: u32,
    /// The fence's.
    pub fence: u32,
    /// The rally points'.
    pub rally: u32,
}

/// PX4's `CrcMissionItem_t` of `item`, packed little-endian: frame (u8), command (u16),
/// autocontinue (u8), then param1..4, x, y, z as 32-bit words. PX4 decodes a MISSION_ITEM_INT
/// through the MISSION_ITEM layout, so x and y are the integers' bit patterns.
fn crc_item(item: &MISSION_ITEM_INT_DATA) -> [u8; 32] {
    let mut b = [0u8; 32];
    b[0] = item.frame as u8;
    b[1..3].copy_from_slice(&(item.command as u16).to_le_bytes());
    b[3] = item.autocontinue;
    let words = [
        item.param1.to_bits(),
        item.param2.to_bits(),
        item.param3.to_bits(),
        item.param4.to_bits(),
        item.x as u32,
        item.y as u32,
        item.z.to_bits(),
    ];
    for (k, w) in words.iter().enumerate() {
        b[4 + 4 * k..8 + 4 * k].copy_from_slice(&w.to_le_bytes());
    }
    b
}

/// The id PX4 gives a plan of `items`: [`crc32_part`] from 0 over each item's [`crc_item`]
/// (0 for no items).
pub fn plan_id(items: &[MISSION_ITEM_INT_DATA]) -> u32 {
    items.iter().fold(0, |crc, item| crc32_part(&crc_item(item), crc))
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
    /// No plan, downloaded as `personality` answers.
    pub fn new(personality: Personality) -> Self {
        Self {
            personality,
            ..Self::default()
        }
    }

    /// True when downloads of plan `mission_type` go as ArduCopter answers them (its mission).
    fn copter(&self, mission_type: MavMissionType) -> bool {
        self.personality == Personality::ArduPilot && mission_type == MavMissionType::MAV_MISSION_TYPE_MISSION
    }

    /// The mission is at navigation item `nav_seq` as the link numbers it (`None`: not started
    /// since it was stored), for ArduCopter's `current` flag.
    pub fn handle_nav_seq(&mut self, nav_seq: Option<u16>) {
        self.nav_seq = nav_seq;
    }

    /// The items of plan `mission_type` (none for a type not stored).
    pub fn items(&self, mission_type: MavMissionType) -> &[MISSION_ITEM_INT_DATA] {
        match mission_type {
            MavMissionType::MAV_MISSION_TYPE_MISSION => &self.mission,
            MavMissionType::MAV_MISSION_TYPE_FENCE => &self.fence,
            MavMissionType::MAV_MISSION_TYPE_RALLY => &self.rally,
            _ => &[],
        }
    }

    /// Replaces plan `mission_type` and its id (a type not stored is ignored).
    pub fn set(&mut self, mission_type: MavMissionType, items: Vec<MISSION_ITEM_INT_DATA>) {
        let id = plan_id(&items);
        match mission_type {
            MavMissionType::MAV_MISSION_TYPE_MISSION => (self.mission, self.ids.mission) = (items, id),
            MavMissionType::MAV_MISSION_TYPE_FENCE => (self.fence, self.ids.fence) = (items, id),
            MavMissionType::MAV_MISSION_TYPE_RALLY => (self.rally, self.ids.rally) = (items, id),
            _ => {}
        }
    }

    /// The id of plan `mission_type` (0 when none is stored or for a type not stored).
    pub fn id(&self, mission_type: MavMissionType) -> u32 {
        match mission_type {
            MavMissionType::MAV_MISSION_TYPE_MISSION => self.ids.mission,
            MavMissionType::MAV_MISSION_TYPE_FENCE => self.ids.fence,
            MavMissionType::MAV_MISSION_TYPE_RALLY => self.ids.rally,
            _ => 0,
        }
    }

    /// The ids of the three plans.
    pub fn ids(&self) -> PlanIds {
        self.ids
    }

    /// MISSION_COUNT of plan `mission_type` for a download, addressed to `ids`, with the plan's
    /// id as `opaque_id`; ArduCopter's mission counts its home slot (1 with nothing uploaded).
    pub fn download_count(&self, ids: Ids, mission_type: MavMissionType) -> MavMessage {
        let stored = self.items(mission_type).len() as u16;
        MavMessage::MISSION_COUNT(MISSION_COUNT_DATA {
            count: if self.copter(mission_type) {
                stored.max(1)
            } else {
                stored
            },
            target_system: ids.0,
            target_component: ids.1,
            mission_type,
            opaque_id: self.id(mission_type),
        })
    }

    /// Item `seq` of plan `mission_type` addressed to `ids`, or a MISSION_ACK(INVALID_SEQUENCE)
    /// of that type. PX4 answers with MISSION_ITEM_INT; ArduCopter's mission answers item 0
    /// with `home`, and ArduCopter answers each item of every plan in the form asked for:
    /// MISSION_ITEM_INT for a MISSION_REQUEST_INT (`int_form`), MISSION_ITEM otherwise.
    #[allow(deprecated)] // MISSION_ITEM: what DroneKit downloads
    pub fn download_item(
        &self,
        ids: Ids,
        mission_type: MavMissionType,
        seq: u16,
        int_form: bool,
        home: &Home,
    ) -> MavMessage {
        let copter = self.copter(mission_type);
        let int_form = int_form || self.personality == Personality::Px4;
        let item = match (copter, seq) {
            (true, 0) => Some(home_item(home)),
            _ => self.items(mission_type).get(usize::from(seq)).cloned(),
        };
        let Some(item) = item else {
            return mission_ack(ids, mission_type, MavMissionResult::MAV_MISSION_INVALID_SEQUENCE);
        };
        let item = MISSION_ITEM_INT_DATA {
            target_system: ids.0,
            target_component: ids.1,
            mission_type,
            current: if copter {
                current_flag(item.command, self.nav_seq)
            } else {
                item.current
            },
            ..item
        };
        if !int_form {
            MavMessage::MISSION_ITEM(item_float(&item))
        } else {
            MavMessage::MISSION_ITEM_INT(item)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mavlink::dialects::ardupilotmega::{MavCmd, MavFrame};

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

    /// The CRC from its definition, bit by bit: reflected polynomial 0xEDB88320, from `crc`,
    /// no inversion before or after.
    fn crc_by_bits(data: &[u8], mut crc: u32) -> u32 {
        for b in data {
            crc ^= u32::from(*b);
            for _ in 0..8 {
                crc = if crc & 1 == 1 {
                    (crc >> 1) ^ 0xEDB8_8320
                } else {
                    crc >> 1
                };
            }
        }
        crc
    }

    /// A waypoint 10 m up in MAV_FRAME_GLOBAL_RELATIVE_ALT (as QGroundControl sends it in
    /// MISSION_ITEM_INT), then RETURN_TO_LAUNCH.
    fn two_items() -> Vec<MISSION_ITEM_INT_DATA> {
        let wp = MISSION_ITEM_INT_DATA {
            frame: mavlink::dialects::ardupilotmega::MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT,
            command: MavCmd::MAV_CMD_NAV_WAYPOINT,
            autocontinue: 1,
            param2: 2.0,
            param4: 90.0,
            x: 473_977_418,
            y: 85_455_939,
            z: 10.0,
            ..item(0, MavCmd::MAV_CMD_NAV_WAYPOINT)
        };
        let rtl = MISSION_ITEM_INT_DATA {
            frame: mavlink::dialects::ardupilotmega::MavFrame::MAV_FRAME_MISSION,
            autocontinue: 1,
            ..item(1, MavCmd::MAV_CMD_NAV_RETURN_TO_LAUNCH)
        };
        vec![wp, rtl]
    }

    #[test]
    fn a_plan_id_is_px4s_crc_over_the_packed_items() {
        let items = two_items();
        // The packed struct written out field by field: frame 3, command 16, autocontinue 1,
        // param1..4, x and y as their integers' bytes, z.
        let mut wp = vec![3u8, 16, 0, 1];
        for f in [0.0f32, 2.0, 0.0, 90.0] {
            wp.extend(f.to_le_bytes());
        }
        wp.extend(473_977_418i32.to_le_bytes());
        wp.extend(85_455_939i32.to_le_bytes());
        wp.extend(10.0f32.to_le_bytes());
        let mut rtl = vec![2u8, 20, 0, 1];
        rtl.extend([0u8; 28]);
        assert_eq!(wp.len(), 32);
        let expected = crc_by_bits(&rtl, crc_by_bits(&wp, 0));
        assert_eq!(plan_id(&items), expected);
        // The same value from Python: `~zlib.crc32(wp + rtl, 0xFFFFFFFF) & 0xFFFFFFFF`.
        assert_eq!(expected, 0xB3C5_B097);
        assert_eq!(plan_id(&[]), 0, "no plan");
        // What a MISSION_ITEM_INT does not carry into the struct leaves the id alone.
        let mut moved = items.clone();
        moved[0].seq = 9;
        moved[0].current = 1;
        moved[0].mission_type = MavMissionType::MAV_MISSION_TYPE_FENCE;
        assert_eq!(plan_id(&moved), expected);
        moved[0].y += 1;
        assert_ne!(plan_id(&moved), expected);
    }

    #[test]
    fn each_plan_keeps_its_id_and_a_download_names_it() {
        let mut store = PlanStore::default();
        assert_eq!(store.ids(), PlanIds::default());
        store.set(RALLY, two_items());
        let id = plan_id(&two_items());
        assert_eq!(
            store.ids(),
            PlanIds {
                rally: id,
                ..PlanIds::default()
            }
        );
        let MavMessage::MISSION_COUNT(c) = store.download_count(GCS, RALLY) else {
            panic!()
        };
        assert_eq!((c.count, c.opaque_id), (2, id));
        let MavMessage::MISSION_COUNT(c) = store.download_count(GCS, MISSION) else {
            panic!()
        };
        assert_eq!((c.count, c.opaque_id), (0, 0));
        store.set(RALLY, Vec::new());
        assert_eq!(
            (store.id(RALLY), store.id(MavMissionType::MAV_MISSION_TYPE_ALL)),
            (0, 0)
        );
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
        let rally0 = store.download_item(GCS, RALLY, 0, false, &Home::default());
        assert!(
            matches!(rally0, MavMessage::MISSION_ITEM_INT(ref i) if i.command == MavCmd::MAV_CMD_NAV_RALLY_POINT && i.target_system == 255)
        );
        assert_eq!(typed(&rally0), Some((RALLY, 0)));
        let invalid = MavMissionResult::MAV_MISSION_INVALID_SEQUENCE as u32;
        assert_eq!(
            typed(&store.download_item(GCS, RALLY, 1, false, &Home::default())),
            Some((RALLY, invalid))
        );
        assert_eq!(
            typed(&store.download_item(GCS, FENCE, 0, false, &Home::default())),
            Some((FENCE, invalid))
        );
        // A stored item answers with the type asked for, whatever it was uploaded with.
        let stray = MISSION_ITEM_INT_DATA {
            mission_type: FENCE,
            ..item(0, MavCmd::MAV_CMD_NAV_WAYPOINT)
        };
        store.set(MISSION, vec![stray]);
        assert_eq!(
            typed(&store.download_item(GCS, MISSION, 0, false, &Home::default())),
            Some((MISSION, 0))
        );
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

    #[test]
    #[allow(deprecated)] // MISSION_ITEM: what DroneKit downloads
    fn arducopter_downloads_its_mission_with_home_in_slot_0_in_the_form_asked_for() {
        let home = Home {
            lat_deg: -35.363_261,
            lon_deg: 149.165_23,
            alt_amsl_m: 584.0,
        };
        let mut store = PlanStore::new(Personality::ArduPilot);
        let count = |store: &PlanStore, t| match store.download_count(GCS, t) {
            MavMessage::MISSION_COUNT(c) => c.count,
            _ => u16::MAX,
        };
        assert_eq!(count(&store, MISSION), 1, "home alone");
        assert_eq!(count(&store, FENCE), 0, "no home slot in a fence");
        let MavMessage::MISSION_ITEM(h) = store.download_item(GCS, MISSION, 0, false, &home) else {
            panic!("MISSION_REQUEST is answered with MISSION_ITEM")
        };
        assert_eq!(
            (h.seq, h.command, h.frame),
            (0, MavCmd::MAV_CMD_NAV_WAYPOINT, MavFrame::MAV_FRAME_GLOBAL)
        );
        assert_eq!(
            (h.x, h.y, h.z, h.target_system),
            (home.lat_deg as f32, home.lon_deg as f32, 584.0, 255)
        );
        let uploaded = MISSION_ITEM_INT_DATA {
            frame: MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT,
            x: -353_632_610,
            y: 1_491_652_300,
            z: 5.0,
            ..item(0, MavCmd::MAV_CMD_NAV_TAKEOFF)
        };
        let wp = MISSION_ITEM_INT_DATA {
            x: -353_640_000,
            ..item(1, MavCmd::MAV_CMD_NAV_WAYPOINT)
        };
        store.set(MISSION, vec![uploaded, wp]);
        assert_eq!(count(&store, MISSION), 2);
        let MavMessage::MISSION_ITEM_INT(h) = store.download_item(GCS, MISSION, 0, true, &home) else {
            panic!("MISSION_REQUEST_INT is answered with MISSION_ITEM_INT")
        };
        assert_eq!(
            (h.command, h.x, h.y, h.z),
            (MavCmd::MAV_CMD_NAV_WAYPOINT, -353_632_610, 1_491_652_300, 584.0)
        );
        let MavMessage::MISSION_ITEM(w) = store.download_item(GCS, MISSION, 1, false, &home) else {
            panic!()
        };
        assert_eq!(
            (w.seq, w.command, w.x),
            (1, MavCmd::MAV_CMD_NAV_WAYPOINT, -35.364f64 as f32)
        );
        let invalid = MavMissionResult::MAV_MISSION_INVALID_SEQUENCE as u32;
        assert_eq!(
            typed(&store.download_item(GCS, MISSION, 2, false, &home)),
            Some((MISSION, invalid))
        );
        // PX4 answers every request with MISSION_ITEM_INT and has no home slot.
        let mut px4 = PlanStore::default();
        assert_eq!(count(&px4, MISSION), 0);
        px4.set(MISSION, store.items(MISSION).to_vec());
        assert!(matches!(
            px4.download_item(GCS, MISSION, 0, false, &home),
            MavMessage::MISSION_ITEM_INT(ref i) if i.command == MavCmd::MAV_CMD_NAV_TAKEOFF
        ));
    }
}
