//! A stored mission as the commander flies it (mavlink.md §7), in local NED about home.

use crate::math::Vec3;

/// Default acceptance radius of a waypoint when the item gives none [m].
pub const DEFAULT_ACCEPT_RADIUS_M: f64 = 0.5;

/// One mission item.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MissionItem {
    /// NAV_TAKEOFF to `height_m` above home [m] over the current position.
    Takeoff {
        /// Height above home [m].
        height_m: f64,
    },
    /// NAV_WAYPOINT: fly to `pos_w` [m], hold `hold_s` [s] once within `accept_m` [m].
    Waypoint {
        /// Target, local NED [m].
        pos_w: Vec3,
        /// Hold time [s].
        hold_s: f64,
        /// Acceptance radius [m].
        accept_m: f64,
        /// Heading at the waypoint [rad]; `None` keeps the current one.
        yaw_rad: Option<f64>,
    },
    /// NAV_LOITER_TIME: fly to `pos_w` [m] and hold there `seconds` [s].
    LoiterTime {
        /// Target, local NED [m].
        pos_w: Vec3,
        /// Hold time [s].
        seconds: f64,
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
}

/// A validated mission: items in order, item 0 first (PX4 numbering).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Mission {
    /// Items.
    pub items: Vec<MissionItem>,
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
}
