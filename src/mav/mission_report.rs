//! MISSION_CURRENT (42) as PX4 fills it (`MavlinkMissionManager::send_mission_current` and
//! `update_mission_state`, docs/mavlink.md §7): the current item, the item count (UINT16_MAX
//! without a mission), the plan ids of the stored mission, fence and rally points
//! ([`PlanIds`]), and PX4's mission mode and mission state, which need a little memory:
//!
//! - `mission_mode`: 0 until the vehicle's first state, then 1 (ACTIVE) in AUTO.MISSION,
//!   AUTO.TAKEOFF and AUTO.LAND, 2 (SUSPENDED) in any other mode;
//! - `mission_state`: NO_MISSION without items; else COMPLETE once the mission finished; else
//!   ACTIVE while the mode is active; else PAUSED once an item of this mission was reached; else
//!   NOT_STARTED while nothing was reached and the current item is the first; otherwise it stays
//!   what it was (UNKNOWN before the vehicle's first state).
//!
//! "Reached" is PX4's `mission_result.seq_reached` as the MAVLink module last saw it: the latest
//! MISSION_ITEM_REACHED, forgotten when another mission is stored (a new plan id).
//!
//! ArduCopter's face (docs/ardupilot.md §6, `GCS_MAVLINK::send_mission_current`) numbers the
//! items from 1 (slot 0 is home): MISSION_CURRENT and MISSION_ITEM_REACHED carry the
//! commander's item + 1 (MISSION_CURRENT 0 without a mission); the total counts the flown items
//! (0 without), the state is Copter's (NOT_STARTED while stopped, ACTIVE while running,
//! COMPLETE), and the mode 1 in AUTO, 0 otherwise. Pure.

use mavlink::dialects::ardupilotmega::{
    MavMessage, MissionState as MavMissionState, MISSION_CURRENT_DATA, MISSION_ITEM_REACHED_DATA,
};

use super::ardupilot::copter_mission::link_seq;
use super::identity::Personality;
use crate::commander::{FlightMode, MissionState};
use crate::telemetry::Snapshot;

pub use super::plan_store::PlanIds;

/// MISSION_MODE: a mode that flies mission items.
const MODE_ACTIVE: u8 = 1;
/// MISSION_MODE: any other mode.
const MODE_SUSPENDED: u8 = 2;

/// What MISSION_CURRENT remembers between vehicle states.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MissionReport {
    mode: u8,
    state: MavMissionState,
    reached: Option<u16>,
    mission_id: u32,
    /// Whose face the reports show (PX4's or ArduCopter's).
    personality: Personality,
}

impl Default for MissionReport {
    /// PX4's.
    fn default() -> Self {
        Self::new(Personality::Px4)
    }
}

impl MissionReport {
    /// Nothing known yet, reported as `personality` reports.
    pub fn new(personality: Personality) -> Self {
        Self {
            mode: 0,
            state: MavMissionState::MISSION_STATE_UNKNOWN,
            reached: None,
            mission_id: 0,
            personality,
        }
    }

    /// The commander's mission item `seq` was reached: noted, and the MISSION_ITEM_REACHED
    /// that announces it (ArduCopter's numbered from 1).
    pub fn handle_reached(&mut self, seq: u16) -> MavMessage {
        self.reached = Some(seq);
        let seq = match self.personality {
            Personality::Px4 => seq,
            Personality::ArduPilot => link_seq(seq),
        };
        MavMessage::MISSION_ITEM_REACHED(MISSION_ITEM_REACHED_DATA { seq })
    }

    /// The vehicle's latest state `s` with the stored plans' `ids`: the mode and state again.
    pub fn handle_state(&mut self, s: &Snapshot, ids: PlanIds) {
        if ids.mission != self.mission_id {
            self.mission_id = ids.mission;
            self.reached = None;
        }
        self.mode = if matches!(s.mode, FlightMode::Mission | FlightMode::Takeoff | FlightMode::Land) {
            MODE_ACTIVE
        } else {
            MODE_SUSPENDED
        };
        self.state = if s.mission_total == 0 || s.mission_state == MissionState::NoMission {
            MavMissionState::MISSION_STATE_NO_MISSION
        } else if s.mission_state == MissionState::Complete {
            MavMissionState::MISSION_STATE_COMPLETE
        } else if self.mode == MODE_ACTIVE {
            MavMissionState::MISSION_STATE_ACTIVE
        } else if self.reached.is_some() {
            MavMissionState::MISSION_STATE_PAUSED
        } else if s.mission_seq < 1 {
            MavMissionState::MISSION_STATE_NOT_STARTED
        } else {
            self.state
        };
    }

    /// MISSION_CURRENT for the commander's item `seq` of the mission in `s`, naming the plans
    /// by `ids`.
    pub fn mission_current(&self, s: &Snapshot, seq: u16, ids: PlanIds) -> MavMessage {
        if self.personality == Personality::ArduPilot {
            return copter_mission_current(s, seq);
        }
        MavMessage::MISSION_CURRENT(MISSION_CURRENT_DATA {
            seq,
            total: if s.mission_total == 0 {
                u16::MAX
            } else {
                s.mission_total
            },
            mission_state: self.state,
            mission_mode: self.mode,
            mission_id: ids.mission,
            fence_id: ids.fence,
            rally_points_id: ids.rally,
        })
    }
}

/// ArduCopter's MISSION_CURRENT for the commander's item `seq` of the mission in `s`. ArduCopter
/// 4.5 names no plan: `mission_id`, `fence_id` and `rally_points_id` are 0 (it sends the
/// message's first five fields only).
fn copter_mission_current(s: &Snapshot, seq: u16) -> MavMessage {
    let none = s.mission_total == 0 || s.mission_state == MissionState::NoMission;
    let mission_state = match s.mission_state {
        _ if none => MavMissionState::MISSION_STATE_NO_MISSION,
        MissionState::Active => MavMissionState::MISSION_STATE_ACTIVE,
        MissionState::Complete => MavMissionState::MISSION_STATE_COMPLETE,
        _ => MavMissionState::MISSION_STATE_NOT_STARTED,
    };
    MavMessage::MISSION_CURRENT(MISSION_CURRENT_DATA {
        seq: if none { 0 } else { link_seq(seq) },
        total: if none { 0 } else { s.mission_total },
        mission_state,
        mission_mode: u8::from(s.mode == FlightMode::Mission),
        ..Default::default()
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::guidance::Home;
    use MavMissionState::*;

    fn snapshot(mode: FlightMode, seq: u16, total: u16, state: MissionState) -> Snapshot {
        Snapshot {
            mode,
            mission_seq: seq,
            mission_total: total,
            mission_state: state,
            ..Snapshot::initial(Home::default())
        }
    }

    fn current(r: &MissionReport, s: &Snapshot, ids: PlanIds) -> MISSION_CURRENT_DATA {
        let MavMessage::MISSION_CURRENT(m) = r.mission_current(s, s.mission_seq, ids) else {
            panic!()
        };
        m
    }

    #[test]
    fn unknown_before_the_first_state_then_no_mission_and_the_ids() {
        let mut r = MissionReport::default();
        let s = Snapshot::initial(Home::default());
        let none = current(&r, &s, PlanIds::default());
        assert_eq!(
            (none.mission_state, none.mission_mode, none.total),
            (MISSION_STATE_UNKNOWN, 0, u16::MAX)
        );
        let ids = PlanIds {
            mission: 0,
            fence: 7,
            rally: 9,
        };
        r.handle_state(&s, ids);
        let m = current(&r, &s, ids);
        assert_eq!((m.mission_state, m.mission_mode), (MISSION_STATE_NO_MISSION, 2));
        assert_eq!((m.mission_id, m.fence_id, m.rally_points_id), (0, 7, 9));
    }

    #[test]
    fn a_mission_runs_through_px4s_states() {
        use FlightMode::{Land, Loiter, Mission, Takeoff};
        let ids = PlanIds {
            mission: 42,
            ..PlanIds::default()
        };
        let mut r = MissionReport::default();
        let step = |r: &mut MissionReport, mode, seq, state| {
            let s = snapshot(mode, seq, 3, state);
            r.handle_state(&s, ids);
            let m = current(r, &s, ids);
            (m.mission_state, m.mission_mode)
        };
        assert_eq!(
            step(&mut r, Loiter, 0, MissionState::NotStarted),
            (MISSION_STATE_NOT_STARTED, 2)
        );
        // AUTO.TAKEOFF and AUTO.LAND count as active mission modes, as in PX4.
        assert_eq!(
            step(&mut r, Takeoff, 0, MissionState::NotStarted),
            (MISSION_STATE_ACTIVE, 1)
        );
        assert_eq!(
            step(&mut r, Loiter, 0, MissionState::NotStarted),
            (MISSION_STATE_NOT_STARTED, 2)
        );
        assert_eq!(
            step(&mut r, Mission, 0, MissionState::Active),
            (MISSION_STATE_ACTIVE, 1)
        );
        r.handle_reached(0);
        assert_eq!(
            step(&mut r, Mission, 1, MissionState::Active),
            (MISSION_STATE_ACTIVE, 1)
        );
        assert_eq!(step(&mut r, Loiter, 1, MissionState::Paused), (MISSION_STATE_PAUSED, 2));
        assert_eq!(step(&mut r, Land, 1, MissionState::Paused), (MISSION_STATE_ACTIVE, 1));
        r.handle_reached(2);
        assert_eq!(
            step(&mut r, Loiter, 2, MissionState::Complete),
            (MISSION_STATE_COMPLETE, 2)
        );
        // Another mission (another id): nothing reached yet.
        let other = PlanIds {
            mission: 43,
            ..PlanIds::default()
        };
        let s = snapshot(Loiter, 0, 2, MissionState::NotStarted);
        r.handle_state(&s, other);
        assert_eq!(current(&r, &s, other).mission_state, MISSION_STATE_NOT_STARTED);
    }

    #[test]
    fn a_state_px4_does_not_decide_stays_what_it_was() {
        let ids = PlanIds {
            mission: 5,
            ..PlanIds::default()
        };
        let mut r = MissionReport::default();
        let active = snapshot(FlightMode::Mission, 2, 4, MissionState::Active);
        r.handle_state(&active, ids);
        // Left before any item was reached, at item 2: PX4 leaves the state as it was.
        let left = snapshot(FlightMode::Loiter, 2, 4, MissionState::Paused);
        r.handle_state(&left, ids);
        assert_eq!(current(&r, &left, ids).mission_state, MISSION_STATE_ACTIVE);
    }

    #[test]
    fn arducopter_numbers_from_1_and_reports_its_own_states() {
        let ids = PlanIds {
            mission: 9,
            ..PlanIds::default()
        };
        let mut r = MissionReport::new(Personality::ArduPilot);
        let step = |r: &mut MissionReport, mode, seq, total, state| {
            let s = snapshot(mode, seq, total, state);
            r.handle_state(&s, ids);
            let m = current(r, &s, ids);
            (m.seq, m.total, m.mission_state, m.mission_mode)
        };
        assert_eq!(
            step(&mut r, FlightMode::Loiter, 0, 0, MissionState::NoMission),
            (0, 0, MISSION_STATE_NO_MISSION, 0)
        );
        assert_eq!(
            step(&mut r, FlightMode::Loiter, 0, 5, MissionState::NotStarted),
            (1, 5, MISSION_STATE_NOT_STARTED, 0)
        );
        assert_eq!(
            step(&mut r, FlightMode::Mission, 2, 5, MissionState::Active),
            (3, 5, MISSION_STATE_ACTIVE, 1)
        );
        assert_eq!(
            step(&mut r, FlightMode::Position, 2, 5, MissionState::Paused),
            (3, 5, MISSION_STATE_NOT_STARTED, 0)
        );
        assert_eq!(
            step(&mut r, FlightMode::Loiter, 4, 5, MissionState::Complete),
            (5, 5, MISSION_STATE_COMPLETE, 0),
            "on the last item seq == total"
        );
        assert_eq!(
            r.handle_reached(4),
            MavMessage::MISSION_ITEM_REACHED(MISSION_ITEM_REACHED_DATA { seq: 5 })
        );
        let s = snapshot(FlightMode::Mission, 2, 5, MissionState::Active);
        let m = current(&r, &s, ids);
        assert_eq!(
            (m.mission_id, m.fence_id, m.rally_points_id),
            (0, 0, 0),
            "4.5 names no plan"
        );
        // PX4 reports the commander's numbers.
        assert_eq!(
            MissionReport::default().handle_reached(4),
            MavMessage::MISSION_ITEM_REACHED(MISSION_ITEM_REACHED_DATA { seq: 4 })
        );
    }
}
