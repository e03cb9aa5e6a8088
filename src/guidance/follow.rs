//! Follow-me (PX4's follow-target mode): where to fly for a target reported by FOLLOW_TARGET.
//! Pure.
//!
//! The reports are smoothed, `p̂ ← ρ p̂ + (1 − ρ) p` with ρ = `FLW_TGT_RS` (0 takes each report
//! as it is); the target's course χ is its velocity's bearing while it moves faster than
//! [`MOVING_M_S`] and the last course otherwise (at first, the bearing from the vehicle to the
//! target, so the vehicle stays on its side). The point flown:
//! ```text
//! p_f,xy = p̂_xy + d (cos(χ + α), sin(χ + α))     d = FLW_TGT_DST, α = FLW_TGT_FA (0 front, 180 behind)
//! z_f    = z_home − h   (FLW_TGT_ALT_M 0, 1)  or  ẑ − h (2, the target's altitude)   h = FLW_TGT_HT
//! ψ_f    = bearing from the vehicle to the target
//! ```
//! Never below PX4's `MINIMUM_SAFETY_ALTITUDE` ([`SAFETY_HEIGHT_M`] above home): z_f is capped
//! there (a target reported at or below home's altitude, as MAVSDK's follow-me example does in
//! SITL, holds the vehicle at that height instead of landing it), and a vehicle below it holds
//! its horizontal position and climbs at [`EMERGENCY_ASCENT_M_S`] (PX4's emergency ascent).

use crate::control::FlatSetpoint;
use crate::math::Vec3;

/// A target slower than this keeps its last course [m/s].
pub const MOVING_M_S: f64 = 0.5;
/// The lowest height above home the mode flies (PX4's `MINIMUM_SAFETY_ALTITUDE`) [m].
pub const SAFETY_HEIGHT_M: f64 = 1.0;
/// The climb rate below [`SAFETY_HEIGHT_M`] (PX4's `EMERGENCY_ASCENT_SPEED`) [m/s].
pub const EMERGENCY_ASCENT_M_S: f64 = 0.5;

/// Where the height of the follow point comes from (`FLW_TGT_ALT_M`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FollowAltitude {
    /// A constant height above home (0).
    #[default]
    AboveHome,
    /// Above the terrain (1); the terrain here is flat at home's height, so as 0.
    AboveTerrain,
    /// Above the target's own altitude (2).
    AboveTarget,
}

/// Follow-me settings (PX4 names and defaults in brackets).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FollowParams {
    /// Height above home or the target [m] (`FLW_TGT_HT`, 8).
    pub height_m: f64,
    /// Horizontal distance to the target [m] (`FLW_TGT_DST`, 8).
    pub distance_m: f64,
    /// Where around the target, from its course [rad] (`FLW_TGT_FA`, 180°: behind).
    pub angle_rad: f64,
    /// Height reference (`FLW_TGT_ALT_M`, 0).
    pub altitude: FollowAltitude,
    /// Fastest horizontal speed while following [m/s] (`FLW_TGT_MAX_VEL`, 5).
    pub max_speed_m_s: f64,
    /// Smoothing of the reports, 0 none, towards 1 heavy [-] (`FLW_TGT_RS`, 0.1).
    pub responsiveness: f64,
}

impl Default for FollowParams {
    fn default() -> Self {
        Self {
            height_m: 8.0,
            distance_m: 8.0,
            angle_rad: std::f64::consts::PI,
            altitude: FollowAltitude::AboveHome,
            max_speed_m_s: 5.0,
            responsiveness: 0.1,
        }
    }
}

/// What the vehicle knows of the target.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FollowTarget {
    /// Smoothed position, world NED [m].
    pub pos_w: Vec3,
    /// Last reported velocity, world NED [m/s].
    pub vel_w: Vec3,
    /// Course [rad] (`None` until it moved or a vehicle position set it).
    course_rad: Option<f64>,
}

impl FollowTarget {
    /// The first report: position `pos_w` [m], velocity `vel_w` [m/s].
    pub fn new(pos_w: Vec3, vel_w: Vec3) -> Self {
        Self {
            pos_w,
            vel_w,
            course_rad: moving_course(vel_w),
        }
    }

    /// A new report, smoothed with `FLW_TGT_RS`.
    pub fn report(&mut self, pos_w: Vec3, vel_w: Vec3, p: &FollowParams) {
        let rho = p.responsiveness.clamp(0.0, 0.99);
        self.pos_w = rho * self.pos_w + (1.0 - rho) * pos_w;
        self.vel_w = vel_w;
        if let Some(course) = moving_course(vel_w) {
            self.course_rad = Some(course);
        }
    }

    /// The setpoint that follows the target from vehicle position `vehicle_w` [m], home at
    /// `home_w` [m] (the raw setpoint; the caller flies it through its limits).
    pub fn setpoint(&mut self, vehicle_w: Vec3, home_w: Vec3, p: &FollowParams) -> FlatSetpoint {
        let to_target = self.pos_w - vehicle_w;
        let floor_z = home_w.z - SAFETY_HEIGHT_M;
        if vehicle_w.z > floor_z {
            return FlatSetpoint {
                pos_w: Some(Vec3::new(vehicle_w.x, vehicle_w.y, floor_z)),
                vel_w: Some(Vec3::new(0.0, 0.0, -EMERGENCY_ASCENT_M_S)),
                ..FlatSetpoint::default()
            };
        }
        let course = *self.course_rad.get_or_insert(to_target.y.atan2(to_target.x));
        let a = course + p.angle_rad;
        let z = match p.altitude {
            FollowAltitude::AboveHome | FollowAltitude::AboveTerrain => home_w.z - p.height_m,
            FollowAltitude::AboveTarget => self.pos_w.z - p.height_m,
        };
        let point = Vec3::new(
            self.pos_w.x + p.distance_m * a.cos(),
            self.pos_w.y + p.distance_m * a.sin(),
            z.min(floor_z),
        );
        let facing = if to_target.xy().norm() > 0.1 {
            Some(to_target.y.atan2(to_target.x))
        } else {
            None
        };
        FlatSetpoint {
            pos_w: Some(point),
            vel_w: Some(Vec3::new(self.vel_w.x, self.vel_w.y, 0.0)),
            yaw_rad: facing,
            ..FlatSetpoint::default()
        }
    }
}

/// The bearing of `vel_w` [rad] when it is faster than [`MOVING_M_S`].
fn moving_course(vel_w: Vec3) -> Option<f64> {
    (vel_w.xy().norm() > MOVING_M_S).then(|| vel_w.y.atan2(vel_w.x))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_point_is_behind_a_moving_target_at_the_distance_and_height() {
        let p = FollowParams::default();
        let mut t = FollowTarget::new(Vec3::new(50.0, 0.0, 0.0), Vec3::new(2.0, 0.0, 0.0));
        let sp = t.setpoint(Vec3::new(0.0, 0.0, -8.0), Vec3::zeros(), &p);
        let point = sp.pos_w.unwrap_or_default();
        assert!((point - Vec3::new(42.0, 0.0, -8.0)).norm() < 1e-9, "{point:?}");
        assert_eq!(sp.yaw_rad, Some(0.0), "facing the target");
        assert_eq!(sp.vel_w, Some(Vec3::new(2.0, 0.0, 0.0)), "its velocity as feed-forward");
    }

    #[test]
    fn a_still_target_keeps_the_vehicle_on_its_side_and_the_angle_turns_the_point() {
        let p = FollowParams {
            angle_rad: 0.0,
            distance_m: 2.0,
            altitude: FollowAltitude::AboveTarget,
            ..Default::default()
        };
        // Vehicle south of a still target: course = north (vehicle → target), front = north.
        let mut t = FollowTarget::new(Vec3::new(10.0, 0.0, -1.0), Vec3::zeros());
        let sp = t.setpoint(Vec3::new(0.0, 0.0, -8.0), Vec3::zeros(), &p);
        assert!((sp.pos_w.unwrap_or_default() - Vec3::new(12.0, 0.0, -9.0)).norm() < 1e-9);
        // A slow drift east does not change the course; a walk east does.
        t.report(Vec3::new(10.0, 0.0, -1.0), Vec3::new(0.0, 0.3, 0.0), &p);
        let sp = t.setpoint(Vec3::new(0.0, 0.0, -8.0), Vec3::zeros(), &p);
        assert!((sp.pos_w.unwrap_or_default().x - 12.0).abs() < 1e-9);
        t.report(Vec3::new(10.0, 0.0, -1.0), Vec3::new(0.0, 1.5, 0.0), &p);
        let sp = t.setpoint(Vec3::new(0.0, 0.0, -8.0), Vec3::zeros(), &p);
        assert!((sp.pos_w.unwrap_or_default() - Vec3::new(10.0, 2.0, -9.0)).norm() < 1e-9);
    }

    #[test]
    fn the_vehicle_never_follows_below_the_safety_height() {
        let p = FollowParams {
            altitude: FollowAltitude::AboveTarget,
            height_m: 8.0,
            ..Default::default()
        };
        // A target 8 m below home (MAVSDK's example: 480 m AMSL, home 488 m): capped at 1 m.
        let home = Vec3::new(0.0, 0.0, 0.0);
        let mut t = FollowTarget::new(Vec3::new(30.0, 0.0, 8.0), Vec3::zeros());
        let sp = t.setpoint(Vec3::new(0.0, 0.0, -5.0), home, &p);
        assert_eq!(sp.pos_w.map(|w| w.z), Some(-SAFETY_HEIGHT_M));
        // Below it: hold horizontally, climb at the emergency rate.
        let sp = t.setpoint(Vec3::new(3.0, 4.0, -0.5), home, &p);
        assert_eq!(sp.pos_w, Some(Vec3::new(3.0, 4.0, -SAFETY_HEIGHT_M)));
        assert_eq!(sp.vel_w, Some(Vec3::new(0.0, 0.0, -EMERGENCY_ASCENT_M_S)));
    }

    #[test]
    fn reports_are_smoothed_by_the_responsiveness() {
        let p = FollowParams {
            responsiveness: 0.5,
            ..Default::default()
        };
        let mut t = FollowTarget::new(Vec3::zeros(), Vec3::zeros());
        t.report(Vec3::new(4.0, 0.0, 0.0), Vec3::zeros(), &p);
        assert_eq!(t.pos_w, Vec3::new(2.0, 0.0, 0.0));
        let raw = FollowParams {
            responsiveness: 0.0,
            ..Default::default()
        };
        t.report(Vec3::new(4.0, 0.0, 0.0), Vec3::zeros(), &raw);
        assert_eq!(t.pos_w, Vec3::new(4.0, 0.0, 0.0));
    }
}
