//! `rotorpilot`: a MAVLink-speaking multirotor flight-controller emulator.
//!
//! The flight controller's maths and protocol state live in plain structs that take values (time
//! included) and return values; clocks, sockets, threads and files stay in the thin runtime layer
//! ([`runtime`], [`runners`]). The simulated vehicle is the separate `firmware_sim` crate, reached
//! only through [`sitl`]. Frames are NED world and FRD body; units are SI. docs/architecture.md
//! maps where each behaviour lives, who owns which state and which clock decides what.
//!
//! # Layout
//!
//! The vehicle's decisions:
//! - [`commander`]: arming, PX4 flight modes, take-off/hold/land/return, missions, offboard,
//!   sticks, failsafes, land detection; a composition of parts that own their state.
//! - [`guidance`]: setpoint generators: take-off climb, landing descent, paths, trajectories
//!   (`[trajectory]` TOML), stick references, orbit and follow-me points, geofence and rally.
//! - [`params`]: the parameter table (PX4 and RP_ names), each parameter declared once as a row;
//!   docs/parameters.md is generated from the rows.
//!
//! One tick:
//! - [`flight`]: what flies the plant: the flight controller (commander, flight core, the state
//!   source, motor failures; the telemetry snapshot) or a bare flight core following setpoints.
//! - [`control`]: vehicle state, setpoints and the geometric, hierarchical and passivity-based
//!   laws behind one interface (docs/control.md).
//! - [`allocation`]: G_q from the airframe, min-norm inverse, saturation policy (docs/allocation.md).
//! - [`wrench_estimator`]: the momentum-based wrench estimator and its Chebyshev gain design
//!   (docs/estimator.md); its offline run over a log.
//! - [`nav_filter`]: the navigation filter: an error-state EKF (PX4 EKF2's structure) fusing IMU,
//!   delayed GNSS, barometer and magnetometer readings (docs/navigation_filter.md).
//! - [`lockstep`]: a pilot and the plant stepped together at a fixed step: the only place the
//!   plant is stepped; observers and exit status of runs; scheduled failures.
//! - [`sitl`]: the only seam between the flight controller and the plant crate; which sensors are read.
//! - [`telemetry`]: the per-tick snapshot the links stream.
//! - [`airframe`]: the FC's view of an airframe file (presets, validation, errors naming the field).
//! - [`sensor_failure`]: sensor failures by MAVLink's unit and type names.
//! - [`math`], [`rpy`]: numeric aliases, hat/vee, Euler angles; the RPY (ZYX) dynamic model
//!   (docs/model.md §3).
//!
//! The wire and the logs:
//! - [`mav`]: MAVLink: codec, signing, the sans-IO link state machine and its protocol services.
//! - [`ulog`]: flight logs in PX4's ULog format (encoder, topics, profiles, recorder).
//!
//! Files and runs:
//! - [`scenario`], [`sweep`]: scenario and sweep files validated into run descriptions; run statistics.
//! - [`report`]: what the `alloc` and `gains` commands print.
//! - [`suggest`]: "did you mean …?" for mistyped names.
//! - [`runtime`]: the autopilot process (`rotorpilot run`): tick threads, UDP links, logs, keys.
//! - [`runners`]: the other subcommands that fly the lockstep: `fly`, `sim`, `bench`,
//!   `montecarlo`, `sweep`.
#![warn(missing_docs)]
#![deny(unsafe_code)]

pub mod airframe;
pub mod allocation;
pub mod commander;
pub mod control;
pub mod flight;
pub mod guidance;
pub mod lockstep;
pub mod math;
pub mod mav;
pub mod nav_filter;
pub mod params;
pub mod report;
pub mod rpy;
pub mod runners;
pub mod runtime;
pub mod scenario;
pub mod sensor_failure;
pub mod sitl;
pub mod suggest;
pub mod sweep;
pub mod telemetry;
pub mod ulog;
pub mod wrench_estimator;
