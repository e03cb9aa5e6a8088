use super::*;
use crate::guidance::Home;

const MARGIN_M: f64 = 4.0;

fn polygon(inclusion: bool, v: &[Point2]) -> Zone {
    Zone {
        inclusion,
        shape: Shape::Polygon(v.to_vec()),
    }
}

fn circle(inclusion: bool, center: Point2, radius_m: f64) -> Zone {
    Zone {
        inclusion,
        shape: Shape::Circle { center, radius_m },
    }
}

fn square(inclusion: bool, c: Point2, half: f64) -> Zone {
    let v = [
        [c[0] - half, c[1] - half],
        [c[0] + half, c[1] - half],
        [c[0] + half, c[1] + half],
        [c[0] - half, c[1] + half],
    ];
    polygon(inclusion, &v)
}

/// Distance from `p` to the segment a–b [m].
fn to_segment(p: Point2, a: Point2, b: Point2) -> f64 {
    let ab = [b[0] - a[0], b[1] - a[1]];
    let len2 = ab[0] * ab[0] + ab[1] * ab[1];
    let t = (((p[0] - a[0]) * ab[0] + (p[1] - a[1]) * ab[1]) / len2).clamp(0.0, 1.0);
    dist(p, [a[0] + t * ab[0], a[1] + t * ab[1]])
}

/// Distance from `p` to the boundary of `zone` [m].
fn to_boundary(zone: &Zone, p: Point2) -> f64 {
    match &zone.shape {
        Shape::Circle { center, radius_m } => (dist(p, *center) - radius_m).abs(),
        Shape::Polygon(v) => (0..v.len())
            .map(|i| to_segment(p, v[i], v[(i + 1) % v.len()]))
            .fold(f64::INFINITY, f64::min),
    }
}

/// The polyline flown: start, the way points, destination.
fn flown(from: Point2, to: Point2, path: &FencePath) -> Vec<Point2> {
    let mut line = vec![from];
    if let FencePath::Around(way) = path {
        line.extend(way);
    }
    line.push(to);
    line
}

fn length(line: &[Point2]) -> f64 {
    line.windows(2).map(|w| dist(w[0], w[1])).sum()
}

/// Every point of the polyline, every 5 cm, keeps every zone's rule with at least `clear_m` [m]
/// to spare (start and destination excepted within `clear_m` of them).
fn assert_clear(fence: &Geofence, line: &[Point2], clear_m: f64) {
    let (from, to) = (line[0], line[line.len() - 1]);
    for w in line.windows(2) {
        let steps = (dist(w[0], w[1]) / 0.05).ceil().max(1.0) as usize;
        for k in 0..=steps {
            let t = k as f64 / steps as f64;
            let p = [w[0][0] + t * (w[1][0] - w[0][0]), w[0][1] + t * (w[1][1] - w[0][1])];
            for (i, zone) in fence.zones.iter().enumerate() {
                assert!(zone.allows(p), "{p:?} breaks zone {i}: {line:?}");
                let near_end = dist(p, from) < clear_m || dist(p, to) < clear_m;
                assert!(
                    near_end || to_boundary(zone, p) >= clear_m,
                    "{p:?} only {} m off zone {i}: {line:?}",
                    to_boundary(zone, p)
                );
            }
        }
    }
}

#[test]
fn no_fence_or_nothing_in_the_way_flies_straight() {
    assert_eq!(
        plan(&Geofence::default(), [0.0, 0.0], [100.0, 0.0], MARGIN_M),
        FencePath::Direct
    );
    let fence = Geofence {
        zones: vec![
            square(true, [0.0, 0.0], 500.0),
            square(false, [50.0, 40.0], 20.0),
            circle(false, [50.0, -40.0], 20.0),
        ],
    };
    assert_eq!(plan(&fence, [0.0, 0.0], [100.0, 0.0], MARGIN_M), FencePath::Direct);
    assert_eq!(
        plan(&fence, [0.0, 0.0], [0.0, 0.0], MARGIN_M),
        FencePath::Direct,
        "already there"
    );
}

#[test]
fn an_exclusion_square_in_the_way_is_flown_round_on_its_shorter_side() {
    // A 40 m square centred 10 m east of the straight line: the west side is shorter.
    let fence = Geofence {
        zones: vec![square(false, [50.0, 10.0], 20.0)],
    };
    let (from, to) = ([0.0, 0.0], [100.0, 0.0]);
    let path = plan(&fence, from, to, MARGIN_M);
    let FencePath::Around(way) = &path else {
        panic!("{path:?}")
    };
    // Round the two western corners, grown by the margin: (30 − 4, −10 − 4), (70 + 4, −14).
    assert_eq!(way.len(), 2, "{way:?}");
    assert!(
        dist(way[0], [26.0, -14.0]) < 1e-9 && dist(way[1], [74.0, -14.0]) < 1e-9,
        "{way:?}"
    );
    let line = flown(from, to, &path);
    assert_clear(&fence, &line, 0.99 * MARGIN_M);
    let expected = 2.0 * 26.0f64.hypot(14.0) + 48.0;
    assert!((length(&line) - expected).abs() < 1e-9, "{}", length(&line));
    // Mirrored east of the line, it goes round the east side.
    let fence = Geofence {
        zones: vec![square(false, [50.0, -10.0], 20.0)],
    };
    let FencePath::Around(way) = plan(&fence, from, to, MARGIN_M) else {
        panic!()
    };
    assert!(way.iter().all(|p| (p[1] - 14.0).abs() < 1e-9), "{way:?}");
}

#[test]
fn a_circle_is_flown_round_its_octagon() {
    let fence = Geofence {
        zones: vec![circle(false, [100.0, 5.0], 40.0)],
    };
    let (from, to) = ([0.0, 0.0], [200.0, 0.0]);
    let path = plan(&fence, from, to, MARGIN_M);
    let FencePath::Around(way) = &path else {
        panic!("{path:?}")
    };
    // Every way point is an octagon vertex: r / cos(π/8) + m from the centre, west of it.
    let r = 40.0 / (std::f64::consts::PI / 8.0).cos() + MARGIN_M;
    for p in way {
        assert!((dist(*p, [100.0, 5.0]) - r).abs() < 1e-9 && p[1] < 5.0, "{way:?}");
    }
    let line = flown(from, to, &path);
    // The octagon's edges pass r cos(π/8) = 40 + 0.92 m from the centre.
    assert_clear(&fence, &line, 0.92 * MARGIN_M);
    // No longer than over the octagon's western vertex, no shorter than past the circle's.
    let len = length(&line);
    assert!(
        len < 2.0 * 100.0f64.hypot(r) && len > 2.0 * 100.0f64.hypot(35.0 + MARGIN_M),
        "{len}"
    );
}

#[test]
fn a_concave_inclusion_zone_is_followed_round_its_inner_corner() {
    // A U open to the north: the vehicle in the west arm returns to the east arm.
    let u = polygon(
        true,
        &[
            [0.0, 0.0],
            [100.0, 0.0],
            [100.0, 30.0],
            [20.0, 30.0],
            [20.0, 70.0],
            [100.0, 70.0],
            [100.0, 100.0],
            [0.0, 100.0],
        ],
    );
    let fence = Geofence { zones: vec![u] };
    let (from, to) = ([90.0, 15.0], [90.0, 85.0]);
    let path = plan(&fence, from, to, MARGIN_M);
    let FencePath::Around(way) = &path else {
        panic!("{path:?}")
    };
    // Round the two inner corners of the notch, each moved 4 m off it.
    assert_eq!(way, &vec![[16.0, 26.0], [16.0, 74.0]]);
    assert_clear(&fence, &flown(from, to, &path), 0.99 * MARGIN_M);
}

#[test]
fn zones_together_are_avoided_and_inclusion_zones_kept() {
    // An exclusion wall across most of a corridor, a circle behind its gap: round both.
    let fence = Geofence {
        zones: vec![
            square(true, [50.0, 0.0], 60.0),
            polygon(false, &[[40.0, -70.0], [60.0, -70.0], [60.0, 30.0], [40.0, 30.0]]),
            circle(false, [80.0, 40.0], 10.0),
        ],
    };
    let (from, to) = ([0.0, 0.0], [100.0, 0.0]);
    let path = plan(&fence, from, to, MARGIN_M);
    assert!(matches!(path, FencePath::Around(_)), "{path:?}");
    assert_clear(&fence, &flown(from, to, &path), 0.92 * MARGIN_M);
}

#[test]
fn a_sharp_corner_is_cut_a_margin_off() {
    // A thin triangle (6°) across the line, pointing west: round its tip, which is cut a margin
    // off instead of pushed 4 m / sin 3° = 76 m out.
    let fence = Geofence {
        zones: vec![polygon(false, &[[45.0, 80.0], [55.0, 80.0], [50.0, -10.0]])],
    };
    let (from, to) = ([0.0, 0.0], [100.0, 0.0]);
    let path = plan(&fence, from, to, MARGIN_M);
    let FencePath::Around(way) = &path else {
        panic!("{path:?}")
    };
    assert_clear(&fence, &flown(from, to, &path), 0.99 * MARGIN_M);
    let tip = [50.0, -10.0];
    let nearest = way.iter().map(|p| dist(*p, tip)).fold(f64::INFINITY, f64::min);
    assert!(nearest < 3.0 * MARGIN_M, "the cut passes near the tip: {way:?}");
}

#[test]
fn without_a_way_inside_the_fence_there_is_no_path() {
    // A wall across the whole inclusion zone.
    let fence = Geofence {
        zones: vec![
            square(true, [50.0, 0.0], 60.0),
            polygon(false, &[[40.0, -70.0], [60.0, -70.0], [60.0, 70.0], [40.0, 70.0]]),
        ],
    };
    assert_eq!(plan(&fence, [0.0, 0.0], [100.0, 0.0], MARGIN_M), FencePath::NoPath);
    // The start within the margin of a zone in the way.
    let fence = Geofence {
        zones: vec![square(false, [50.0, 0.0], 20.0)],
    };
    assert_eq!(plan(&fence, [28.0, 0.0], [100.0, 0.0], MARGIN_M), FencePath::NoPath);
    // A zone that cannot be planned (doubles back on itself).
    let fence = Geofence {
        zones: vec![polygon(false, &[[0.0, 0.0], [10.0, 0.0], [0.0, 0.0], [0.0, 10.0]])],
    };
    assert_eq!(plan(&fence, [50.0, 50.0], [-50.0, -50.0], MARGIN_M), FencePath::NoPath);
}

/// PX4's test plan (multicopter_mission_geofence_avoid.plan): from its third waypoint home,
/// round the exclusion polygon and circle, inside the inclusion polygon.
#[test]
fn px4s_test_plan_returns_round_both_exclusion_zones() {
    let home = Home {
        lat_deg: 47.3977444,
        lon_deg: 8.5455918,
        alt_amsl_m: 489.338,
    };
    let local = |lat: f64, lon: f64| {
        let p = home.to_local(lat, lon, home.alt_amsl_m);
        [p.x, p.y]
    };
    let poly = |inclusion, v: &[[f64; 2]]| polygon(inclusion, &v.iter().map(|p| local(p[0], p[1])).collect::<Vec<_>>());
    let fence = Geofence {
        zones: vec![
            Zone {
                inclusion: false,
                shape: Shape::Circle {
                    center: local(47.395306422855064, 8.54286777893347),
                    radius_m: 111.05361447891983,
                },
            },
            poly(
                false,
                &[
                    [47.3991036, 8.5368519],
                    [47.3985883, 8.5434353],
                    [47.3967667, 8.5442537],
                    [47.3968827, 8.5417818],
                ],
            ),
            poly(
                true,
                &[
                    [47.39999163985872, 8.535047740378417],
                    [47.39994510029728, 8.545445143543049],
                    [47.39274987948735, 8.551976999573185],
                    [47.39365751759516, 8.53812458836515],
                ],
            ),
        ],
    };
    let to = [0.0, 0.0];
    for from in [
        local(47.39635128979426, 8.53915466175144),
        local(47.39446602392638, 8.540564444881795),
    ] {
        assert!(fence.zones.iter().all(|z| z.allows(from)));
        let path = plan(&fence, from, to, MARGIN_M);
        assert!(matches!(path, FencePath::Around(_)), "{path:?}");
        assert_clear(&fence, &flown(from, to, &path), 0.92 * MARGIN_M);
    }
}
