//! AUTO.MISSION execution and progress (docs/mavlink.md §7): one item at a time, each
//! turned into guidance; reached items are announced; after the last item the vehicle loiters
//! (unless it landed or returns). Waypoints are flown on a [`Track`]: a waypoint without a hold
//! followed by another position is flown through at its corner speed and counts as reached once
//! the vehicle is within its acceptance radii (`NAV_ACC_RAD` or the item's, `NAV_MC_ALT_RAD`), as
//! PX4's navigator does; the others are arrived at standing still.

use crate::guidance::{Guidance, Mission, MissionItem, Track, TrackLeg};
use crate::math::Vec3;

use super::auto_paths::AutoPaths;
use super::{Event, FlightMode, Moment};

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
    mission: Mission,
    seq: usize,
    state: MissionState,
    phase: Phase,
    speed_m_s: Option<f64>,
    /// How often each item's DO_JUMP was taken (by item index).
    jumps_taken: Vec<u32>,
    /// Where the vehicle was when the current item started [m]: the position of the parts of
    /// an item that are the vehicle's ([`crate::guidance::HereParts`]).
    anchor_w: Option<Vec3>,
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
    /// Holding until the mission is left (NAV_LOITER_UNLIM).
    HoldForever,
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
            anchor_w: None,
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
        self.anchor_w = None;
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

    /// Current item, item count and mission state (MISSION_CURRENT).
    pub fn progress(&self) -> (usize, usize, MissionState) {
        (self.seq, self.mission.len(), self.state)
    }

    /// No mission is stored.
    pub fn is_empty(&self) -> bool {
        self.mission.is_empty()
    }

    /// The current item.
    pub fn seq(&self) -> usize {
        self.seq
    }

    /// MISSION_START from item `first` (a finished mission can be flown again); false when there
    /// is no such item.
    pub fn start_at(&mut self, first: usize) -> bool {
        if first >= self.mission.len() {
            return false;
        }
        self.seq = first;
        if self.state == MissionState::Complete {
            self.state = MissionState::NotStarted;
        }
        true
    }

    /// Another mode took over: an active mission is paused.
    pub fn pause(&mut self) {
        if self.state == MissionState::Active {
            self.state = MissionState::Paused;
        }
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

/// The commander's guidance as a mission flies it: what to fly, where a take-off climbs to and
/// whether a take-off climb is under way.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct MissionFlight {
    /// What to fly.
    pub guidance: Guidance,
    /// Where the take-off climbs to [m].
    pub takeoff_target_w: Option<Vec3>,
    /// A take-off climb is under way.
    pub climbing_out: bool,
}

impl MissionRun {
    /// One tick of AUTO.MISSION flying `flight`, planned by `paths`, the vehicle `in_air` or
    /// not: the flight from now on, and the mode to switch to when the mission hands over
    /// (AUTO.RTL for a return item, AUTO.LOITER after the last item). Reached items and the
    /// current one are announced in `events`.
    pub fn advance(
        &mut self,
        paths: &AutoPaths,
        in_air: bool,
        flight: MissionFlight,
        now: Moment,
        events: &mut Vec<Event>,
    ) -> (MissionFlight, Option<FlightMode>) {
        let mut f = flight;
        let then = self.tick(paths, in_air, &mut f, now, events);
        (f, then)
    }

    /// [`Self::advance`] on the flight `f`.
    fn tick(
        &mut self,
        paths: &AutoPaths,
        in_air: bool,
        f: &mut MissionFlight,
        now: Moment,
        events: &mut Vec<Event>,
    ) -> Option<FlightMode> {
        let Moment {
            x, yaw_rad: yaw, t_s, ..
        } = now;
        if self.phase == Phase::Start {
            self.anchor_w = Some(x.pos_w);
        }
        // Heights above home follow a home moved in flight (PX4 reads them at flight time).
        let item = self.item_at(self.seq, paths.home_z_m())?;
        let speed = self.speed_m_s.unwrap_or(paths.cruise_speed());
        let on_ground = !in_air;
        match (self.phase, item) {
            (Phase::Start, MissionItem::Takeoff { height_m }) => {
                let target = Vec3::new(x.pos_w.x, x.pos_w.y, -height_m);
                f.takeoff_target_w = Some(target);
                f.climbing_out = on_ground;
                f.guidance = if on_ground {
                    paths.climb_to(x, target, yaw, t_s)
                } else {
                    paths.path_to(x, target, yaw, paths.cruise_speed(), t_s)
                };
                self.phase = Phase::Travel;
            }
            (Phase::Start, MissionItem::Waypoint { pos_w, .. } | MissionItem::LoiterTime { pos_w, .. })
                if on_ground =>
            {
                // Take off straight up to the item's height (at least MIS_TAKEOFF_ALT) first.
                let height = (-pos_w.z).max(paths.params().takeoff_alt_m);
                let target = Vec3::new(x.pos_w.x, x.pos_w.y, -height);
                f.takeoff_target_w = Some(target);
                f.climbing_out = true;
                f.guidance = paths.climb_to(x, target, yaw, t_s);
                self.phase = Phase::ClimbFirst;
            }
            (Phase::ClimbFirst, _) => {
                let target = f.takeoff_target_w.unwrap_or(x.pos_w);
                if f.guidance.finished(t_s) && (x.pos_w - target).norm() <= ARRIVE_M {
                    f.climbing_out = false;
                    self.phase = Phase::Start;
                }
            }
            (Phase::Start, MissionItem::Waypoint { pos_w, .. } | MissionItem::LoiterTime { pos_w, .. }) => {
                let heading = match item {
                    MissionItem::Waypoint { yaw_rad: Some(y), .. } => y,
                    _ => yaw,
                };
                let leg = TrackLeg {
                    target_w: pos_w,
                    next_w: self.fly_through_to(&item, paths.home_z_m()),
                    accept_m: Self::accept_radius(paths, &item),
                    yaw_rad: heading,
                    cruise_m_s: speed,
                    corner_gain: paths.params().mission.corner_gain,
                };
                f.guidance = match f.guidance {
                    // Flown on from the waypoint before: the reference keeps its motion.
                    Guidance::Track(mut track) => {
                        track.leg = leg;
                        Guidance::Track(track)
                    }
                    _ => Guidance::Track(Track::new(x.pos_w, x.vel_w, yaw, t_s, leg, paths.limits(speed))),
                };
                self.phase = Phase::Travel;
            }
            (Phase::Start, MissionItem::Land { pos_w }) => match pos_w {
                Some(p) if (p - x.pos_w).xy().norm() > ARRIVE_M => {
                    let above = Vec3::new(p.x, p.y, x.pos_w.z);
                    f.guidance = paths.path_to(x, above, yaw, speed, t_s);
                    self.phase = Phase::Travel;
                }
                _ => self.begin_landing(paths, f, now, pos_w),
            },
            (Phase::Start, MissionItem::ReturnToLaunch) => {
                self.reached(events);
                self.state = MissionState::Complete;
                return Some(FlightMode::ReturnToLaunch);
            }
            (Phase::Start, MissionItem::ChangeSpeed { speed_m_s }) => {
                self.speed_m_s = Some(speed_m_s);
                return self.next_item(events);
            }
            (Phase::Start, MissionItem::Jump { target, repeat }) => {
                // Resolved at once, never flown: the item it leads to starts next tick.
                let next = self.resolve_jump(target, repeat);
                return self.go_on_at(next, events);
            }
            (Phase::Start, MissionItem::Delay { seconds }) => {
                f.guidance = Guidance::Hold {
                    pos_w: x.pos_w,
                    yaw_rad: yaw,
                };
                self.phase = Phase::Hold(t_s + seconds);
            }
            (Phase::Travel, _) => {
                let goal = match item {
                    MissionItem::Takeoff { .. } => f.takeoff_target_w.unwrap_or(x.pos_w),
                    MissionItem::Waypoint { pos_w, .. } | MissionItem::LoiterTime { pos_w, .. } => pos_w,
                    MissionItem::Land { pos_w: Some(p) } => Vec3::new(p.x, p.y, x.pos_w.z),
                    _ => x.pos_w,
                };
                let moved = matches!(f.guidance, Guidance::Track(t) if t.leg.target_w != goal);
                if moved && matches!(item, MissionItem::Waypoint { .. } | MissionItem::LoiterTime { .. }) {
                    // Home moved in flight: the reference flies the item where it is now.
                    let next_w = self.fly_through_to(&item, paths.home_z_m());
                    if let Guidance::Track(track) = &mut f.guidance {
                        track.leg.target_w = goal;
                        track.leg.next_w = next_w;
                    }
                }
                let accept = match item {
                    MissionItem::Waypoint { .. } => Self::accept_radius(paths, &item),
                    _ => ARRIVE_M,
                };
                let within = (x.pos_w - goal).xy().norm() <= accept.max(ARRIVE_M)
                    && (x.pos_w.z - goal.z).abs() <= paths.params().mission.alt_accept_m.max(ARRIVE_M);
                let flown_through = matches!(f.guidance, Guidance::Track(t) if t.leg.next_w.is_some());
                if within && (flown_through || f.guidance.finished(t_s)) {
                    if matches!(item, MissionItem::Takeoff { .. }) {
                        f.climbing_out = false;
                    }
                    match item {
                        MissionItem::Land { pos_w } => self.begin_landing(paths, f, now, pos_w),
                        MissionItem::Waypoint { hold_s, .. } if hold_s > 0.0 => self.phase = Phase::Hold(t_s + hold_s),
                        MissionItem::LoiterTime { seconds, .. } => {
                            self.phase = seconds.map_or(Phase::HoldForever, |s| Phase::Hold(t_s + s));
                        }
                        _ => return self.next_item(events),
                    }
                }
            }
            (Phase::Hold(until_s), _) if t_s >= until_s => return self.next_item(events),
            (Phase::Landing, _) if on_ground => {
                self.reached(events);
                self.state = MissionState::Complete;
                self.phase = Phase::Done;
            }
            _ => {}
        }
        None
    }

    /// Item `seq` as flown with home at `home_z_m` [m] (NED z): the parts of its position that
    /// are the vehicle's are where the vehicle was when the current item started; a later item
    /// with such parts is not known yet (`None`: the mission stops before it).
    fn item_at(&self, seq: usize, home_z_m: f64) -> Option<MissionItem> {
        let item = self.mission.item_at_home(seq, home_z_m)?;
        let here = self.mission.here(seq);
        if !here.any() {
            return Some(item);
        }
        let at = self.anchor_w.filter(|_| seq == self.seq)?;
        Some(match item {
            MissionItem::Waypoint {
                pos_w,
                hold_s,
                accept_m,
                yaw_rad,
            } => MissionItem::Waypoint {
                pos_w: here.resolve(pos_w, at),
                hold_s,
                accept_m,
                yaw_rad,
            },
            MissionItem::LoiterTime { pos_w, seconds } => MissionItem::LoiterTime {
                pos_w: here.resolve(pos_w, at),
                seconds,
            },
            other => other,
        })
    }

    /// The acceptance radius of `item` [m]: its own, else `NAV_ACC_RAD`.
    fn accept_radius(paths: &AutoPaths, item: &MissionItem) -> f64 {
        match item {
            MissionItem::Waypoint { accept_m: Some(r), .. } => *r,
            _ => paths.params().mission.accept_m,
        }
    }

    /// Where the mission goes after `item` when `item` is flown through (a waypoint without a
    /// hold, followed by another position before anything that stops: PX4's "next" setpoint):
    /// the next position, `None` when the vehicle stops at `item`.
    fn fly_through_to(&self, item: &MissionItem, home_z_m: f64) -> Option<Vec3> {
        let MissionItem::Waypoint { pos_w, hold_s, .. } = *item else {
            return None;
        };
        if hold_s > 0.0 {
            return None;
        }
        for seq in self.seq + 1..self.mission.len() {
            match self.item_at(seq, home_z_m)? {
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
    fn begin_landing(&mut self, paths: &AutoPaths, f: &mut MissionFlight, now: Moment, at_w: Option<Vec3>) {
        let Moment {
            x, yaw_rad: yaw, t_s, ..
        } = now;
        let mut guidance = paths.descend(x, yaw, t_s);
        if let (Guidance::Descend { xy_w, .. }, Some(at_w)) = (&mut guidance, at_w) {
            *xy_w = at_w;
        }
        f.guidance = guidance;
        self.phase = Phase::Landing;
    }

    fn reached(&mut self, events: &mut Vec<Event>) {
        events.push(Event::MissionItemReached(self.seq as u16));
    }

    /// Marks the current item reached and moves on; after the last one, loiter here (the mode
    /// to switch to).
    fn next_item(&mut self, events: &mut Vec<Event>) -> Option<FlightMode> {
        self.reached(events);
        self.go_on_at(self.seq + 1, events)
    }

    /// The mission goes on at item `seq`; past the last one, it is complete and the vehicle
    /// loiters here (the mode to switch to).
    fn go_on_at(&mut self, seq: usize, events: &mut Vec<Event>) -> Option<FlightMode> {
        self.seq = seq;
        // A DO_JUMP is resolved on the way, never current (as MISSION_CURRENT shows neither
        // PX4's nor ArduCopter's); a loop of jumps alone is left to the tick.
        for _ in 0..self.mission.len() {
            match self.mission.items.get(self.seq) {
                Some(&MissionItem::Jump { target, repeat }) => self.seq = self.resolve_jump(target, repeat),
                _ => break,
            }
        }
        self.phase = Phase::Start;
        if self.seq >= self.mission.len() {
            self.seq = self.mission.len().saturating_sub(1);
            self.state = MissionState::Complete;
            Some(FlightMode::Loiter)
        } else {
            events.push(Event::MissionCurrent(self.seq as u16));
            None
        }
    }
}

#[cfg(test)]
#[path = "mission_run_tests.rs"]
mod tests;
