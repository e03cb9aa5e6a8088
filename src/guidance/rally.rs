//! Uploaded rally points (MAVLink plan type RALLY, PX4's "safe points") in local NED about
//! home, and the choice a return makes among them and home: PX4's ([`RallyPoints::closest`],
//! under `RTL_TYPE`) or ArduCopter's ([`RallyRule::Copter`], docs/ardupilot.md §6), the rule
//! the points were uploaded under. Pure.

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
    /// How a return chooses among them and home.
    pub rule: RallyRule,
}

/// How a return chooses between home and the rally points: the vehicle personality's rule,
/// carried by the points it uploaded.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum RallyRule {
    /// PX4's: `RTL_TYPE` decides, with [`RallyPoints::closest`]'s margins.
    #[default]
    Px4,
    /// ArduCopter's (`AP_Rally::calc_best_rally_or_home_location`): the horizontally nearest
    /// point, unless it is farther than `limit_m` (`RALLY_LIMIT_KM`; `None`: no limit) or,
    /// with `include_home` (`RALLY_INCL_HOME`), home is not farther than it.
    Copter {
        /// Farthest a rally point may be [m].
        limit_m: Option<f64>,
        /// Home is a destination too.
        include_home: bool,
    },
}

impl RallyRule {
    /// ArduCopter's defaults: `RALLY_LIMIT_KM` 0.3, `RALLY_INCL_HOME` 1.
    pub const COPTER: Self = Self::Copter {
        limit_m: Some(300.0),
        include_home: true,
    };
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

    /// Where ArduCopter's return from `from_w` goes with home at `home_w` [m], under its
    /// `limit_m` and `include_home` ([`RallyRule::Copter`]): a rally point, or `None` for home.
    pub fn copter_choice(
        &self,
        from_w: &Vec3,
        home_w: &Vec3,
        limit_m: Option<f64>,
        include_home: bool,
    ) -> Option<Vec3> {
        let d = |p: &Vec3| (p.xy() - from_w.xy()).norm();
        let nearest = self.points_w.iter().min_by(|a, b| d(a).total_cmp(&d(b))).copied()?;
        if limit_m.is_some_and(|limit| limit > 0.0 && d(&nearest) > limit) {
            return None;
        }
        (!include_home || d(&nearest) < d(home_w)).then_some(nearest)
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
            ..Default::default()
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
            ..Default::default()
        };
        let above = Vec3::new(0.0, 25.0, -20.0);
        assert_eq!(tie.closest(&above, 25.0, Some(&home)), None);
        assert!(RallyPoints::default().closest(&here, f64::INFINITY, None).is_none());
    }

    #[test]
    fn arducopter_takes_the_nearest_point_within_its_limit_unless_home_is_nearer() {
        let rally = RallyPoints {
            points_w: vec![Vec3::new(100.0, 0.0, -10.0), Vec3::new(0.0, 40.0, -5.0)],
            rule: RallyRule::COPTER,
        };
        let home = Vec3::zeros();
        let choice = |from: Vec3, limit: Option<f64>, incl: bool| rally.copter_choice(&from, &home, limit, incl);
        // 10 m from the point by home, 50 m from home: the point (no margin, none by home skipped).
        let near = Vec3::new(0.0, 50.0, -20.0);
        assert_eq!(choice(near, Some(300.0), true), Some(Vec3::new(0.0, 40.0, -5.0)));
        // Home nearer than every point: home, unless home is not a destination.
        let by_home = Vec3::new(0.0, 10.0, -20.0);
        assert_eq!(choice(by_home, Some(300.0), true), None);
        assert_eq!(choice(by_home, Some(300.0), false), Some(Vec3::new(0.0, 40.0, -5.0)));
        // Every point beyond RALLY_LIMIT_KM: home, even when home is farther still; 0 or none: no limit.
        let far = Vec3::new(0.0, 500.0, -20.0);
        assert_eq!(choice(far, Some(300.0), false), None);
        assert_eq!(choice(far, Some(0.0), true), Some(Vec3::new(0.0, 40.0, -5.0)));
        assert_eq!(choice(far, None, true), Some(Vec3::new(0.0, 40.0, -5.0)));
        assert_eq!(RallyPoints::default().copter_choice(&far, &home, None, false), None);
    }
}
