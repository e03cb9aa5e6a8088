//! `rotorpilot fly`: a take-off climb and hover flown by a bare flight core following a
//! [`ClimbProfile`], in [`Lockstep`] with the plant, as fast as the CPU allows. Runtime layer: it
//! reads the wall clock (for the real-time factor) and writes the CSV export and the ULog file;
//! the maths it calls is pure.

use std::io::Write;
use std::path::PathBuf;
use std::time::Instant;

use serde::Serialize;
use thiserror::Error;

use crate::airframe::{Airframe, AirframeSource};
use crate::control::ControllerKind;
use crate::flight::{FlightCore, SetpointFollower};
use crate::guidance::ClimbProfile;
use crate::lockstep::{Exit, Lockstep, Observer, SetupError, Tick};
use crate::math::{euler_zyx, Vec3};
use crate::runtime::ulog_file::UlogFile;
use crate::scenario::summary::RunStats;
use crate::sitl::{SensorModel, SimPlant};
use crate::ulog::{LogInfo, Profile, Recorder, RecorderSetup};

/// What to fly.
#[derive(Debug, Clone, PartialEq)]
pub struct FlyOptions {
    /// Simulated duration [s].
    pub duration_s: f64,
    /// Hover altitude above the start point [m].
    pub altitude_m: f64,
    /// Time of the take-off climb [s].
    pub climb_s: f64,
    /// Control and integration step [s].
    pub dt_s: f64,
    /// Sensor-noise seed.
    pub seed: u64,
    /// Which sensors the flight controller reads.
    pub sensors: SensorModel,
    /// Control law.
    pub controller: ControllerKind,
    /// CSV log to write, if any.
    pub csv: Option<PathBuf>,
    /// ULog file to write (every tick: the full profile), if any.
    pub ulog: Option<PathBuf>,
}

impl Default for FlyOptions {
    fn default() -> Self {
        Self {
            duration_s: 10.0,
            altitude_m: 2.0,
            climb_s: 4.0,
            dt_s: 1e-3,
            seed: 0,
            sensors: SensorModel::State,
            controller: ControllerKind::Geometric,
            csv: None,
            ulog: None,
        }
    }
}

/// Why a flight could not run.
#[derive(Debug, Error)]
pub enum FlyError {
    /// The airframe, flight core or plant was refused.
    #[error(transparent)]
    Setup(#[from] SetupError),
    /// An option is out of range.
    #[error("--{option}: {reason}")]
    Option {
        /// Option name.
        option: &'static str,
        /// What is wrong.
        reason: String,
    },
    /// The log could not be written.
    #[error("cannot write {path}: {source}")]
    Io {
        /// Log path.
        path: String,
        /// Cause.
        source: std::io::Error,
    },
}

/// Result of a flight, printed as JSON.
#[derive(Debug, Clone, Serialize)]
pub struct FlightSummary {
    /// Airframe name.
    pub airframe: String,
    /// Controller used.
    pub controller: &'static str,
    /// Number of rotors.
    pub rotors: usize,
    /// Simulated time [s].
    pub sim_time_s: f64,
    /// Ticks run.
    pub ticks: u64,
    /// Final true position, world NED [m].
    pub final_position_m: [f64; 3],
    /// Final position minus setpoint, world NED [m].
    pub final_error_m: [f64; 3],
    /// Largest tilt during the flight [deg].
    pub max_tilt_deg: f64,
    /// Simulated time spent with the allocation saturated [s].
    pub saturated_time_s: f64,
    /// Final mean rotor speed [rad/s].
    pub final_rotor_speed_rad_s: f64,
    /// Hover rotor speed the FC expects [rad/s].
    pub hover_speed_rad_s: f64,
    /// Still resting on the ground at the end.
    pub on_ground: bool,
    /// Wall-clock time of the loop [s].
    pub wall_time_s: f64,
    /// Simulated time over wall-clock time [-].
    pub real_time_factor: f64,
}

/// Flies a take-off to `altitude_m` and a hover with the chosen controller.
pub fn fly(src: &AirframeSource, opts: &FlyOptions) -> Result<FlightSummary, FlyError> {
    check_options(opts)?;
    let (airframe, core, plant) = build(src, opts)?;
    let rotors = core.allocator().rotor_count();
    for w in plant.warnings() {
        tracing::warn!("{w}");
    }
    let start = plant.true_state();
    let yaw = euler_zyx(&start.r_wb).z;
    let climb = ClimbProfile {
        start_w: start.pos_w,
        target_w: start.pos_w - Vec3::new(0.0, 0.0, opts.altitude_m),
        duration_s: opts.climb_s,
        yaw_rad: yaw,
    };
    let log = match &opts.csv {
        Some(path) => Some(CsvLog::create(path, rotors)?),
        None => None,
    };
    let ulog = match &opts.ulog {
        Some(path) => {
            let setup = RecorderSetup::new(&airframe, plant.true_mass_kg(), Profile::Full, opts.dt_s);
            let info = LogInfo::new(&airframe.name, opts.controller, None);
            let file = UlogFile::create(path, Recorder::new(setup), &info, &[], 0.0);
            Some(file.map_err(|source| FlyError::Io {
                path: path.display().to_string(),
                source,
            })?)
        }
        None => None,
    };
    let mut follower = SetpointFollower::new(core, climb);
    if opts.sensors == SensorModel::Suite {
        follower = follower.starting_at(&start);
    }
    let mut lockstep = Lockstep::new(follower, plant, opts.dt_s);
    let mut observer = (RunStats::default(), log, ulog);

    let ticks = (opts.duration_s / opts.dt_s).round() as u64;
    let wall = Instant::now();
    lockstep.run(ticks, &mut observer);
    let wall_time_s = wall.elapsed().as_secs_f64();
    let (stats, log, ulog) = observer;
    let stats = stats.summary(opts.dt_s);
    if let Some(log) = log {
        log.finish()?;
    }
    if let Some(ulog) = ulog {
        ulog.finish().map_err(|e| FlyError::Io {
            path: e.path.display().to_string(),
            source: e.source,
        })?;
    }
    let plant = lockstep.plant();
    let truth = plant.truth();
    let speeds = plant.motor_speeds();
    let sim_time_s = ticks as f64 * opts.dt_s;
    Ok(FlightSummary {
        airframe: airframe.name.clone(),
        controller: opts.controller.name(),
        rotors,
        sim_time_s,
        ticks,
        final_position_m: truth.pos_w.into(),
        final_error_m: stats.final_position_error_m,
        max_tilt_deg: stats.max_tilt_deg,
        saturated_time_s: stats.saturated_time_s,
        final_rotor_speed_rad_s: speeds.iter().sum::<f64>() / speeds.len() as f64,
        hover_speed_rad_s: airframe.hover_speed_rad_s(),
        on_ground: truth.on_ground,
        wall_time_s,
        real_time_factor: if wall_time_s > 0.0 {
            sim_time_s / wall_time_s
        } else {
            f64::INFINITY
        },
    })
}

/// The FC's airframe, the flight core and the plant of a flight.
fn build(src: &AirframeSource, opts: &FlyOptions) -> Result<(Airframe, FlightCore, SimPlant), SetupError> {
    let airframe = Airframe::from_source(src)?;
    let core = FlightCore::for_airframe(&airframe, opts.controller, opts.dt_s)?;
    Ok((
        airframe,
        core,
        SimPlant::from_source(src, opts.seed)?.with_sensor_model(opts.sensors),
    ))
}

fn check_options(o: &FlyOptions) -> Result<(), FlyError> {
    let bad = |option, reason: &str| {
        Err(FlyError::Option {
            option,
            reason: reason.to_string(),
        })
    };
    if !(o.duration_s.is_finite() && o.duration_s > 0.0 && o.duration_s <= 1e6) {
        return bad("duration", "must be a positive number of seconds up to 1e6");
    }
    if !(o.altitude_m.is_finite() && (0.0..=1000.0).contains(&o.altitude_m)) {
        return bad("altitude", "must be between 0 and 1000 m");
    }
    if !(o.dt_s.is_finite() && o.dt_s > 0.0 && o.dt_s <= 0.01) {
        return bad("dt", "must be in (0, 0.01] s");
    }
    if !(o.climb_s.is_finite() && o.climb_s >= 0.0) {
        return bad("climb", "must be a non-negative number of seconds");
    }
    Ok(())
}

/// CSV log of a flight; the first write error stops the flight and is reported by
/// [`CsvLog::finish`].
struct CsvLog {
    path: String,
    out: std::io::BufWriter<std::fs::File>,
    error: Option<FlyError>,
}

impl Observer<()> for CsvLog {
    fn observe(&mut self, tick: &Tick<()>, plant: &SimPlant) -> Option<Exit> {
        let Some(step) = &tick.control.step else {
            return None;
        };
        let written = self.row(
            tick.t_s,
            &tick.control.state,
            &tick.reference_w(),
            &step.allocation.applied,
            plant.motor_speeds(),
        );
        match written {
            Ok(()) => None,
            Err(e) => {
                self.error = Some(e);
                Some(Exit::Stopped)
            }
        }
    }
}

impl CsvLog {
    fn create(path: &std::path::Path, rotors: usize) -> Result<Self, FlyError> {
        let name = path.display().to_string();
        let io = |source| FlyError::Io {
            path: name.clone(),
            source,
        };
        let file = std::fs::File::create(path).map_err(io)?;
        let mut out = std::io::BufWriter::new(file);
        let mut header = String::from("t,x,y,z,x_ref,y_ref,z_ref,vx,vy,vz,roll,pitch,yaw,thrust,tau_x,tau_y,tau_z");
        for i in 1..=rotors {
            header.push_str(&format!(",omega_{i}"));
        }
        writeln!(out, "{header}").map_err(io)?;
        Ok(Self {
            path: name,
            out,
            error: None,
        })
    }

    fn row(
        &mut self,
        t: f64,
        s: &crate::control::VehicleState,
        reference: &Vec3,
        applied: &crate::allocation::Wrench,
        speeds: &[f64],
    ) -> Result<(), FlyError> {
        let e = euler_zyx(&s.r_wb);
        let mut line = format!(
            "{t:.3},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            s.pos_w.x,
            s.pos_w.y,
            s.pos_w.z,
            reference.x,
            reference.y,
            reference.z,
            s.vel_w.x,
            s.vel_w.y,
            s.vel_w.z,
            e.x,
            e.y,
            e.z,
            applied.thrust_n,
            applied.torque_b.x,
            applied.torque_b.y,
            applied.torque_b.z
        );
        for w in speeds {
            line.push_str(&format!(",{w}"));
        }
        writeln!(self.out, "{line}").map_err(|source| FlyError::Io {
            path: self.path.clone(),
            source,
        })
    }

    fn finish(mut self) -> Result<(), FlyError> {
        if let Some(e) = self.error.take() {
            return Err(e);
        }
        self.out.flush().map_err(|source| FlyError::Io {
            path: self.path.clone(),
            source,
        })
    }
}
