//! A stored mission as the commander flies it (docs/mavlink.md §7), in local NED about home.

use crate::math::Vec3;

/// One mission item.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MissionItem {
    /// NAV_TAKEOFF to `height_m` above home [m] over the current position.
    Takeoff {
        /// Height above home [m].
        height_m: f64,
    },
    /// NAV_WAYPOINT: fly to `pos_w` [m], hold `hold_s` [s] once within `accept_m` [m]
    /// (`None`: the item gives none, `NAV_ACC_RAD` applies); with no hold, flown through.
    Waypoint {
        /// Target, local NED [m].
        pos_w: Vec3,
        /// Hold time [s].
        hold_s: f64,
        /// Acceptance radius [m].
        accept_m: Option<f64>,
        /// Heading at the waypoint [rad]; `None` keeps the current one.
        yaw_rad: Option<f64>,
    },
    /// NAV_LOITER_TIME: fly to `pos_w` [m] and hold there `seconds` [s]; NAV_LOITER_UNLIM
    /// (`seconds` `None`): hold there until the mission is left.
    LoiterTime {
        /// Target, local NED [m].
        pos_w: Vec3,
        /// Hold time [s]; `None` for ever.
        seconds: Option<f64>,
    },
    /// NAV_LAND at `pos_w` (z ignored) or, when `None`, here.
    Land {
        /// Landing point, local NED [m].
        pos_w: Option<Vec3>,
    },
    /// NAV_RETURN_TO_LAUNCH.
    ReturnToLaunch,
    /// DO_CHANGE_SPEED to `speed_m_s` [m/s].
    ChangeSpeed {
        /// Horizontal speed [m/s].
        speed_m_s: f64,
    },
    /// NAV_DELAY for `seconds` [s], holding position.
    Delay {
        /// Delay [s].
        seconds: f64,
    },
    /// DO_JUMP: go on at item `target`, `repeat` times (`None`: for ever), then past this item.
    Jump {
        /// Index of the item the mission goes on at.
        target: usize,
        /// How often the jump is taken; `None` always.
        repeat: Option<u32>,
    },
}

impl MissionItem {
    /// True when every number of the item is finite.
    pub fn is_finite(&self) -> bool {
        let v = |p: &Vec3| p.iter().all(|c| c.is_finite());
        match self {
            Self::Takeoff { height_m } => height_m.is_finite(),
            Self::Waypoint {
                pos_w,
                hold_s,
                accept_m,
                yaw_rad,
            } => {
                v(pos_w)
                    && hold_s.is_finite()
                    && accept_m.is_none_or(f64::is_finite)
                    && yaw_rad.is_none_or(f64::is_finite)
            }
            Self::LoiterTime { pos_w, seconds } => v(pos_w) && seconds.is_none_or(f64::is_finite),
            Self::Land { pos_w } => pos_w.as_ref().is_none_or(v),
            Self::ReturnToLaunch => true,
            Self::ChangeSpeed { speed_m_s } => speed_m_s.is_finite(),
            Self::Delay { seconds } => seconds.is_finite(),
            Self::Jump { .. } => true,
        }
    }
}

/// A validated mission: items in order, item 0 first (PX4 numbering).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Mission {
    /// Items.
    pub items: Vec<MissionItem>,
    /// Per item, true when its height is above home (a GLOBAL_RELATIVE_ALT frame): its heights
    /// are stored above the local origin and follow home when home moves, as PX4 reads them at
    /// flight time; an item without an entry keeps its height.
    pub above_home: Vec<bool>,
    /// Per item, which of its coordinates stand for where the vehicle is when the item starts
    /// (ArduCopter reads a latitude and longitude of 0, or an altitude of 0, so); an item
    /// without an entry keeps its position.
    pub here: Vec<HereParts>,
}

/// Which coordinates of a mission item's position are the vehicle's own when the item starts
/// (docs/ardupilot.md §6): ArduCopter's `loc_from_cmd` takes a latitude and longitude of 0 as
/// the current position and an altitude of 0 as the current altitude.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct HereParts {
    /// North and east are the vehicle's.
    pub xy: bool,
    /// The height is the vehicle's.
    pub z: bool,
}

impl HereParts {
    /// `pos_w` [m] with the parts that are the vehicle's taken from `at_w` [m].
    pub fn resolve(self, pos_w: Vec3, at_w: Vec3) -> Vec3 {
        Vec3::new(
            if self.xy { at_w.x } else { pos_w.x },
            if self.xy { at_w.y } else { pos_w.y },
            if self.z { at_w.z } else { pos_w.z },
        )
    }

    /// True when some part is the vehicle's.
    pub fn any(self) -> bool {
        self.xy || self.z
    }
}

impl Mission {
    /// Number of items.
    pub fn len(&self) -> usize {
        self.items.len()
    }

    /// True without items.
    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }

    /// True when every number of every item is finite.
    pub fn is_finite(&self) -> bool {
        self.items.iter().all(MissionItem::is_finite)
    }

    /// Which parts of item `seq`'s position are the vehicle's when it starts.
    pub fn here(&self, seq: usize) -> HereParts {
        self.here.get(seq).copied().unwrap_or_default()
    }

    /// Item `seq` as flown with home at `home_z_m` [m] (NED z of home in the local frame): an
    /// item whose height is above home is moved by home's height over the origin.
    pub fn item_at_home(&self, seq: usize, home_z_m: f64) -> Option<MissionItem> {
        let item = *self.items.get(seq)?;
        if !self.above_home.get(seq).copied().unwrap_or(false) {
            return Some(item);
        }
        let lift = |p: Vec3| Vec3::new(p.x, p.y, p.z + home_z_m);
        Some(match item {
            MissionItem::Takeoff { height_m } => MissionItem::Takeoff {
                height_m: height_m - home_z_m,
            },
            MissionItem::Waypoint {
                pos_w,
                hold_s,
                accept_m,
                yaw_rad,
            } => MissionItem::Waypoint {
                pos_w: lift(pos_w),
                hold_s,
                accept_m,
                yaw_rad,
            },
            MissionItem::LoiterTime { pos_w, seconds } => MissionItem::LoiterTime {
                pos_w: lift(pos_w),
                seconds,
            },
            MissionItem::Land { pos_w } => MissionItem::Land { pos_w: pos_w.map(lift) },
            other => other,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_single_non_finite_number_makes_a_mission_non_finite() {
        let wp = |x: f64| MissionItem::Waypoint {
            pos_w: Vec3::new(x, 0.0, -2.0),
            hold_s: 0.0,
            accept_m: None,
            yaw_rad: None,
        };
        let mut m = Mission {
            items: vec![
                MissionItem::Takeoff { height_m: 2.0 },
                wp(1.0),
                MissionItem::Land { pos_w: None },
            ],
            ..Default::default()
        };
        assert!(m.is_finite());
        m.items.push(wp(f64::NAN));
        assert!(!m.is_finite());
        assert!(!MissionItem::Delay { seconds: f64::INFINITY }.is_finite());
    }

    #[test]
    fn heights_above_home_follow_home_and_the_others_stay() {
        let wp = MissionItem::Waypoint {
            pos_w: Vec3::new(1.0, 2.0, -20.0),
            hold_s: 0.0,
            accept_m: None,
            yaw_rad: None,
        };
        let m = Mission {
            items: vec![MissionItem::Takeoff { height_m: 20.0 }, wp, wp],
            above_home: vec![true, true, false],
            ..Default::default()
        };
        // Home 5 m below the origin (NED z +5): relative heights come down 5 m.
        assert_eq!(m.item_at_home(0, 5.0), Some(MissionItem::Takeoff { height_m: 15.0 }));
        let MissionItem::Waypoint { pos_w, .. } = m.item_at_home(1, 5.0).unwrap() else {
            panic!("a waypoint stays a waypoint");
        };
        assert_eq!(pos_w, Vec3::new(1.0, 2.0, -15.0));
        assert_eq!(m.item_at_home(2, 5.0), Some(wp), "an AMSL height stays");
        assert_eq!(m.item_at_home(3, 5.0), None);
    }

    #[test]
    fn the_parts_that_are_here_come_from_where_the_vehicle_is() {
        let (pos, at) = (Vec3::new(1.0, 2.0, -3.0), Vec3::new(10.0, 20.0, -30.0));
        let here = |xy, z| HereParts { xy, z };
        assert_eq!(here(false, false).resolve(pos, at), pos);
        assert_eq!(here(true, false).resolve(pos, at), Vec3::new(10.0, 20.0, -3.0));
        assert_eq!(here(false, true).resolve(pos, at), Vec3::new(1.0, 2.0, -30.0));
        assert!(!here(false, false).any() && here(false, true).any());
        let m = Mission::default();
        assert_eq!(m.here(4), HereParts::default(), "no entry: the item's own position");
    }
}
