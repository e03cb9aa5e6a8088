//! AUTO.MISSION execution and progress (docs/mavlink.md §7): one item at a time, each
//! turned into guidance; reached items are announced; after the last item the vehicle loiters
//! (unless it landed or returns). Waypoints are flown on a [`Track`]: a waypoint without a hold
//! followed by another position is flown through at its corner speed and counts as reached once
//! the vehicle is within its acceptance radii (`NAV_ACC_RAD` or the item's, `NAV_MC_ALT_RAD`), as
//! PX4's navigator does; the others are arrived at standing still.

use crate::control::VehicleState;
use crate::math::Vec3;
use crate::navigation::{Guidance, Mission, MissionItem, Track, TrackLeg};

use super::{Commander, Event, FlightMode};

/// Distance within which a take-off or the end of a travel leg counts as arrived [m].
const ARRIVE_M: f64 = 0.2;

/// MAVLink MISSION_STATE.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MissionState {
    /// No mission stored.
    NoMission,
    /// Stored, not started.
    NotStarted,
    /// Being flown.
    Active,
    /// Paused (another mode took over).
    Paused,
    /// Finished.
    Complete,
}

/// Progress through the stored mission.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct MissionRun {
    pub mission: Mission,
    pub seq: usize,
    pub state: MissionState,
    phase: Phase,
    speed_m_s: Option<f64>,
    /// How often each item's DO_JUMP was taken (by item index).
    jumps_taken: Vec<u32>,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Phase {
    /// The item's guidance is not set yet.
    Start,
    /// Climbing vertically to the first item's height (started on the ground with an item
    /// that is not a take-off, as PX4 does).
    ClimbFirst,
    /// Flying to the item's point.
    Travel,
    /// Holding until the time [s].
    Hold(f64),
    /// Descending to land.
    Landing,
    /// The mission ended here (landed).
    Done,
}

impl Default for MissionRun {
    fn default() -> Self {
        Self {
            mission: Mission::default(),
            seq: 0,
            state: MissionState::NoMission,
            phase: Phase::Start,
            speed_m_s: None,
            jumps_taken: Vec::new(),
        }
    }
}

impl MissionRun {
    /// A new stored mission, not started.
    pub fn replace(&mut self, mission: Mission) {
        self.state = if mission.is_empty() {
            MissionState::NoMission
        } else {
            MissionState::NotStarted
        };
        self.jumps_taken = vec![0; mission.len()];
        self.mission = mission;
        self.seq = 0;
        self.phase = Phase::Start;
        self.speed_m_s = None;
    }

    /// Starts (or resumes) flying at the current item; a finished mission starts over.
    pub fn start(&mut self) {
        if self.state == MissionState::Complete {
            self.seq = 0;
            self.jumps_taken.fill(0);
        }
        self.state = MissionState::Active;
        self.phase = Phase::Start;
    }

    /// Goes on at item `seq` (`reset`: the DO_JUMP counts start over); false when there is no
    /// such item.
    pub fn set_current(&mut self, seq: usize, reset: bool) -> bool {
        if seq >= self.mission.len() {
            return false;
        }
        if reset {
            self.jumps_taken.fill(0);
        }
        self.seq = seq;
        self.phase = Phase::Start;
        if self.state == MissionState::Complete {
            self.state = MissionState::NotStarted;
        }
        true
    }

    /// DO_JUMP item `seq` reached: the item the mission goes on at, counting the jump when it is
    /// taken (PX4: `repeat` times, then past it).
    fn resolve_jump(&mut self, target: usize, repeat: Option<u32>) -> usize {
        let taken = self.jumps_taken.get(self.seq).copied().unwrap_or(0);
        if repeat.is_none_or(|r| taken < r) {
            if let Some(t) = self.jumps_taken.get_mut(self.seq) {
                *t = t.saturating_add(1);
            }
            target
        } else {
            self.seq + 1
        }
    }
}

impl Commander {
    /// MISSION_SET_CURRENT / DO_SET_MISSION_CURRENT: the mission goes on at `seq` (flown from
    /// there at once in AUTO.MISSION; a DO_JUMP there is resolved as if reached).
    pub(super) fn set_mission_current(&mut self, seq: Option<usize>, reset: bool) -> super::Outcome {
        let seq = seq.unwrap_or(self.mission.seq);
        if self.mission.set_current(seq, reset) {
            self.pending.push(Event::MissionCurrent(seq as u16));
            super::Outcome::Accepted
        } else {
            super::Outcome::Denied(format!(
                "Mission: no item {seq} (the mission has {})",
                self.mission.mission.len()
            ))
        }
    }

    /// One tick of AUTO.MISSION.
    pub(super) fn advance_mission(&mut self, x: &VehicleState, yaw: f64, t_s: f64, events: &mut Vec<Event>) {
        // Heights above home follow a home moved in flight (PX4 reads them at flight time).
        let Some(item) = self.mission.mission.item_at_home(self.mission.seq, self.home_w.z) else {
            return;
        };
        let speed = self.mission.speed_m_s.unwrap_or(self.cruise_speed());
        let on_ground = !self.in_air();
        match (self.mission.phase, item) {
            (Phase::Start, MissionItem::Takeoff { height_m }) => {
                let target = Vec3::new(x.pos_w.x, x.pos_w.y, -height_m);
                self.takeoff_target_w = Some(target);
                self.climbing_out = on_ground;
                self.guidance = if on_ground {
                    self.climb_to(x, target, yaw, t_s)
                } else {
                    self.path_to(x, target, yaw, self.cruise_speed(), t_s)
                };
                self.mission.phase = Phase::Travel;
            }
            (Phase::Start, MissionItem::Waypoint { pos_w, .. } | MissionItem::LoiterTime { pos_w, .. })
                if on_ground =>
            {
                // Take off straight up to the item's height (at least MIS_TAKEOFF_ALT) first.
                let height = (-pos_w.z).max(self.params.takeoff_alt_m);
                let target = Vec3::new(x.pos_w.x, x.pos_w.y, -height);
                self.takeoff_target_w = Some(target);
                self.climbing_out = true;
                self.guidance = self.climb_to(x, target, yaw, t_s);
                self.mission.phase = Phase::ClimbFirst;
            }
            (Phase::ClimbFirst, _) => {
                let target = self.takeoff_target_w.unwrap_or(x.pos_w);
                if self.guidance.finished(t_s) && (x.pos_w - target).norm() <= ARRIVE_M {
                    self.climbing_out = false;
                    self.mission.phase = Phase::Start;
                }
            }
            (Phase::Start, MissionItem::Waypoint { pos_w, .. } | MissionItem::LoiterTime { pos_w, .. }) => {
                let heading = match item {
                    MissionItem::Waypoint { yaw_rad: Some(y), .. } => y,
                    _ => yaw,
                };
                let leg = TrackLeg {
                    target_w: pos_w,
                    next_w: self.fly_through_to(&item),
                    accept_m: self.accept_radius(&item),
                    yaw_rad: heading,
                    cruise_m_s: speed,
                    corner_gain: self.params.mission.corner_gain,
                };
                self.guidance = match self.guidance {
                    // Flown on from the waypoint before: the reference keeps its motion.
                    Guidance::Track(mut track) => {
                        track.leg = leg;
                        Guidance::Track(track)
                    }
                    _ => Guidance::Track(Track::new(x.pos_w, x.vel_w, yaw, t_s, leg, self.limits(speed))),
                };
                self.mission.phase = Phase::Travel;
            }
            (Phase::Start, MissionItem::Land { pos_w }) => match pos_w {
                Some(p) if (p - x.pos_w).xy().norm() > ARRIVE_M => {
                    let above = Vec3::new(p.x, p.y, x.pos_w.z);
                    self.guidance = self.path_to(x, above, yaw, speed, t_s);
                    self.mission.phase = Phase::Travel;
                }
                _ => self.begin_landing(x, pos_w, yaw, t_s),
            },
            (Phase::Start, MissionItem::ReturnToLaunch) => {
                self.reached(events);
                self.mission.state = MissionState::Complete;
                self.enter(FlightMode::ReturnToLaunch, x, t_s);
                events.push(Event::ModeChanged(FlightMode::ReturnToLaunch));
            }
            (Phase::Start, MissionItem::ChangeSpeed { speed_m_s }) => {
                self.mission.speed_m_s = Some(speed_m_s);
                self.next_item(x, t_s, events);
            }
            (Phase::Start, MissionItem::Jump { target, repeat }) => {
                // Resolved at once, never flown: the item it leads to starts next tick.
                let next = self.mission.resolve_jump(target, repeat);
                self.go_on_at(next, x, t_s, events);
            }
            (Phase::Start, MissionItem::Delay { seconds }) => {
                self.guidance = Guidance::Hold {
                    pos_w: x.pos_w,
                    yaw_rad: yaw,
                };
                self.mission.phase = Phase::Hold(t_s + seconds);
            }
            (Phase::Travel, _) => {
                let goal = match item {
                    MissionItem::Takeoff { .. } => self.takeoff_target_w.unwrap_or(x.pos_w),
                    MissionItem::Waypoint { pos_w, .. } | MissionItem::LoiterTime { pos_w, .. } => pos_w,
                    MissionItem::Land { pos_w: Some(p) } => Vec3::new(p.x, p.y, x.pos_w.z),
                    _ => x.pos_w,
                };
                let moved = matches!(self.guidance, Guidance::Track(t) if t.leg.target_w != goal);
                if moved && matches!(item, MissionItem::Waypoint { .. } | MissionItem::LoiterTime { .. }) {
                    // Home moved in flight: the reference flies the item where it is now.
                    let next_w = self.fly_through_to(&item);
                    if let Guidance::Track(track) = &mut self.guidance {
                        track.leg.target_w = goal;
                        track.leg.next_w = next_w;
                    }
                }
                let accept = match item {
                    MissionItem::Waypoint { .. } => self.accept_radius(&item),
                    _ => ARRIVE_M,
                };
                let within = (x.pos_w - goal).xy().norm() <= accept.max(ARRIVE_M)
                    && (x.pos_w.z - goal.z).abs() <= self.params.mission.alt_accept_m.max(ARRIVE_M);
                let flown_through = matches!(self.guidance, Guidance::Track(t) if t.leg.next_w.is_some());
                if within && (flown_through || self.guidance.finished(t_s)) {
                    if matches!(item, MissionItem::Takeoff { .. }) {
                        self.climbing_out = false;
                    }
                    match item {
                        MissionItem::Land { pos_w } => self.begin_landing(x, pos_w, yaw, t_s),
                        MissionItem::Waypoint { hold_s, .. } if hold_s > 0.0 => {
                            self.mission.phase = Phase::Hold(t_s + hold_s)
                        }
                        MissionItem::LoiterTime { seconds, .. } => self.mission.phase = Phase::Hold(t_s + seconds),
                        _ => self.next_item(x, t_s, events),
                    }
                }
            }
            (Phase::Hold(until_s), _) if t_s >= until_s => self.next_item(x, t_s, events),
            (Phase::Landing, _) if on_ground => {
                self.reached(events);
                self.mission.state = MissionState::Complete;
                self.mission.phase = Phase::Done;
            }
            _ => {}
        }
    }

    /// The acceptance radius of `item` [m]: its own, else `NAV_ACC_RAD`.
    fn accept_radius(&self, item: &MissionItem) -> f64 {
        match item {
            MissionItem::Waypoint { accept_m: Some(r), .. } => *r,
            _ => self.params.mission.accept_m,
        }
    }

    /// Where the mission goes after `item` when `item` is flown through (a waypoint without a
    /// hold, followed by another position before anything that stops: PX4's "next" setpoint):
    /// the next position, `None` when the vehicle stops at `item`.
    fn fly_through_to(&self, item: &MissionItem) -> Option<Vec3> {
        let MissionItem::Waypoint { pos_w, hold_s, .. } = *item else {
            return None;
        };
        if hold_s > 0.0 {
            return None;
        }
        let mission = &self.mission.mission;
        for seq in self.mission.seq + 1..mission.len() {
            match mission.item_at_home(seq, self.home_w.z)? {
                MissionItem::ChangeSpeed { .. } => continue,
                MissionItem::Waypoint { pos_w: p, .. } | MissionItem::LoiterTime { pos_w: p, .. } => return Some(p),
                MissionItem::Land { pos_w: Some(p) } => return Some(Vec3::new(p.x, p.y, pos_w.z)),
                _ => return None,
            }
        }
        None
    }

    /// Descends over the item's position `at_w` (PX4 lands on the item, not where the vehicle
    /// happened to be when it came within the acceptance radius), or here without one.
    fn begin_landing(&mut self, x: &VehicleState, at_w: Option<Vec3>, yaw: f64, t_s: f64) {
        let mut guidance = self.descend(x, yaw, t_s);
        if let (Guidance::Descend { xy_w, .. }, Some(at_w)) = (&mut guidance, at_w) {
            *xy_w = at_w;
        }
        self.guidance = guidance;
        self.mission.phase = Phase::Landing;
    }

    fn reached(&mut self, events: &mut Vec<Event>) {
        events.push(Event::MissionItemReached(self.mission.seq as u16));
    }

    /// Marks the current item reached and moves on; after the last one, loiter here.
    fn next_item(&mut self, x: &VehicleState, t_s: f64, events: &mut Vec<Event>) {
        self.reached(events);
        self.go_on_at(self.mission.seq + 1, x, t_s, events);
    }

    /// The mission goes on at item `seq`; past the last one, it is complete and the vehicle
    /// loiters here.
    fn go_on_at(&mut self, seq: usize, x: &VehicleState, t_s: f64, events: &mut Vec<Event>) {
        self.mission.seq = seq;
        self.mission.phase = Phase::Start;
        if self.mission.seq >= self.mission.mission.len() {
            self.mission.seq = self.mission.mission.len().saturating_sub(1);
            self.mission.state = MissionState::Complete;
            self.enter(FlightMode::Loiter, x, t_s);
            events.push(Event::ModeChanged(FlightMode::Loiter));
        } else {
            events.push(Event::MissionCurrent(self.mission.seq as u16));
        }
    }
}

#[cfg(test)]
#[path = "mission_run_tests.rs"]
mod tests;
