//! The runners: the subcommands that fly the lockstep outside the autopilot process, each a thin
//! runtime layer (wall clock, threads, files) over the pure core: `fly` (a take-off and hover),
//! `sim` ([`scenario_run`]: a scenario file), `bench` (the speed figures), `montecarlo` (random
//! initial states and wrenches) and `sweep` ([`sweep_run`]: a sweep file's runs on every core).

pub mod bench;
pub mod fly;
pub mod montecarlo;
pub mod scenario_run;
pub mod sweep_run;
