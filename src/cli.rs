//! The command-line syntax of the `rotorpilot` binary (clap): every subcommand and option with
//! its help text. `main.rs` carries them out.

use std::net::SocketAddr;
use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};
use rotorpilot::control::ControllerKind;
use rotorpilot::guidance::Home;
use rotorpilot::runtime;
use rotorpilot::wrench_estimator::ChebyshevDesign;

/// MAVLink-speaking multirotor flight-controller emulator.
#[derive(Debug, Parser)]
#[command(name = "rotorpilot", version, about)]
pub(crate) struct Cli {
    #[command(subcommand)]
    pub(crate) command: Command,
}

#[derive(Debug, Subcommand)]
pub(crate) enum Command {
    /// Run the autopilot: the vehicle at 1 kHz, MAVLink 2 over UDP (PX4 SITL ports), until
    /// Ctrl-C / SIGTERM. Prints one JSON line with the bound addresses when ready.
    #[command(allow_negative_numbers = true)]
    Run {
        /// Airframe preset name or path to a TOML file.
        #[arg(long, default_value = "quad_x")]
        airframe: String,
        /// Control law: geometric, hierarchical or passivity.
        #[arg(long, default_value = "geometric")]
        controller: ControllerKind,
        /// Where GCS telemetry goes (QGC, MAVProxy, pymavlink udpin); shared by all vehicles.
        #[arg(long, default_value = "127.0.0.1:14550")]
        gcs: SocketAddr,
        /// Where API telemetry of the first vehicle goes (MAVSDK) [default: 127.0.0.1:14540 + port base].
        #[arg(long)]
        api: Option<SocketAddr>,
        /// Local address of the first vehicle's GCS link; vehicle i binds port + i (port 0: any
        /// free port) [default: 127.0.0.1:18570 + port base].
        #[arg(long = "bind-gcs")]
        bind_gcs: Option<SocketAddr>,
        /// Local address of the first vehicle's API link; vehicle i binds port + i (port 0: any
        /// free port) [default: 127.0.0.1:14580 + port base].
        #[arg(long = "bind-api")]
        bind_api: Option<SocketAddr>,
        /// Number of vehicles in this process (sysid, ports and seed count up from the first).
        #[arg(long, default_value_t = 1)]
        count: usize,
        /// The autopilot each vehicle presents itself as: `px4` or `ardupilot` (ArduCopter's
        /// modes, GUIDED, streams and parameters); one for every vehicle, or a comma-separated
        /// list with one per vehicle (`--count 2 --autopilot px4,ardupilot`).
        #[arg(long, default_value = "px4", value_delimiter = ',')]
        autopilot: Vec<rotorpilot::mav::identity::Personality>,
        /// PX4 instance number of the first vehicle: shifts the default ports (18570, 14580,
        /// 14540) so several processes can share one machine.
        #[arg(long = "port-base", default_value_t = 0)]
        port_base: u16,
        /// Distance between neighbouring vehicles on the start grid [m].
        #[arg(long, default_value_t = runtime::DEFAULT_SPACING_M)]
        spacing: f64,
        /// Simulated seconds per wall second (0.1 to 1000), or `max` for as fast as possible.
        #[arg(long, default_value = "1")]
        speedup: runtime::Pace,
        /// Stop rotor ROTOR (1-based) at SECONDS of simulated time, on every vehicle
        /// (repeatable), e.g. `--fail-rotor 2@20`.
        #[arg(long = "fail-rotor", value_name = "ROTOR@SECONDS")]
        fail_rotor: Vec<rotorpilot::lockstep::ScheduledFailure>,
        /// Fail sensor UNIT (gyro, accel, mag, baro, gps) in way TYPE (off, stuck, garbage,
        /// wrong, slow, delayed, intermittent; ok restores it) at SECONDS of simulated time, on
        /// every vehicle (repeatable), e.g. `--fail gps:off@30`.
        #[arg(long = "fail", value_name = "UNIT:TYPE@SECONDS")]
        fail: Vec<rotorpilot::lockstep::ScheduledSensorFailure>,
        /// What the flight controller reads: `realistic` (IMU, GPS, barometer and magnetometer
        /// through the navigation filter, as PX4 SITL) or `ideal` (the exact state, armable at
        /// once).
        #[arg(long, default_value = "realistic", value_parser = parse_sensor_model)]
        sensors: rotorpilot::sitl::SensorModel,
        /// MAVLink 2 signing key: a file of exactly 32 key bytes, or a passphrase (hashed with
        /// SHA-256 as MAVProxy does). With a key, only signed frames are obeyed and every frame
        /// sent is signed; a missing file means no key until SETUP_SIGNING stores one there.
        /// The signing timestamp is kept in FILE.timestamp.
        #[arg(long = "signing-key", value_name = "FILE")]
        signing_key: Option<PathBuf>,
        /// Home as LAT,LON,ALT [deg, deg, m AMSL].
        #[arg(long, default_value = "47.397742,8.545594,488.0")]
        home: String,
        /// MAVLink system id (1–255).
        #[arg(long, default_value_t = 1)]
        sysid: u8,
        /// Sensor-noise seed.
        #[arg(long, default_value_t = 0)]
        seed: u64,
        /// Stop after this many wall-clock seconds (default: run until Ctrl-C / SIGTERM).
        #[arg(long)]
        duration: Option<f64>,
        /// Write DIR/flight.tlog (MAVLink telemetry log) and the ULog flight logs,
        /// DIR/log/YYYY-MM-DD/HH_MM_SS.ulg (PX4's naming, UTC; by default one per arming, as
        /// SDLOG_MODE says), served to log downloads [default: the flight logs only, in
        /// $XDG_STATE_HOME/rotorpilot/instance-K or ~/.local/state/rotorpilot/instance-K, K the
        /// PX4 instance: --port-base + the vehicle's index].
        #[arg(long, value_name = "DIR", conflicts_with = "no_log")]
        log: Option<PathBuf>,
        /// Write no logs at all and serve none (SDLOG_MODE -1 stops only the flight logs).
        #[arg(long = "no-log")]
        no_log: bool,
        /// Rates of the ULog topics: default (PX4-like, tens of Hz) or full (every 1 kHz tick).
        #[arg(long = "log-profile", default_value = "default")]
        log_profile: rotorpilot::ulog::Profile,
        /// Parameter file (QGC `SYSID COMPID NAME VALUE TYPE` lines or `NAME VALUE` lines).
        #[arg(long)]
        params: Option<PathBuf>,
        #[command(flatten)]
        link: LinkImpairmentArgs,
    },
    /// Headless take-off and hover in lockstep with the plant, as fast as the CPU allows,
    /// printing a JSON summary.
    #[command(allow_negative_numbers = true)]
    Fly {
        /// Airframe preset name or path to a TOML file.
        #[arg(long, default_value = "quad_x")]
        airframe: String,
        /// Simulated duration [s].
        #[arg(long, default_value_t = 10.0)]
        duration: f64,
        /// Hover altitude above the start point [m].
        #[arg(long, default_value_t = 2.0)]
        altitude: f64,
        /// Sensor-noise seed.
        #[arg(long, default_value_t = 0)]
        seed: u64,
        /// Control law: geometric, hierarchical or passivity.
        #[arg(long, default_value = "geometric")]
        controller: ControllerKind,
        /// Write every tick to this CSV file.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Write every tick to this ULog file (the full profile).
        #[arg(long)]
        log: Option<PathBuf>,
        /// What the flight controller reads: `ideal` (the exact state) or `realistic` (IMU, GPS,
        /// barometer and magnetometer through the navigation filter).
        #[arg(long, default_value = "ideal", value_parser = parse_sensor_model)]
        sensors: rotorpilot::sitl::SensorModel,
    },
    /// Fly a scenario file headless as fast as the CPU allows; write DIR/run.ulg (ULog, every
    /// tick) and DIR/summary.json and print the summary.
    Sim {
        /// Scenario file (TOML).
        scenario: PathBuf,
        /// Output directory (created if missing).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Also write DIR/run.csv (one row per tick, the columns plot_run.py reads).
        #[arg(long, requires = "out")]
        csv: bool,
        /// Simulated seconds per wall second (0.1 to 1000), or `max` (default): the output is
        /// the same at any speed.
        #[arg(long, default_value = "max")]
        speedup: runtime::Pace,
        /// Read these sensors instead of the scenario's `[sensors] model`: `ideal` or
        /// `realistic`.
        #[arg(long, value_parser = parse_sensor_model)]
        sensors: Option<rotorpilot::sitl::SensorModel>,
        /// Fail a sensor at a simulated time, added to the scenario's (repeatable), e.g.
        /// `--fail gps:off@20`; needs realistic sensors.
        #[arg(long = "fail", value_name = "UNIT:TYPE@SECONDS")]
        fail: Vec<rotorpilot::lockstep::ScheduledSensorFailure>,
    },
    /// Run the wrench estimator offline over a flight log (homework exercise 4) and print
    /// {"samples", "final", "mass_estimate"} as JSON.
    #[command(allow_negative_numbers = true)]
    Estimate {
        /// The flight log: a ULog file with every tick (`sim --out DIR` writes DIR/run.ulg; `fly
        /// --log`; `run --log-profile full`), a run.csv (`sim --csv`), or a CSV with columns
        /// t,thrust,tau_x,tau_y,tau_z,vx,vy,vz,phi,theta,psi,phi_dot,theta_dot,psi_dot.
        #[arg(long)]
        log: PathBuf,
        /// Nominal mass [kg].
        #[arg(long)]
        mass: f64,
        /// Nominal principal inertia Ixx,Iyy,Izz [kg·m²].
        #[arg(long)]
        inertia: String,
        #[command(flatten)]
        design: DesignArgs,
        /// Write t,fx,fy,fz,tx,ty,tz,mass per sample to this CSV file.
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Print the allocation matrix G_q of an airframe.
    Alloc {
        /// Airframe preset name or path to a TOML file.
        #[arg(long)]
        airframe: String,
        /// Print one JSON object instead of a table.
        #[arg(long)]
        json: bool,
    },
    /// Measure speed and scale: headless ticks/s per control law, the real-time factor at
    /// --speedup max, the largest vehicle count at real time, start-up time to the first
    /// HEARTBEAT and the COMMAND_ACK round trip.
    Bench {
        /// Airframe preset name or path to a TOML file.
        #[arg(long, default_value = "quad_x")]
        airframe: String,
        /// Print one JSON object instead of a table.
        #[arg(long)]
        json: bool,
        /// A few seconds' smoke run with rough figures (small counts, short windows).
        #[arg(long)]
        quick: bool,
        /// Only what the flight logs cost: the full profile in fly and sim, and run's default
        /// profile at real time.
        #[arg(long)]
        logging: bool,
        /// Wall time of each real-time trial and of the max-speed run [s].
        #[arg(long)]
        window: Option<f64>,
        /// Largest vehicle count to try.
        #[arg(long = "max-count")]
        max_count: Option<usize>,
        /// Vehicle count of the first real-time trial (doubled until real time fails).
        #[arg(long = "first-count")]
        first_count: Option<usize>,
    },
    /// Monte Carlo robustness campaign: every law flies to a hover at the origin from random
    /// initial states under random constant wrenches, with the estimator running; prints the
    /// convergence rate, non-finite values, faults, panics and convergence times.
    #[command(allow_negative_numbers = true)]
    Montecarlo(MonteCarloArgs),
    /// Fly every run of a sweep file (a base scenario, axes over its fields, seeds) on every
    /// core; write DIR/results.parquet (one row per run: swept values, seed, status, metrics)
    /// and DIR/sweep.json (docs/sweep.md).
    Sweep(SweepArgs),
    /// Design wrench-estimator gains from an analog Chebyshev type-I low-pass (docs/estimator.md §3).
    #[command(allow_negative_numbers = true)]
    Gains {
        #[command(flatten)]
        design: DesignArgs,
        /// Print one JSON object.
        #[arg(long)]
        json: bool,
    },
}

/// `rotorpilot montecarlo` options; unset envelope bounds keep the airframe's defaults.
#[derive(Debug, Args)]
pub(crate) struct MonteCarloArgs {
    /// Control law: geometric, hierarchical, passivity or all.
    #[arg(long, default_value = "all")]
    pub(crate) controller: String,
    /// Airframe preset name or path to a TOML file.
    #[arg(long, default_value = "quad_x")]
    pub(crate) airframe: String,
    /// Runs per control law.
    #[arg(long, default_value_t = 1000)]
    pub(crate) runs: usize,
    /// Seed of the draws (same seed, same report).
    #[arg(long, default_value_t = 0)]
    pub(crate) seed: u64,
    /// Simulated time per run [s].
    #[arg(long, default_value_t = 6.0)]
    pub(crate) duration: f64,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    pub(crate) json: bool,
    /// Largest initial tilt from the vertical [deg] [default: 60].
    #[arg(long = "max-tilt")]
    pub(crate) max_tilt: Option<f64>,
    /// Largest initial body-rate magnitude [rad/s] [default: 3].
    #[arg(long = "max-rate")]
    pub(crate) max_rate: Option<f64>,
    /// Largest initial speed [m/s] [default: 3].
    #[arg(long = "max-speed")]
    pub(crate) max_speed: Option<f64>,
    /// Largest initial distance from the setpoint [m] [default: 1].
    #[arg(long = "max-offset")]
    pub(crate) max_offset: Option<f64>,
    /// Largest constant external force [N] [default: 0.2 × believed weight].
    #[arg(long = "max-force")]
    pub(crate) max_force: Option<f64>,
    /// Largest constant external torque per body axis, T or TX,TY,TZ [N·m] [default: 0.2 × each
    /// axis' authority at hover].
    #[arg(long = "max-torque")]
    pub(crate) max_torque: Option<String>,
    /// Position tolerance of the criterion [m].
    #[arg(long = "pos-tol", default_value_t = 0.1)]
    pub(crate) pos_tol: f64,
    /// Attitude tolerance of the criterion [deg].
    #[arg(long = "att-tol", default_value_t = 5.0)]
    pub(crate) att_tol: f64,
    /// The criterion must hold over this final window [s].
    #[arg(long, default_value_t = 1.0)]
    pub(crate) window: f64,
    /// Estimator order (0: no estimator).
    #[arg(long = "est-order", default_value_t = 1)]
    pub(crate) est_order: usize,
    /// Estimator passband ripple [dB].
    #[arg(long = "est-ripple-db", default_value_t = 3.0)]
    pub(crate) est_ripple_db: f64,
    /// Estimator passband edge [rad/s].
    #[arg(long = "est-wp", default_value_t = 2.0)]
    pub(crate) est_wp: f64,
    /// Fly without subtracting the estimated wrench.
    #[arg(long = "no-compensation")]
    pub(crate) no_compensation: bool,
    /// Heading of the hover setpoint: zero (north; the vehicle also turns by up to 180°) or
    /// initial (the run's initial heading).
    #[arg(long, default_value = "zero")]
    pub(crate) heading: rotorpilot::runners::montecarlo::Heading,
    /// Stop rotor ROTOR (1-based) SECONDS into every run (repeatable), e.g. `--fail-rotor 2@1`.
    #[arg(long = "fail-rotor", value_name = "ROTOR@SECONDS")]
    pub(crate) fail_rotor: Vec<rotorpilot::lockstep::ScheduledFailure>,
    /// Worker threads [default: one per core].
    #[arg(long)]
    pub(crate) threads: Option<usize>,
    /// Also write every run as DIR/results.parquet (the layout of `sweep`, docs/sweep.md §5)
    /// and the report as DIR/report.json.
    #[arg(long)]
    pub(crate) out: Option<PathBuf>,
}

/// `rotorpilot sweep` options.
#[derive(Debug, Args)]
pub(crate) struct SweepArgs {
    /// Sweep file (TOML).
    pub(crate) sweep: PathBuf,
    /// Output directory (created if missing).
    #[arg(long, required_unless_present = "plan")]
    pub(crate) out: Option<PathBuf>,
    /// Worker threads [default: one per core].
    #[arg(long)]
    pub(crate) jobs: Option<usize>,
    /// Fly only runs A to B−1 of the whole sweep (`A..B`, 0-based): one shard of a campaign.
    #[arg(long, value_name = "A..B", value_parser = parse_run_range)]
    pub(crate) runs: Option<std::ops::Range<usize>>,
    /// Print the sweep's manifest (run count, axes, the files it reads) as JSON; fly nothing.
    #[arg(long, conflicts_with_all = ["out", "runs", "jobs"])]
    pub(crate) plan: bool,
}

/// `A..B` with A < B.
fn parse_run_range(text: &str) -> Result<std::ops::Range<usize>, String> {
    let (a, b) = text
        .split_once("..")
        .ok_or_else(|| format!("\"{text}\": expected A..B"))?;
    let number = |s: &str| {
        s.trim()
            .parse::<usize>()
            .map_err(|e| format!("\"{text}\": {s:?} is not a run index ({e})"))
    };
    let (a, b) = (number(a)?, number(b)?);
    if a >= b {
        return Err(format!("\"{text}\": the range is empty (A must be below B)"));
    }
    Ok(a..b)
}

/// A Chebyshev estimator design on the command line (docs/estimator.md §3).
#[derive(Debug, Args)]
pub(crate) struct DesignArgs {
    /// Estimator (filter) order r.
    #[arg(long)]
    pub(crate) order: usize,
    /// Passband ripple [dB].
    #[arg(long = "ripple-db")]
    pub(crate) ripple_db: f64,
    /// Passband edge [rad/s].
    #[arg(long)]
    pub(crate) wp: f64,
    /// Estimator sample time [s] (the log's, for `estimate`).
    #[arg(long, default_value_t = 0.001)]
    pub(crate) ts: f64,
}

impl DesignArgs {
    pub(crate) fn design(&self) -> ChebyshevDesign {
        ChebyshevDesign {
            order: self.order,
            ripple_db: self.ripple_db,
            passband_rad_s: self.wp,
        }
    }
}

/// `--sensors ideal|realistic`.
fn parse_sensor_model(text: &str) -> Result<rotorpilot::sitl::SensorModel, String> {
    rotorpilot::sitl::SensorModel::from_name(text)
        .ok_or_else(|| format!("\"{text}\": expected \"ideal\" or \"realistic\""))
}

/// A bad radio link on purpose, for trying ground stations: `run`'s `--link-*` options.
#[derive(Debug, Args)]
pub(crate) struct LinkImpairmentArgs {
    /// Drop this share of the datagrams, e.g. `20%` or `0.2`; `UP/DOWN` gives each direction
    /// (to the vehicle / from it), e.g. `5%/20%`.
    #[arg(long = "link-loss", value_name = "P")]
    link_loss: Option<String>,
    /// Hold each datagram for a delay drawn uniformly from this range, e.g. `0..50ms`, `20ms`,
    /// `0.1s` (delays reorder datagrams); `UP/DOWN` for each direction.
    #[arg(long = "link-delay", value_name = "RANGE")]
    link_delay: Option<String>,
    /// Send this share of the datagrams twice, e.g. `5%`; `UP/DOWN` for each direction.
    #[arg(long = "link-duplicate", value_name = "P")]
    link_duplicate: Option<String>,
    /// Seed of the impairment's draws (vehicle i draws from SEED + i).
    #[arg(long = "link-seed", value_name = "SEED", default_value_t = 0)]
    link_seed: u64,
    /// Which links are impaired: `gcs`, `api` or `all`.
    #[arg(long = "link-impaired", value_name = "LINKS", default_value = "all")]
    link_impaired: String,
}

impl LinkImpairmentArgs {
    /// The impairment asked for, `None` without any `--link-loss/-delay/-duplicate`.
    pub(crate) fn config(&self) -> Result<Option<runtime::impairment::LinkImpairment>, String> {
        runtime::impairment::LinkImpairment::from_options(
            self.link_loss.as_deref(),
            self.link_delay.as_deref(),
            self.link_duplicate.as_deref(),
            &self.link_impaired,
            self.link_seed,
        )
        .map_err(|e| e.to_string())
    }
}

/// The comma-separated numbers `text` of `option`; an error names the option and `expected`.
pub(crate) fn parse_numbers(option: &str, text: &str, expected: &str) -> Result<Vec<f64>, String> {
    text.split(',')
        .map(|s| s.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|e| format!("{option} {text:?}: {e}; expected {expected}"))
}

/// Altitudes [m AMSL] a home may have: the ISA troposphere the barometer's pressure follows.
pub(crate) const HOME_ALT_RANGE_M: (f64, f64) = (-500.0, 11_000.0);

/// `LAT,LON,ALT` [deg, deg, m AMSL].
pub(crate) fn parse_home(text: &str) -> Result<Home, String> {
    let v = parse_numbers("--home", text, "LAT,LON,ALT")?;
    let (lo, hi) = HOME_ALT_RANGE_M;
    match v[..] {
        [lat, lon, alt] if lat.abs() <= 90.0 && lon.abs() <= 180.0 && (lo..=hi).contains(&alt) => Ok(Home {
            lat_deg: lat,
            lon_deg: lon,
            alt_amsl_m: alt,
        }),
        _ => Err(format!(
            "--home {text:?}: expected LAT,LON,ALT with |LAT| ≤ 90, |LON| ≤ 180 and ALT in [{lo}, {hi}] m"
        )),
    }
}
