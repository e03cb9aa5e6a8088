//! A return's way round the geofence: the shortest horizontal path from the vehicle to the
//! return destination that keeps a margin inside every inclusion zone and outside every
//! exclusion zone, as PX4's navigator plans it for RTL (`GeofenceAvoidancePlanner`, PX4 1.17).
//! Pure.
//!
//! The method is a visibility graph:
//! - every zone becomes a ring pushed away from its forbidden side by the margin m (PX4: twice
//!   `NAV_ACC_RAD` for a multicopter): an exclusion polygon grows, an inclusion polygon shrinks,
//!   each edge moved by m; a corner of a forbidden region sharper than 60° is cut off by an edge
//!   m from it (two vertices instead of one); a circle becomes the regular octagon
//!   with vertices at r / cos(π/8) + m (exclusion, so the octagon holds the grown circle) or at
//!   r − m (inclusion, inside the shrunk circle);
//! - the graph's nodes are the ring vertices that bend round a forbidden region (convex corners
//!   of exclusions, concave corners of inclusions): no shortest path turns anywhere else;
//! - two points see each other when the segment between them enters no forbidden region of the
//!   rings grown by 0.99 m (slightly less than the planning rings, so that an edge running along
//!   a ring is not refused by rounding);
//! - Dijkstra from the destination gives every node its shortest way there; the start joins
//!   the node it sees whose distance plus the way from it is least.
//!
//! When the start sees the destination the return flies straight ([`FencePath::Direct`]); when
//! neither the destination nor any node is visible from it (the start or the destination within
//! the margin of a zone, a destination cut off, or a zone that cannot be planned, such as a
//! polygon that doubles back) there is no path and PX4 flies straight home ignoring the fence
//! ([`FencePath::NoPath`]).

use super::geofence::{Geofence, Point2, Shape, Zone};

/// Vertices of the polygon a circle is planned as (PX4: 8).
pub const CIRCLE_SIDES: usize = 8;
/// Share of the margin the visibility test grows the zones by.
const CHECK_SCALE: f64 = 0.99;
/// The smallest margin planned with [m]: the rings must lie off the zones.
const MIN_MARGIN_M: f64 = 0.1;

/// What a return does about the fence.
#[derive(Debug, Clone, PartialEq)]
pub enum FencePath {
    /// Nothing lies in the way (or there is no fence): straight to the destination.
    Direct,
    /// Through these points, local NED north and east [m], then to the destination.
    Around(Vec<Point2>),
    /// No path inside the fence: straight to the destination, ignoring it (PX4's fallback).
    NoPath,
}

/// A zone as the planner sees it: its ring walked with the forbidden region on the left.
#[derive(Debug, Clone)]
struct Ring {
    points: Vec<Point2>,
    inclusion: bool,
}

/// The way from `from` to `to` (local NED north and east [m]) that keeps `margin_m` [m] off
/// every zone of `fence` (module docs); margins under 0.1 m are planned as 0.1 m.
pub fn plan(fence: &Geofence, from: Point2, to: Point2, margin_m: f64) -> FencePath {
    if fence.is_empty() {
        return FencePath::Direct;
    }
    let margin = if margin_m.is_finite() {
        margin_m.max(MIN_MARGIN_M)
    } else {
        MIN_MARGIN_M
    };
    let rings = |scale: f64| -> Option<Vec<Ring>> { fence.zones.iter().map(|z| ring(z, margin * scale)).collect() };
    let (Some(planned), Some(checked)) = (rings(1.0), rings(CHECK_SCALE)) else {
        return FencePath::NoPath;
    };
    let all_finite = [from, to].iter().flatten().all(|v| v.is_finite());
    if !all_finite {
        return FencePath::NoPath;
    }
    if visible(from, to, &checked) {
        return FencePath::Direct;
    }
    let nodes: Vec<Point2> = planned.iter().flat_map(bending_vertices).collect();
    let to_dest = shortest_to(&nodes, to, &checked);
    let best = nodes
        .iter()
        .enumerate()
        .filter(|(i, _)| to_dest.cost[*i].is_finite())
        .filter(|(_, n)| visible(from, **n, &checked))
        .map(|(i, n)| (i, dist(from, *n) + to_dest.cost[i]))
        .min_by(|a, b| a.1.total_cmp(&b.1));
    let Some((mut at, _)) = best else {
        return FencePath::NoPath;
    };
    let mut way = vec![nodes[at]];
    while let Some(next) = to_dest.next[at] {
        way.push(nodes[next]);
        at = next;
    }
    FencePath::Around(way)
}

/// Each node's shortest way to the destination: its length [m] (infinite when cut off) and
/// the node after it (`None`: the destination itself).
struct ToDestination {
    cost: Vec<f64>,
    next: Vec<Option<usize>>,
}

/// Dijkstra over the nodes' visibility graph, from the destination `to` backwards.
fn shortest_to(nodes: &[Point2], to: Point2, checked: &[Ring]) -> ToDestination {
    let n = nodes.len();
    let mut cost: Vec<f64> = nodes
        .iter()
        .map(|p| {
            if visible(*p, to, checked) {
                dist(*p, to)
            } else {
                f64::INFINITY
            }
        })
        .collect();
    let mut next = vec![None; n];
    let mut done = vec![false; n];
    let mut sees: Vec<Option<bool>> = vec![None; n * n];
    for _ in 0..n {
        let Some(u) = (0..n)
            .filter(|i| !done[*i] && cost[*i].is_finite())
            .min_by(|a, b| cost[*a].total_cmp(&cost[*b]))
        else {
            break;
        };
        done[u] = true;
        for v in (0..n).filter(|v| !done[*v]) {
            let through = cost[u] + dist(nodes[u], nodes[v]);
            if through >= cost[v] {
                continue;
            }
            let seen = *sees[u * n + v].get_or_insert_with(|| visible(nodes[u], nodes[v], checked));
            if seen {
                cost[v] = through;
                next[v] = Some(u);
            }
        }
    }
    ToDestination { cost, next }
}

/// Distance between two points [m].
fn dist(a: Point2, b: Point2) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// Twice the signed area of the triangle a, b, c: positive when c lies left of a → b.
fn orient(a: Point2, b: Point2, c: Point2) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// The vertices of `ring` at which it turns left, round its forbidden region.
fn bending_vertices(ring: &Ring) -> Vec<Point2> {
    let p = &ring.points;
    let n = p.len();
    (0..n)
        .filter(|i| orient(p[(i + n - 1) % n], p[*i], p[(i + 1) % n]) > 0.0)
        .map(|i| p[i])
        .collect()
}

/// The ring of `zone` moved `margin_m` [m] off its forbidden side; `None` when the zone cannot
/// be planned (fewer than three distinct vertices, an edge doubling back, a circle that the
/// margin empties, a number that is not finite).
fn ring(zone: &Zone, margin_m: f64) -> Option<Ring> {
    if !zone.is_finite() {
        return None;
    }
    let points = match &zone.shape {
        Shape::Circle { center, radius_m } => {
            let half = std::f64::consts::PI / CIRCLE_SIDES as f64;
            let r = if zone.inclusion {
                radius_m - margin_m
            } else {
                radius_m / half.cos() + margin_m
            };
            if r <= 0.0 || *radius_m <= 0.1 {
                return None;
            }
            // Counter-clockwise round an exclusion, clockwise inside an inclusion.
            let turn = if zone.inclusion { -2.0 * half } else { 2.0 * half };
            (0..CIRCLE_SIDES)
                .map(|i| {
                    let a = (i as f64 + 0.5) * turn;
                    [center[0] + r * a.cos(), center[1] + r * a.sin()]
                })
                .collect()
        }
        Shape::Polygon(vertices) => offset_polygon(vertices, zone.inclusion, margin_m)?,
    };
    Some(Ring {
        points,
        inclusion: zone.inclusion,
    })
}

/// A polygon's vertices walked with its forbidden region on the left, each edge moved
/// `margin_m` [m] to the right, corners sharper than 60° cut.
fn offset_polygon(vertices: &[Point2], inclusion: bool, margin_m: f64) -> Option<Vec<Point2>> {
    let mut v: Vec<Point2> = Vec::with_capacity(vertices.len());
    for p in vertices {
        if v.last().is_none_or(|q| dist(*q, *p) > 1e-6) {
            v.push(*p);
        }
    }
    while v.len() > 1 && v.first().zip(v.last()).is_some_and(|(a, b)| dist(*a, *b) <= 1e-6) {
        v.pop();
    }
    let n = v.len();
    if n < 3 {
        return None;
    }
    let area2: f64 = (0..n).map(|i| orient([0.0, 0.0], v[i], v[(i + 1) % n])).sum();
    // Positive area: counter-clockwise, its inside on the left. An exclusion forbids its inside,
    // an inclusion its outside.
    if (area2 > 0.0) == inclusion {
        v.reverse();
    }
    let unit = |a: Point2, b: Point2| {
        let d = dist(a, b);
        [(b[0] - a[0]) / d, (b[1] - a[1]) / d]
    };
    let left = |e: Point2| [-e[1], e[0]];
    let mut out = Vec::with_capacity(2 * n);
    for i in 0..n {
        let (prev, at, next) = (v[(i + n - 1) % n], v[i], v[(i + 1) % n]);
        let (e_in, e_out) = (unit(prev, at), unit(at, next));
        let (n_in, n_out) = (left(e_in), left(e_out));
        let bis = [n_in[0] + n_out[0], n_in[1] + n_out[1]];
        let len = bis[0].hypot(bis[1]);
        if len < 1e-9 {
            return None;
        }
        // The edges moved off the forbidden side: lines through `at − n·m` along each edge.
        let shifted = |n: Point2| [at[0] - n[0] * margin_m, at[1] - n[1] * margin_m];
        let (line_in, line_out) = (shifted(n_in), shifted(n_out));
        let turns_left = orient(prev, at, next) > 0.0;
        if turns_left && len < 1.0 {
            // Sharp corner of the forbidden region: a cut perpendicular to the bisector, m
            // from the corner.
            let b = [bis[0] / len, bis[1] / len];
            let base = shifted(b);
            let along = left(b);
            out.push(cross_point(line_in, e_in, base, along)?);
            out.push(cross_point(line_out, e_out, base, along)?);
        } else {
            out.push(cross_point(line_in, e_in, line_out, e_out).unwrap_or(line_in));
        }
    }
    Some(out)
}

/// Where the line through `p` along `d` meets the line through `q` along `e`; `None` when they
/// are parallel.
fn cross_point(p: Point2, d: Point2, q: Point2, e: Point2) -> Option<Point2> {
    let den = d[0] * e[1] - d[1] * e[0];
    if den.abs() < 1e-12 {
        return None;
    }
    let t = ((q[0] - p[0]) * e[1] - (q[1] - p[1]) * e[0]) / den;
    Some([p[0] + t * d[0], p[1] + t * d[1]])
}

/// True when the segment `a`–`b` enters no forbidden region of `rings`.
fn visible(a: Point2, b: Point2, rings: &[Ring]) -> bool {
    rings.iter().all(|r| !enters(a, b, r))
}

/// True when the segment `a`–`b` touches the forbidden region of `ring`: it meets an edge, or
/// (meeting none) lies on the forbidden side throughout.
fn enters(a: Point2, b: Point2, ring: &Ring) -> bool {
    let p = &ring.points;
    let n = p.len();
    if (0..n).any(|i| segments_meet(a, b, p[i], p[(i + 1) % n])) {
        return true;
    }
    inside(p, a) != ring.inclusion
}

/// True when the closed segments p1–p2 and q1–q2 share a point.
fn segments_meet(p1: Point2, p2: Point2, q1: Point2, q2: Point2) -> bool {
    let (d1, d2) = (orient(q1, q2, p1), orient(q1, q2, p2));
    let (d3, d4) = (orient(p1, p2, q1), orient(p1, p2, q2));
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0)) && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0)) {
        return true;
    }
    let on = |a: Point2, b: Point2, c: Point2, o: f64| {
        o == 0.0 && c[0] >= a[0].min(b[0]) && c[0] <= a[0].max(b[0]) && c[1] >= a[1].min(b[1]) && c[1] <= a[1].max(b[1])
    };
    on(q1, q2, p1, d1) || on(q1, q2, p2, d2) || on(p1, p2, q1, d3) || on(p1, p2, q2, d4)
}

/// Even-odd point in polygon.
fn inside(p: &[Point2], c: Point2) -> bool {
    let n = p.len();
    let mut inside = false;
    for i in 0..n {
        let (a, b) = (p[i], p[(i + n - 1) % n]);
        if (a[1] > c[1]) != (b[1] > c[1]) && c[0] < a[0] + (b[0] - a[0]) * (c[1] - a[1]) / (b[1] - a[1]) {
            inside = !inside;
        }
    }
    inside
}

#[cfg(test)]
#[path = "fence_path_tests.rs"]
mod tests;
