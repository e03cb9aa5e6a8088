//! Tests of [`TrajectorySpec`](super::TrajectorySpec): TOML text for each kind, and refusals
//! naming the field.

use super::*;
use crate::math::Vec3;
use std::f64::consts::FRAC_PI_2;

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Scenario {
    trajectory: TrajectorySpec,
}

fn parse(text: &str) -> Result<TrajectorySpec, String> {
    toml::from_str::<Scenario>(text)
        .map(|s| s.trajectory)
        .map_err(|e| e.to_string())
}

fn build(text: &str) -> Result<Trajectory, String> {
    parse(text)?.build().map_err(|e| e.to_string())
}

#[test]
fn hover_and_quintic_from_toml() {
    let h = build("[trajectory]\nkind = \"hover\"\nposition = [1, 2, -3]\nyaw = 90\n").unwrap();
    let s = h.sample(4.0);
    assert_eq!(s.pos_w, Vec3::new(1.0, 2.0, -3.0));
    assert!((s.yaw_rad - FRAC_PI_2).abs() < 1e-15);
    assert_eq!(h.duration_s(), None);

    let text = r#"
        [trajectory]
        kind = "quintic"
        start = [0, 0, -1]
        goal = [3.5, 0, -2]
        duration = 4
        yaw = 0
        goal_yaw = -90
    "#;
    let q = build(text).unwrap();
    assert_eq!(q.duration_s(), Some(4.0));
    assert_eq!(q.sample(4.0).pos_w, Vec3::new(3.5, 0.0, -2.0));
    assert!((q.sample(4.0).yaw_rad + FRAC_PI_2).abs() < 1e-15);
    assert!(q.sample(2.0).yaw_rate_rad_s < 0.0);
}

#[test]
fn waypoints_from_toml() {
    let text = r#"
        [trajectory]
        kind = "waypoints"
        waypoints = [[0, 0, -2], [4, 0, -2, 90], [4, 4, -2], [0, 0, -2, 0]]
        speed = 2.0
        yaw_rate = 45
        hold = 1
    "#;
    let Trajectory::Waypoints(w) = build(text).unwrap() else {
        panic!("not waypoints")
    };
    let yaws: Vec<f64> = w.legs().iter().map(|l| l.path.goal_yaw_rad.to_degrees()).collect();
    assert_eq!(yaws, [90.0, 90.0, 0.0]);
    assert!((w.legs()[0].path.peak_speed_m_s() - 2.0).abs() < 1e-12);
    let pts = "waypoints = [[0, 0, -2], [1, 0, -2], [1, 1, -2]]";
    let t = build(&format!(
        "[trajectory]\nkind = \"waypoints\"\n{pts}\nsegment_time = [2, 3]"
    ));
    assert_eq!(t.unwrap().duration_s(), Some(5.0));
    let t = build(&format!(
        "[trajectory]\nkind = \"waypoints\"\n{pts}\nsegment_time = 2.5"
    ));
    assert_eq!(t.unwrap().duration_s(), Some(5.0));
}

#[test]
fn circle_from_toml() {
    let text = r#"
        [trajectory]
        kind = "circle"
        center = [0, 0, -2]
        radius = 1.5
        period = 10
        ramp = 4
        laps = 3
        direction = "counterclockwise"
        yaw_mode = "tangent"
    "#;
    let c = build(text).unwrap();
    assert_eq!(c.duration_s(), Some(34.0));
    assert_eq!(c.start_w(), Vec3::new(1.5, 0.0, -2.0));
    assert!((c.start_yaw_rad() + FRAC_PI_2).abs() < 1e-15);
    let minimal = "[trajectory]\nkind = \"circle\"\ncentre = [0, 0, -2]\nradius = 1\nperiod = 8\n";
    let c = build(minimal).unwrap();
    assert_eq!((c.duration_s(), c.sample(20.0).yaw_rad), (None, 0.0));
}

#[test]
fn refusals_name_the_field() {
    let cases = [
        (
            "kind = \"quintic\"\nstart = [0,0,0]\ngoal = [1,0,0]\nduration = -1",
            "trajectory.duration: must be positive, got -1",
        ),
        (
            "kind = \"hover\"\nposition = [0, nan, 0]",
            "trajectory.position: must be finite",
        ),
        (
            "kind = \"hover\"\nposition = [0, 0, 0]\nyaw = inf",
            "trajectory.yaw: must be a finite",
        ),
        (
            "kind = \"waypoints\"\nwaypoints = []\nspeed = 1",
            "trajectory.waypoints: needs at least",
        ),
        (
            "kind = \"waypoints\"\nwaypoints = [[0, 0]]\nspeed = 1",
            "trajectory.waypoints[0]: needs",
        ),
        (
            "kind = \"waypoints\"\nwaypoints = [[0, 0, 0]]",
            "trajectory.segment_time: missing",
        ),
        (
            "kind = \"waypoints\"\nwaypoints = [[0,0,0]]\nspeed = 1\nsegment_time = 1",
            "trajectory.segment_time: give",
        ),
        (
            "kind = \"waypoints\"\nwaypoints = [[0,0,0]]\nsegment_time = 1\nyaw_rate = 9",
            "trajectory.yaw_rate: only with `speed`",
        ),
        (
            "kind = \"waypoints\"\nwaypoints = [[0,0,0], [1,0,0]]\nspeed = 0",
            "trajectory.speed: must be positive, got 0",
        ),
        (
            "kind = \"circle\"\ncentre = [0,0,0]\nradius = -2\nperiod = 5",
            "trajectory.radius: must be positive, got -2",
        ),
        (
            "kind = \"circle\"\ncentre = [0,0,0]\nradius = 2\nperiod = 5\nlaps = 0.5",
            "trajectory.laps: laps × period (2.5 s) must be at least the ramp time (5 s)",
        ),
        (
            "kind = \"circle\"\ncentre = [0,0,0]\nradius = 2\nperiod = 5\nyaw_mode = \"tangent\"\nyaw = 3",
            "trajectory.yaw: only with yaw_mode",
        ),
    ];
    for (body, want) in cases {
        let got = build(&format!("[trajectory]\n{body}\n")).unwrap_err();
        assert!(got.starts_with(want), "{body}\n→ {got}");
    }
}

#[test]
fn toml_errors_point_at_unknown_or_missing_keys() {
    let e = parse("[trajectory]\nkind = \"hover\"\nposition = [0, 0, 0]\nheading = 3\n");
    assert!(e.unwrap_err().contains("heading"));
    let e = parse("[trajectory]\nkind = \"spiral\"\n").unwrap_err();
    assert!(e.contains("spiral"), "{e}");
    let e = parse("[trajectory]\nkind = \"quintic\"\nstart = [0, 0, 0]\ngoal = [1, 0, 0]\n");
    assert!(e.unwrap_err().contains("duration"));
    let e = parse("[trajectory]\nkind = \"circle\"\ncentre = [0, 0]\nradius = 1\nperiod = 2\n");
    assert!(e.unwrap_err().contains("length 3"));
}
