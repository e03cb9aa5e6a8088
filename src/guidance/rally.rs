//! Uploaded rally points (MAVLink plan type RALLY, PX4's "safe points") in local NED about
//! home, and the choice of the closest one that PX4's RTL makes. Pure.

use crate::math::Vec3;

/// Rally points closer than this to home are not return destinations when home is one [m]
/// (PX4 `MAX_DIST_FROM_HOME_FOR_LAND_APPROACHES`).
pub const MIN_DIST_FROM_HOME_M: f64 = 10.0;
/// A destination replaces a closer-ranked one only when it is nearer by more than this [m]
/// (PX4 `MIN_DIST_THRESHOLD`).
pub const MIN_DIST_MARGIN_M: f64 = 2.0;

/// The stored rally points; empty when none are stored.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RallyPoints {
    /// The points, local NED [m], in upload order.
    pub points_w: Vec<Vec3>,
}

impl RallyPoints {
    /// No points.
    pub fn is_empty(&self) -> bool {
        self.points_w.is_empty()
    }

    /// True when every coordinate is finite.
    pub fn is_finite(&self) -> bool {
        self.points_w.iter().all(|p| p.iter().all(|c| c.is_finite()))
    }

    /// The rally point horizontally closest to `from_w` that is nearer than `beat_m` by more
    /// than [`MIN_DIST_MARGIN_M`]; when `home_w` is given (home is a destination too), points
    /// within [`MIN_DIST_FROM_HOME_M`] of it are skipped (PX4 `RTL::findClosestSafePoint`).
    pub fn closest(&self, from_w: &Vec3, beat_m: f64, home_w: Option<&Vec3>) -> Option<Vec3> {
        let mut best: Option<(f64, Vec3)> = None;
        for p in &self.points_w {
            if home_w.is_some_and(|h| (p.xy() - h.xy()).norm() <= MIN_DIST_FROM_HOME_M) {
                continue;
            }
            let d = (p.xy() - from_w.xy()).norm();
            let to_beat = best.map_or(beat_m, |(b, _)| b);
            if d + MIN_DIST_MARGIN_M < to_beat {
                best = Some((d, *p));
            }
        }
        best.map(|(_, p)| p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_closest_point_wins_by_a_margin_and_points_by_home_are_skipped() {
        let rally = RallyPoints {
            points_w: vec![
                Vec3::new(100.0, 0.0, 0.0),
                Vec3::new(0.0, 40.0, -5.0),
                Vec3::new(5.0, 0.0, 0.0),
            ],
        };
        let home = Vec3::zeros();
        let here = Vec3::new(10.0, 50.0, -20.0);
        let to_home = here.xy().norm();
        assert_eq!(
            rally.closest(&here, to_home, Some(&home)),
            Some(Vec3::new(0.0, 40.0, -5.0))
        );
        // Near home: home itself is closer than any far rally point.
        let near_home = Vec3::new(3.0, 0.0, -20.0);
        assert_eq!(rally.closest(&near_home, 3.0, Some(&home)), None);
        // Without home as an option the point by home counts.
        assert_eq!(
            rally.closest(&near_home, f64::INFINITY, None),
            Some(Vec3::new(5.0, 0.0, 0.0))
        );
        // A point only 1 m nearer than home does not beat it.
        let tie = RallyPoints {
            points_w: vec![Vec3::new(0.0, 49.0, 0.0)],
        };
        let above = Vec3::new(0.0, 25.0, -20.0);
        assert_eq!(tie.closest(&above, 25.0, Some(&home)), None);
        assert!(RallyPoints::default().closest(&here, f64::INFINITY, None).is_none());
    }
}
