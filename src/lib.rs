//! `rotorpilot`: a MAVLink-speaking multirotor flight-controller emulator.
//!
//! The flight controller's maths lives in plain structs that take values and return values;
//! clocks, files and (later) sockets stay in a thin runtime layer. The simulated vehicle is the
//! separate `firmware_sim` crate, reached only through [`sitl`]. Frames are NED world and FRD
//! body; units are SI.
//!
//! # Layout
//!
//! - [`math`]: numeric aliases, hat/vee, Euler angles, angle wrapping.
//! - [`airframe`]: the FC's view of an airframe file (presets, validation, errors naming the field).
//! - [`bench`]: `rotorpilot bench`: ticks/s, speed-up, vehicles at real time, start-up, ACK latency (runtime layer).
//! - [`allocation`]: G_q from the airframe, min-norm inverse, saturation policy (docs/allocation.md).
//! - [`commander`]: arm/disarm, PX4 flight modes, take-off/hold/land/return, land detection
//!   and auto-disarm on simulated time.
//! - [`control`]: vehicle state, setpoints and the geometric, hierarchical and passivity-based
//!   controllers behind one interface (docs/control.md).
//! - [`flight`]: what flies the plant: the flight controller (commander, flight core, navigator,
//!   parameters, rotor-failure monitor, home; telemetry snapshot) or a bare flight core following setpoints;
//!   its `flight_core` is one control tick: estimator → controller → allocation → estimator.
//! - [`lockstep`]: a pilot and the plant stepped together at a fixed step; the only place the
//!   plant is stepped; observers and exit status of runs; scheduled rotor failures.
//! - [`estimation`]: Chebyshev gain design and the momentum-based wrench estimator (docs/estimator.md).
//! - [`rpy`]: the RPY (ZYX) dynamic model: Q, Q̇, M, skew-consistent C (docs/model.md §3).
//! - [`montecarlo`]: `rotorpilot montecarlo`: random initial states and wrenches in an envelope,
//!   convergence rate per law (sampling, runs and statistics pure; threads in its runner).
//! - [`mav`]: MAVLink codec (datagram ↔ frames, hand-built ACK for unknown commands).
//! - [`nav_filter`]: the navigation filter: an error-state EKF (PX4 EKF2's structure) fusing IMU,
//!   delayed GNSS, barometer and magnetometer readings (docs/navigation_filter.md).
//! - [`navigation`]: setpoint generators (take-off climb; hover, quintic, waypoint and circle
//!   trajectories with a `[trajectory]` TOML spec).
//! - [`params`]: the parameter table (PX4 and RP_ names), each parameter declared once as a row,
//!   validated as a whole; the table of docs/parameters.md is generated from the rows.
//! - [`report`]: what the `alloc` and `gains` commands print.
//! - [`scenario`]: scenario files (airframe, mismatch, disturbances, controller, estimator,
//!   trajectory) validated into a run description; run statistics.
//! - [`sim`]: `rotorpilot sim`: scenario runs writing run.csv and summary.json (runtime layer).
//! - [`telemetry`]: the per-tick snapshot the links stream.
//! - [`runtime`]: the autopilot process: paced tick thread and MAVLink UDP links (runtime layer).
//! - [`ulog`]: flight logs in PX4's ULog format (encoder, topics, profiles, recorder).
//! - [`suggest`]: "did you mean …?" for mistyped names.
//! - [`sweep`]: sweep files: a base scenario, axes over its fields (grid, random, Latin
//!   hypercube) and seeds, listed as runs (docs/sweep.md).
//! - [`sweep_run`]: `rotorpilot sweep`: a sweep's runs on worker threads into
//!   `results.parquet` and `sweep.json`; its engine also runs `montecarlo`.
//! - [`sitl`]: the only seam between the flight controller and the plant; which sensors are read.
//! - [`sensor_failure`]: sensor failures by MAVLink's unit and type names.
//! - [`fly`]: `rotorpilot fly`: a take-off and hover at full speed (runtime layer: wall clock,
//!   files).
#![warn(missing_docs)]
#![deny(unsafe_code)]

pub mod airframe;
pub mod allocation;
pub mod bench;
pub mod commander;
pub mod control;
pub mod estimation;
pub mod flight;
pub mod fly;
pub mod lockstep;
pub mod math;
pub mod mav;
pub mod montecarlo;
pub mod nav_filter;
pub mod navigation;
pub mod params;
pub mod report;
pub mod rpy;
pub mod runtime;
pub mod scenario;
pub mod sensor_failure;
pub mod sim;
pub mod sitl;
pub mod suggest;
pub mod sweep;
pub mod sweep_run;
pub mod telemetry;
pub mod ulog;
