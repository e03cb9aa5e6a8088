//! `rotorpilot montecarlo`: a robustness campaign of each control law (issue 6). N random initial
//! states and constant external wrenches are drawn inside an envelope ([`envelope`]) from one
//! seeded ChaCha8 stream; every law flies the same draws to a hover at the origin with the
//! wrench estimator running ([`trial`]); the report gives the convergence rate, counts of
//! non-finite values, faults and panics, and convergence-time quantiles ([`stats`], [`report`]).
//!
//! Sampling, a run and the statistics are pure; [`runner`] spreads runs over threads.

pub mod authority;
pub mod envelope;
pub mod judging;
pub mod report;
pub mod rows;
pub mod runner;
pub mod stats;
pub mod trial;

use thiserror::Error;

use crate::airframe::{Airframe, AirframeSource};
use crate::allocation::Allocator;
use crate::control::ControllerKind;
use crate::flight::CoreError;
use crate::lockstep::{ScheduledFailure, SetupError};
use crate::wrench_estimator::ChebyshevDesign;

pub use envelope::{draws, Draw, Envelope, EnvelopeError};
pub use report::Report;
pub use stats::{ControllerSummary, RunResult};
pub use trial::{Criterion, Heading, TrialError, TrialOutcome, TrialSetup};

/// A campaign that cannot run.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum MonteCarloError {
    /// The envelope is not usable.
    #[error(transparent)]
    Envelope(#[from] EnvelopeError),
    /// No runs or no control law asked for.
    #[error("{0}")]
    Empty(String),
    /// The airframe, estimator or timing is not usable.
    #[error(transparent)]
    Setup(#[from] TrialError),
}

/// Bounds given on the command line; `None` keeps the airframe's default
/// ([`authority::default_envelope`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct EnvelopeOverrides {
    /// Largest initial tilt [deg].
    pub max_tilt_deg: Option<f64>,
    /// Largest initial ‖ω_0‖ [rad/s].
    pub max_rate_rad_s: Option<f64>,
    /// Largest initial ‖v_0‖ [m/s].
    pub max_speed_m_s: Option<f64>,
    /// Largest initial ‖p_0‖ [m].
    pub max_offset_m: Option<f64>,
    /// Largest ‖f_e‖ [N].
    pub max_force_n: Option<f64>,
    /// Largest |τ_e,i| per body axis [N·m].
    pub max_torque_n_m: Option<[f64; 3]>,
}

impl EnvelopeOverrides {
    /// `base` with every given bound replaced.
    pub fn apply(&self, base: Envelope) -> Envelope {
        Envelope {
            max_tilt_rad: self.max_tilt_deg.map_or(base.max_tilt_rad, f64::to_radians),
            max_rate_rad_s: self.max_rate_rad_s.unwrap_or(base.max_rate_rad_s),
            max_speed_m_s: self.max_speed_m_s.unwrap_or(base.max_speed_m_s),
            max_offset_m: self.max_offset_m.unwrap_or(base.max_offset_m),
            max_force_n: self.max_force_n.unwrap_or(base.max_force_n),
            max_torque_n_m: self.max_torque_n_m.unwrap_or(base.max_torque_n_m),
        }
    }
}

/// Everything a campaign needs.
#[derive(Debug, Clone)]
pub struct Campaign {
    /// Airframe text.
    pub airframe: AirframeSource,
    /// Laws to fly, in report order.
    pub controllers: Vec<ControllerKind>,
    /// Rotors that stop in every run (`--fail-rotor`), the same for every draw.
    pub rotor_failures: Vec<ScheduledFailure>,
    /// Runs per law.
    pub runs: usize,
    /// Seed of the draws.
    pub seed: u64,
    /// Simulated time per run [s].
    pub duration_s: f64,
    /// Step [s].
    pub dt_s: f64,
    /// Envelope bounds that differ from the airframe's default.
    pub envelope: EnvelopeOverrides,
    /// Convergence criterion.
    pub criterion: Criterion,
    /// Estimator design (`None`: off).
    pub estimator: Option<ChebyshevDesign>,
    /// Compensation of the estimated wrench.
    pub compensation: bool,
    /// Heading of the hover setpoint.
    pub heading: Heading,
    /// Worker threads.
    pub threads: usize,
}

impl Campaign {
    /// The default campaign on `airframe`: every law, 1000 runs, seed 0, 6 s at 1 ms, the
    /// default envelope and criterion, heading 0, a first-order Chebyshev estimator (3 dB, 2 rad/s) with
    /// compensation, one thread per core.
    pub fn new(airframe: AirframeSource) -> Self {
        Self {
            airframe,
            controllers: ControllerKind::ALL.to_vec(),
            runs: 1000,
            seed: 0,
            duration_s: 6.0,
            dt_s: 1e-3,
            envelope: EnvelopeOverrides::default(),
            criterion: Criterion::default(),
            estimator: Some(ChebyshevDesign {
                order: 1,
                ripple_db: 3.0,
                passband_rad_s: 2.0,
            }),
            compensation: true,
            heading: Heading::Zero,
            rotor_failures: Vec::new(),
            threads: std::thread::available_parallelism().map_or(1, usize::from),
        }
    }

    /// The envelope after the overrides.
    pub fn resolved_envelope(&self) -> Result<Envelope, MonteCarloError> {
        let refused = |e: SetupError| MonteCarloError::Setup(e.into());
        let af = Airframe::from_source(&self.airframe).map_err(|e| refused(e.into()))?;
        let allocator = Allocator::new(&af).map_err(|source| {
            let origin = af.name.clone();
            refused(CoreError::Allocation { origin, source }.into())
        })?;
        let env = self.envelope.apply(authority::default_envelope(&af, &allocator));
        env.validate()?;
        Ok(env)
    }
}

/// A flown campaign: its report, and every run (for `--out`, [`rows`]).
#[derive(Debug, Clone)]
pub struct Flown {
    /// The report.
    pub report: Report,
    /// The envelope the draws came from.
    pub envelope: Envelope,
    /// The draws, the same for every law.
    pub draws: Vec<Draw>,
    /// Per law (in `Campaign::controllers` order), the result of every draw.
    pub results: Vec<Vec<RunResult>>,
}

/// Runs the campaign: the same draws for every law.
pub fn run(c: &Campaign) -> Result<Report, MonteCarloError> {
    fly(c).map(|f| f.report)
}

/// Runs the campaign and keeps every run.
pub fn fly(c: &Campaign) -> Result<Flown, MonteCarloError> {
    if c.runs == 0 {
        return Err(MonteCarloError::Empty("--runs must be at least 1".into()));
    }
    if c.controllers.is_empty() {
        return Err(MonteCarloError::Empty("no control law to fly".into()));
    }
    let env = c.resolved_envelope()?;
    let mut setup = TrialSetup::new(
        &c.airframe,
        c.estimator,
        c.compensation,
        c.dt_s,
        c.duration_s,
        c.criterion,
    )?;
    setup.heading = c.heading;
    for failure in &c.rotor_failures {
        setup.schedule_rotor_failure(*failure)?;
    }
    let draws = draws(&env, c.seed, c.runs);
    let mut controllers = Vec::with_capacity(c.controllers.len());
    let mut all = Vec::with_capacity(c.controllers.len());
    for &kind in &c.controllers {
        let results = runner::fly_all(&setup, kind, &draws, c.threads)?;
        controllers.push(stats::summarize(kind.name(), &env, c.heading, &draws, &results));
        all.push(results);
    }
    let report = Report {
        airframe: setup.airframe.name.clone(),
        runs: c.runs,
        seed: c.seed,
        duration_s: c.duration_s,
        dt_s: c.dt_s,
        envelope: (&env).into(),
        criterion: (&c.criterion).into(),
        estimator: c.estimator.as_ref().map(Into::into),
        compensation: c.compensation,
        heading: c.heading,
        rotor_failures: c.rotor_failures.clone(),
        controllers,
    };
    Ok(Flown {
        report,
        envelope: env,
        draws,
        results: all,
    })
}
