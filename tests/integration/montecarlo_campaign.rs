//! `rotorpilot montecarlo` as a library: a Monte Carlo run is the `rotorpilot sim` scenario of
//! its draw (to rounding), and a campaign's report does not depend on the thread count.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;

use rotorpilot::airframe::AirframeSource;
use rotorpilot::control::ControllerKind;
use rotorpilot::runners::montecarlo::trial::fly;
use rotorpilot::runners::montecarlo::{self, draws, Campaign, Criterion, Heading, TrialSetup};
use rotorpilot::runners::scenario_run::simulate;
use rotorpilot::scenario::Scenario;

fn quad_x() -> AirframeSource {
    AirframeSource::resolve("quad_x").unwrap()
}

#[test]
fn a_run_flies_the_scenario_of_its_draw() {
    let campaign = Campaign::new(quad_x());
    let env = campaign.resolved_envelope().unwrap();
    let mut setup = TrialSetup::new(&quad_x(), campaign.estimator, true, 1e-3, 6.0, Criterion::default()).unwrap();
    setup.heading = Heading::Initial;
    for (k, d) in draws(&env, 11, 3).iter().enumerate() {
        let kind = ControllerKind::ALL[k];
        let yaw_deg = setup.heading.setpoint_yaw_rad(d).to_degrees();
        let v = |x: &nalgebra::Vector3<f64>| format!("[{:?}, {:?}, {:?}]", x.x, x.y, x.z);
        // One tick more: `sim` records the state sensed at the start of each tick, so its last
        // record after 6001 ticks is the state after 6000 steps, the Monte Carlo run's end.
        let text = format!(
            r#"
duration = 6.001
[airframe]
preset = "quad_x"
overrides = {{ plant = {{ ground = {{ height = 10000.0 }}, disturbance = [ {{ kind = "constant", force = {}, torque = {} }} ] }} }}
[initial]
position = [0.0, 0.0, 0.0]
[controller]
kind = "{}"
compensation = true
[estimator]
order = 1
wp = 2.0
[trajectory]
kind = "hover"
position = [0.0, 0.0, 0.0]
yaw = {yaw_deg:?}
"#,
            v(&d.force_w),
            v(&d.torque_b),
            kind.name()
        );
        let mut scn = Scenario::from_toml_str(&text, "replay", "replay", Path::new(".")).unwrap();
        // The exact initial state (the file would round it through degrees).
        scn.initial.pos_w = Some(d.pos_w);
        scn.initial.vel_w = d.vel_w;
        scn.initial.q_wb = d.q_wb;
        scn.initial.omega_b = d.omega_b;
        scn.trajectory = rotorpilot::guidance::trajectory::Trajectory::Hover(rotorpilot::guidance::trajectory::Hover {
            pos_w: nalgebra::Vector3::zeros(),
            yaw_rad: setup.heading.setpoint_yaw_rad(d),
        });
        let sim = simulate(&scn, None).unwrap();
        let mc = fly(&setup, kind, d).unwrap();
        assert_eq!(sim.exit, "complete", "{kind:?}");
        assert_eq!(mc.ticks + 1, sim.tracking.ticks, "{kind:?}");
        // The sensed position (sim) and the true one (Monte Carlo) agree to rounding.
        assert!(
            (mc.final_position_error_m - sim.tracking.final_position_error_norm_m).abs() < 1e-12,
            "{kind:?}: {} vs {}",
            mc.final_position_error_m,
            sim.tracking.final_position_error_norm_m
        );
        assert_eq!(mc.fault_ticks, sim.tracking.controller_fault_ticks, "{kind:?}");
        assert!(mc.converged, "{kind:?}: {mc:?}");
    }
}

#[test]
fn the_report_does_not_depend_on_the_thread_count() {
    let mut c = Campaign::new(quad_x());
    c.runs = 12;
    c.seed = 5;
    c.duration_s = 3.0;
    c.threads = 1;
    let one = montecarlo::run(&c).unwrap();
    c.threads = 3;
    let three = montecarlo::run(&c).unwrap();
    assert_eq!(one, three);
    assert_eq!(one.controllers.len(), 3);
    for s in &one.controllers {
        assert_eq!(s.runs, 12);
        assert_eq!((s.panics, s.non_finite_runs), (0, 0), "{}", s.controller);
    }
}

#[test]
fn bad_campaigns_are_refused() {
    let mut c = Campaign::new(quad_x());
    c.runs = 0;
    assert!(montecarlo::run(&c).unwrap_err().to_string().contains("--runs"));
    let mut c = Campaign::new(quad_x());
    c.envelope.max_speed_m_s = Some(f64::INFINITY);
    assert!(montecarlo::run(&c).unwrap_err().to_string().contains("max-speed"));
    let mut c = Campaign::new(quad_x());
    c.controllers.clear();
    assert!(montecarlo::run(&c).is_err());
}
