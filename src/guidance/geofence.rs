//! An uploaded geofence (MAVLink plan type FENCE) as the commander checks it: inclusion and
//! exclusion polygons and circles in local NED about home, horizontal only (PX4's fence zones
//! carry no altitude). Pure.
//!
//! The rule is PX4's (`Geofence::isInsidePolygonOrCircle`): a point is inside the fence when it
//! is inside every inclusion zone and outside every exclusion zone; an empty fence contains every
//! point. Zones are closed sets: a point on a polygon edge or on a circle is inside that zone.

use crate::math::Vec3;

/// A horizontal point, local NED [m]: north, east.
pub type Point2 = [f64; 2];

/// The shape of a zone, local NED [m].
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    /// A simple (not self-intersecting) polygon: its vertices in order, at least 3.
    Polygon(Vec<Point2>),
    /// A circle about `center` of radius `radius_m` [m].
    Circle {
        /// Centre, north and east [m].
        center: Point2,
        /// Radius [m].
        radius_m: f64,
    },
}

/// One zone of the fence.
#[derive(Debug, Clone, PartialEq)]
pub struct Zone {
    /// Inclusion (the vehicle must stay inside) or exclusion (it must stay outside).
    pub inclusion: bool,
    /// Where it is.
    pub shape: Shape,
}

/// How a point breaks the fence: the zone (index into [`Geofence::zones`]) and its kind.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ZoneBreach {
    /// Index of the zone in upload order.
    pub zone: usize,
    /// The zone is an inclusion zone (the point is outside it); else an exclusion zone (the
    /// point is inside it).
    pub inclusion: bool,
}

impl std::fmt::Display for ZoneBreach {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.inclusion {
            write!(f, "outside inclusion zone {}", self.zone + 1)
        } else {
            write!(f, "inside exclusion zone {}", self.zone + 1)
        }
    }
}

/// The uploaded fence; empty when none is stored.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Geofence {
    /// The zones, in upload order.
    pub zones: Vec<Zone>,
}

impl Zone {
    /// True when `p` is inside the zone's shape or on its boundary.
    pub fn covers(&self, p: Point2) -> bool {
        match &self.shape {
            Shape::Polygon(vertices) => in_polygon(vertices, p),
            Shape::Circle { center, radius_m } => (p[0] - center[0]).hypot(p[1] - center[1]) <= *radius_m,
        }
    }

    /// True when `p` keeps the zone's rule (inside an inclusion zone, outside an exclusion zone).
    pub fn allows(&self, p: Point2) -> bool {
        self.covers(p) == self.inclusion
    }

    /// True when every number of the zone is finite.
    pub fn is_finite(&self) -> bool {
        match &self.shape {
            Shape::Polygon(vertices) => vertices.iter().flatten().all(|v| v.is_finite()),
            Shape::Circle { center, radius_m } => center.iter().chain([radius_m]).all(|v| v.is_finite()),
        }
    }
}

impl Geofence {
    /// No zones: every point is inside.
    pub fn is_empty(&self) -> bool {
        self.zones.is_empty()
    }

    /// The first zone whose rule `pos_w` breaks (z ignored), or `None` when it is inside the fence.
    pub fn breach(&self, pos_w: &Vec3) -> Option<ZoneBreach> {
        let p = [pos_w.x, pos_w.y];
        self.zones.iter().position(|z| !z.allows(p)).map(|zone| ZoneBreach {
            zone,
            inclusion: self.zones[zone].inclusion,
        })
    }

    /// True when `pos_w` is inside the fence (z ignored).
    pub fn contains(&self, pos_w: &Vec3) -> bool {
        self.breach(pos_w).is_none()
    }

    /// True when every number of every zone is finite.
    pub fn is_finite(&self) -> bool {
        self.zones.iter().all(Zone::is_finite)
    }
}

/// Point `p` on the segment `a`–`b` (within 1 mm, for the rounding of 1e-7° coordinates).
fn on_segment(a: Point2, b: Point2, p: Point2) -> bool {
    let (ab, ap) = ([b[0] - a[0], b[1] - a[1]], [p[0] - a[0], p[1] - a[1]]);
    let len2 = ab[0] * ab[0] + ab[1] * ab[1];
    let t = if len2 > 0.0 {
        ((ap[0] * ab[0] + ap[1] * ab[1]) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (ap[0] - t * ab[0]).hypot(ap[1] - t * ab[1]) <= 1e-3
}

/// Point in polygon by the even-odd crossing rule (W. R. Franklin's PNPOLY, as PX4's
/// `insidePolygon`), with points on an edge counted inside.
fn in_polygon(vertices: &[Point2], p: Point2) -> bool {
    let n = vertices.len();
    if n < 3 {
        return false;
    }
    let mut inside = false;
    for i in 0..n {
        let (a, b) = (vertices[i], vertices[(i + n - 1) % n]);
        if on_segment(a, b, p) {
            return true;
        }
        // The edge crosses the east line through p when its ends lie on either side of it.
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let north_at = a[0] + (b[0] - a[0]) * (p[1] - a[1]) / (b[1] - a[1]);
            if p[0] < north_at {
                inside = !inside;
            }
        }
    }
    inside
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::guidance::Home;

    /// A 20 m square centred on home, and an L-shaped (concave) polygon.
    fn square(inclusion: bool) -> Zone {
        let v = vec![[-10.0, -10.0], [10.0, -10.0], [10.0, 10.0], [-10.0, 10.0]];
        Zone {
            inclusion,
            shape: Shape::Polygon(v),
        }
    }

    fn at(n: f64, e: f64) -> Vec3 {
        Vec3::new(n, e, -5.0)
    }

    #[test]
    fn polygons_count_edges_and_vertices_inside_and_handle_concave_shapes() {
        let sq = square(true);
        for p in [
            [0.0, 0.0],
            [9.99, -9.99],
            [10.0, 0.0],
            [-10.0, 3.0],
            [10.0, 10.0],
            [-10.0, -10.0],
        ] {
            assert!(sq.covers(p), "{p:?} inside or on the square");
        }
        for p in [[10.01, 0.0], [0.0, -10.01], [11.0, 11.0], [-30.0, 0.0]] {
            assert!(!sq.covers(p), "{p:?} outside the square");
        }
        // An L: the square minus its north-east quarter.
        let l = Zone {
            inclusion: true,
            shape: Shape::Polygon(vec![
                [-10.0, -10.0],
                [10.0, -10.0],
                [10.0, 0.0],
                [0.0, 0.0],
                [0.0, 10.0],
                [-10.0, 10.0],
            ]),
        };
        assert!(l.covers([5.0, -5.0]) && l.covers([-5.0, 5.0]) && l.covers([0.0, 5.0]));
        assert!(!l.covers([5.0, 5.0]), "the missing quarter");
        // Fewer than three vertices cover nothing.
        let line = Zone {
            inclusion: true,
            shape: Shape::Polygon(vec![[0.0, 0.0], [1.0, 1.0]]),
        };
        assert!(!line.covers([0.5, 0.5]));
    }

    #[test]
    fn circles_are_closed_discs() {
        let c = Zone {
            inclusion: false,
            shape: Shape::Circle {
                center: [3.0, 4.0],
                radius_m: 5.0,
            },
        };
        assert!(c.covers([0.0, 0.0]), "on the circle");
        assert!(c.covers([3.0, 4.0]) && !c.covers([9.0, 4.0]));
        assert!(!c.allows([3.0, 4.0]) && c.allows([9.0, 4.0]), "exclusion");
    }

    #[test]
    fn the_fence_needs_every_inclusion_zone_and_no_exclusion_zone() {
        assert!(Geofence::default().contains(&at(1e5, 1e5)), "empty: no limit");
        let keep_out = Zone {
            inclusion: false,
            shape: Shape::Circle {
                center: [5.0, 5.0],
                radius_m: 2.0,
            },
        };
        let east_circle = Zone {
            inclusion: true,
            shape: Shape::Circle {
                center: [0.0, 8.0],
                radius_m: 6.0,
            },
        };
        let fence = Geofence {
            zones: vec![square(true), keep_out, east_circle],
        };
        assert!(fence.contains(&at(0.0, 5.0)));
        let breach = |n, e| fence.breach(&at(n, e));
        assert_eq!(
            breach(0.0, 12.0),
            Some(ZoneBreach {
                zone: 0,
                inclusion: true
            })
        );
        assert_eq!(
            breach(5.0, 5.5),
            Some(ZoneBreach {
                zone: 1,
                inclusion: false
            })
        );
        assert_eq!(
            breach(-5.0, -5.0),
            Some(ZoneBreach {
                zone: 2,
                inclusion: true
            }),
            "inside the square but outside the circle (PX4: every inclusion zone)"
        );
        assert_eq!(
            breach(5.0, 5.5).map(|b| b.to_string()).as_deref(),
            Some("inside exclusion zone 2")
        );
        assert_eq!(
            breach(0.0, 12.0).map(|b| b.to_string()).as_deref(),
            Some("outside inclusion zone 1")
        );
    }

    #[test]
    fn a_fence_from_latitude_and_longitude_lands_in_local_ned() {
        // 1e-4° of latitude ≈ 11.12 m north; 1e-4° of longitude ≈ 7.53 m east at 47.4° N.
        let home = Home::default();
        let corner = |dlat: f64, dlon: f64| {
            let p = home.to_local(home.lat_deg + dlat, home.lon_deg + dlon, home.alt_amsl_m);
            [p.x, p.y]
        };
        let v = vec![
            corner(-1e-4, -1e-4),
            corner(1e-4, -1e-4),
            corner(1e-4, 1e-4),
            corner(-1e-4, 1e-4),
        ];
        assert!(
            (v[2][0] - 11.12).abs() < 0.01 && (v[2][1] - 7.53).abs() < 0.01,
            "{:?}",
            v[2]
        );
        let fence = Geofence {
            zones: vec![Zone {
                inclusion: true,
                shape: Shape::Polygon(v),
            }],
        };
        assert!(fence.contains(&at(11.0, 7.5)) && !fence.contains(&at(11.0, 7.6)));
        assert!(fence.is_finite());
    }
}
