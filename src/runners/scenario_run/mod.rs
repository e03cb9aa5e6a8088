//! Scenario runs (`rotorpilot sim SCENARIO.toml --out DIR`): the scenario's flight core following
//! its trajectory ([`SetpointFollower`]), or with `[autopilot]` the flight controller flown along
//! it in OFFBOARD ([`OffboardPilot`]), in [`Lockstep`] with the plant, as fast as the CPU allows
//! or paced by the runtime's [`Pacer`] (`--speedup`). Runtime layer: it reads the wall clock and
//! writes `DIR/run.ulg` (ULog, every tick: the full profile), `DIR/summary.json` and on request
//! `DIR/run.csv`; the maths it calls is pure.

mod observers;
pub mod run_csv;

use std::path::Path;
use std::time::{Duration, Instant};

use serde::Serialize;
use thiserror::Error;

use crate::flight::{OffboardPilot, Pilot, SetpointFollower};
use crate::lockstep::{Guard, Lockstep, SetupError, SnapshotReport};
use crate::math::GRAVITY_M_S2;
use crate::runtime::pacer::Pace;
use crate::runtime::ulog_file::UlogFile;
use crate::runtime::ulog_stream::log_params;
use crate::scenario::estimate_stats::{EstimateStats, EstimateTracking, SETTLE_TIME_CONSTANTS};
use crate::scenario::summary::{RunStats, TrackingSummary};
use crate::scenario::Scenario;
use crate::sitl::{SensorModel, SimPlant};

use crate::ulog::{LogInfo, Profile, Recorder, RecorderSetup};
use observers::{CsvObserver, EstimateTracker, EventLog, Paced};
use run_csv::RunCsv;

/// Beyond this distance from the origin the run is stopped as a fly-away [m].
const FLY_AWAY_M: f64 = 1e4;

/// Why a scenario could not run.
#[derive(Debug, Error)]
pub enum SimError {
    /// The flight core or plant was refused.
    #[error(transparent)]
    Setup(#[from] SetupError),
    /// The flight controller of an `[autopilot]` scenario refused a parameter or its start.
    #[error("{field}: {reason}")]
    Autopilot {
        /// Scenario field.
        field: String,
        /// What is wrong.
        reason: String,
    },
    /// An output file could not be written.
    #[error("cannot write {path}: {source}")]
    Io {
        /// File path.
        path: String,
        /// Cause.
        source: std::io::Error,
    },
}

/// Final estimator output.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct EstimateSummary {
    /// Estimator order r.
    pub order: usize,
    /// Final f̂_e, world NED [N].
    pub force_n: [f64; 3],
    /// Final τ̂_e^b, body FRD [N·m].
    pub torque_n_m: [f64; 3],
    /// Final mass estimate m_e + f̂_ez / g [kg].
    pub mass_kg: f64,
    /// RMS errors against the truth once settled.
    pub tracking: Option<EstimateTracking>,
    /// Time from which ‖f̂_e − f_e‖ stayed within 5 % of ‖f_e‖ (at least 0.05 N) to the end;
    /// `None` when it never settled (docs/sweep.md §3, eq. (3.3)) [s].
    pub convergence_time_s: Option<f64>,
    /// Largest excess of ‖f̂_e‖ over ‖f_e‖ (docs/sweep.md §3, eq. (3.4)) [%].
    pub force_overshoot_pct: f64,
}

/// `summary.json`.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct SimSummary {
    /// Scenario name.
    pub scenario: String,
    /// Airframe name.
    pub airframe: String,
    /// Control law.
    pub controller: &'static str,
    /// Compensation of the estimated wrench.
    pub compensation: bool,
    /// Rotor count.
    pub rotors: usize,
    /// Why the run ended: `complete`, `fly_away` or `plant_fault`.
    pub exit: &'static str,
    /// Simulated time [s].
    pub sim_time_s: f64,
    /// Step [s].
    pub dt_s: f64,
    /// Tracking figures.
    #[serde(flatten)]
    pub tracking: TrackingSummary,
    /// Believed mass [kg].
    pub believed_mass_kg: f64,
    /// True mass [kg].
    pub true_mass_kg: f64,
    /// Thrust that holds the true weight, m_true g [N].
    pub true_weight_n: f64,
    /// Final true scripted external force, world NED [N].
    pub true_force_n: [f64; 3],
    /// Final true scripted external torque, body FRD [N·m].
    pub true_torque_n_m: [f64; 3],
    /// Final estimator output, when on.
    pub estimate: Option<EstimateSummary>,
    /// What the commander did on its own (`[autopilot]` scenarios), with the simulated time.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub events: Vec<String>,
    /// Wall-clock time of the loop [s].
    pub wall_time_s: f64,
    /// Simulated over wall-clock time [-].
    pub real_time_factor: f64,
}

/// Flies `scn` as fast as the CPU allows; with `out_dir`, writes `run.ulg` and `summary.json`
/// there (creating the directory).
pub fn simulate(scn: &Scenario, out_dir: Option<&Path>) -> Result<SimSummary, SimError> {
    simulate_paced(scn, out_dir, Pace::Max, false)
}

/// [`simulate`] with simulated time paced against the wall clock (`--speedup`), and `run.csv`
/// too when `csv`: the same ticks in the same order whatever the pace, so the files are
/// bit-identical at any speed-up.
pub fn simulate_paced(scn: &Scenario, out_dir: Option<&Path>, pace: Pace, csv: bool) -> Result<SimSummary, SimError> {
    let mut plant = SimPlant::from_source(&scn.airframe_source, scn.seed)
        .map_err(SetupError::from)?
        .with_sensor_model(scn.sensors);
    for w in plant.warnings() {
        tracing::warn!("{w}");
    }
    let init = &scn.initial;
    if init.pos_w.is_some() {
        plant.set_initial_state(init.pos_w, init.vel_w, init.q_wb, init.omega_b, init.motors_at_hover);
    }
    let autopilot = scn
        .flight_controller()
        .map_err(|(field, reason)| SimError::Autopilot { field, reason })?;
    let trajectory = scn.trajectory.clone();
    let Some(fc) = autopilot else {
        let core = scn.flight_core().map_err(SetupError::from)?;
        let mut follower = SetpointFollower::new(core, trajectory);
        if plant.sensor_model() == SensorModel::Suite {
            follower = follower.starting_at(&plant.true_state());
        }
        let mut lockstep = Lockstep::new(follower, plant, scn.dt_s);
        let order = scn.estimator.as_ref().map_or(0, |s| s.gains.len());
        return fly(&mut lockstep, scn, order, out_dir.map(|dir| (dir, csv)), pace);
    };
    let mut fc = fc;
    if plant.sensor_model() == SensorModel::Suite {
        fc.start_navigation_at(&plant.true_state());
    }
    let order = fc.params().settings().estimator.map_or(0, |d| d.order);
    let mut lockstep = Lockstep::new(OffboardPilot::new(fc, trajectory), plant, scn.dt_s);
    let summary = fly(&mut lockstep, scn, order, out_dir.map(|dir| (dir, csv)), pace)?;
    match lockstep.pilot().start_refused() {
        Some(why) => Err(SimError::Autopilot {
            field: "autopilot".into(),
            reason: format!("the flight controller refused to start: {why}"),
        }),
        None => Ok(summary),
    }
}

/// When the estimate's errors start to count [s]: [`SETTLE_TIME_CONSTANTS`] passband time
/// constants of the scenario's design, a tenth of the run for explicit gains.
fn estimator_settle_s(scn: &Scenario) -> f64 {
    match scn.estimator.as_ref().and_then(|e| e.design) {
        Some(d) => SETTLE_TIME_CONSTANTS / d.passband_rad_s,
        None => 0.1 * scn.duration_s,
    }
}

/// Flies `lockstep` for the scenario's duration with its rotor failures, writing `run.ulg`,
/// `summary.json` and, when asked, `run.csv` into the output directory when given.
fn fly<P: Pilot>(
    lockstep: &mut Lockstep<P>,
    scn: &Scenario,
    estimator_order: usize,
    out: Option<(&Path, bool)>,
    pace: Pace,
) -> Result<SimSummary, SimError>
where
    P::Report: SnapshotReport,
{
    let rotors = lockstep.plant().failed_rotors().len();
    let io = |path: &Path| {
        let path = path.display().to_string();
        move |source| SimError::Io { path, source }
    };
    let out_dir = out.map(|(dir, _)| dir);
    let csv = match out {
        Some((dir, true)) => {
            std::fs::create_dir_all(dir).map_err(io(dir))?;
            let path = dir.join("run.csv");
            Some(CsvObserver {
                csv: RunCsv::create(&path, rotors).map_err(io(&path))?,
                path: path.display().to_string(),
                error: None,
            })
        }
        _ => None,
    };
    let ulog = match out_dir {
        Some(dir) => {
            let path = dir.join("run.ulg");
            let setup = RecorderSetup::new(&scn.airframe, lockstep.plant().true_mass_kg(), Profile::Full, scn.dt_s);
            let info = LogInfo::new(&scn.airframe.name, scn.controller, None);
            let params = lockstep.pilot().params().map(log_params).unwrap_or_default();
            Some(UlogFile::create(&path, Recorder::new(setup), &info, &params, 0.0).map_err(io(&path))?)
        }
        None => None,
    };
    lockstep.set_rotor_failures(scn.rotor_failures.clone());
    let estimate = EstimateTracker {
        stats: EstimateStats::starting_at(estimator_settle_s(scn)),
        last: None,
        mismatch_n: (lockstep.plant().true_mass_kg() - scn.airframe.mass_kg) * GRAVITY_M_S2,
    };
    let mut observer = (
        (estimate, EventLog::default()),
        (RunStats::default(), (csv, ulog), Guard { fly_away_m: FLY_AWAY_M }),
        Paced::new(pace, Duration::from_secs_f64(scn.dt_s)),
    );
    let ticks = (scn.duration_s / scn.dt_s).round() as u64;
    let wall = Instant::now();
    let exit = lockstep.run(ticks, &mut observer);
    let wall_time_s = wall.elapsed().as_secs_f64();
    let ((estimate, EventLog(events)), (stats, (csv, ulog), _), _) = observer;
    let (estimate_stats, last_estimate) = (estimate.stats, estimate.last);
    if let Some(csv) = csv {
        csv.finish()?;
    }
    if let Some(ulog) = ulog {
        ulog.finish().map_err(|e| SimError::Io {
            path: e.path.display().to_string(),
            source: e.source,
        })?;
    }
    let sim_time_s = lockstep.ticks() as f64 * scn.dt_s;
    let plant = lockstep.plant();
    let truth = plant.truth();
    let true_mass_kg = plant.true_mass_kg();
    let summary = SimSummary {
        scenario: scn.name.clone(),
        airframe: scn.airframe.name.clone(),
        controller: scn.controller.name(),
        compensation: scn.compensation,
        rotors,
        exit: exit.name(),
        sim_time_s,
        dt_s: scn.dt_s,
        tracking: stats.summary(scn.dt_s),
        believed_mass_kg: scn.airframe.mass_kg,
        true_mass_kg,
        true_weight_n: true_mass_kg * GRAVITY_M_S2,
        true_force_n: truth.external_and_drag_force_w().into(),
        true_torque_n_m: truth.external_torque_b.into(),
        estimate: last_estimate.map(|e| EstimateSummary {
            order: estimator_order,
            force_n: e.force_w.into(),
            torque_n_m: e.torque_b.into(),
            mass_kg: e.mass_kg,
            tracking: estimate_stats.summary(),
            convergence_time_s: estimate_stats.convergence_time_s(),
            force_overshoot_pct: estimate_stats.force_overshoot_pct(),
        }),
        events,
        wall_time_s,
        real_time_factor: if wall_time_s > 0.0 {
            sim_time_s / wall_time_s
        } else {
            f64::INFINITY
        },
    };
    if let Some(dir) = out_dir {
        let path = dir.join("summary.json");
        let text = serde_json::to_string_pretty(&summary).map_err(|e| SimError::Io {
            path: path.display().to_string(),
            source: std::io::Error::other(e),
        })?;
        std::fs::write(&path, text + "\n").map_err(io(&path))?;
    }
    Ok(summary)
}
