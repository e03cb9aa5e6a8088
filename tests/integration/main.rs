//! rotorpilot's integration tests, one test binary: each module below was a file of its own
//! under `tests/`, and 52 binaries meant 52 links of the crate on every build. One test of a
//! module: `cargo test --release --test integration MODULE::` (e.g. `cli_reference::`).
//!
//! # Layout
//! - `support`, `link_bench`, `flight_bench`, `runtime_vehicle`: the shared benches (a vehicle of
//!   `rotorpilot run` on ephemeral ports, a link machine on virtual clocks, the flight controller
//!   and plant in lockstep, a runtime vehicle stepped tick by tick).
//! - every other module: the closed-loop, protocol and documentation tests of one subject.

mod flight_bench;
mod link_bench;
mod runtime_vehicle;
mod support;

mod airframe_errors;
mod allocation_golden;
mod ardupilot_failsafes;
mod ardupilot_ftp;
mod ardupilot_missions;
mod ardupilot_params;
mod ardupilot_plans;
mod ardupilot_rc;
mod ardupilot_streams;
mod attitude_convergence;
mod autopilot_scenarios;
mod bad_input;
mod cli_reference;
mod commander_flight;
mod controllers_closed_loop;
mod determinism;
mod flight_logs_by_mode;
mod flight_safety;
mod flood;
mod ftp;
mod fuzz_corpus;
mod headless_hover;
mod height_on_estimate;
mod homework_reproduction;
mod link_liveness;
mod link_machine;
mod log_download;
mod magnetic_field_at_home;
mod mavlink_link;
mod mavlink_protocols;
mod mavlink_services;
mod mavlink_shell;
mod mission_flythrough;
mod montecarlo_campaign;
mod motor_failure_flight;
mod offboard_on_estimate;
mod orbit_flight;
mod param_ftp;
mod plan_ids;
mod plan_protocol;
mod plant_vs_fc_wrench;
mod preflight_services;
mod qgc_handshake;
mod readme_params;
mod rotor_failure;
mod rotor_failure_runs;
mod scenario_errors;
mod sensor_failures;
mod sensor_loss_telemetry;
mod stick_flight;
mod sweep_runs;
mod ulog_replay;
