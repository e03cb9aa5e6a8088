//! `rotorpilot` command line: parses options, sets up logging, calls the library, prints results.

use std::io::Write;
use std::net::SocketAddr;
use std::process::ExitCode;

use clap::Parser;
use rotorpilot::airframe::{Airframe, AirframeSource};
use rotorpilot::allocation::Allocator;
use rotorpilot::control::ControllerKind;
use rotorpilot::math::Vec3;
use rotorpilot::params::parse_param_file;
use rotorpilot::report::{estimate_csv, AllocReport, EstimateReport, GainsReport};
use rotorpilot::runners::fly::{fly, FlyOptions};
use rotorpilot::runners::scenario_run::simulate_paced;
use rotorpilot::runtime::log_place::{default_log_root, LogPlace};
use rotorpilot::runtime::{self, RunConfig};
use rotorpilot::scenario::Scenario;
use rotorpilot::wrench_estimator::log_replay::{parse_log, replay};
use rotorpilot::wrench_estimator::ulog_log::parse_ulog;
use rotorpilot::wrench_estimator::{ChebyshevDesign, WrenchObserver};

mod cli;

use cli::{parse_home, parse_numbers, Cli, Command, DesignArgs, MonteCarloArgs, SweepArgs};

/// Where `run` keeps its logs: `--log DIR`, none with `--no-log`, else the per-user default
/// for the vehicles of PX4 instances `port_base` on (none, with a warning, when neither
/// XDG_STATE_HOME nor HOME says where that is).
fn log_place(log: Option<std::path::PathBuf>, no_log: bool, port_base: u16) -> Option<LogPlace> {
    if no_log {
        return None;
    }
    if let Some(dir) = log {
        return Some(LogPlace::Chosen(dir));
    }
    let xdg = std::env::var_os("XDG_STATE_HOME");
    let home = std::env::var_os("HOME");
    match default_log_root(xdg.as_deref(), home.as_deref()) {
        Some(root) => Some(LogPlace::Default {
            root,
            first_instance: usize::from(port_base),
        }),
        None => {
            tracing::warn!("no flight logs: neither XDG_STATE_HOME nor HOME is set (give --log DIR)");
            None
        }
    }
}

/// Completes on Ctrl-C, SIGTERM or after `duration_s` wall-clock seconds.
async fn shutdown_signal(duration_s: Option<f64>) {
    let timeout = async {
        match duration_s {
            Some(d) => tokio::time::sleep(std::time::Duration::from_secs_f64(d)).await,
            None => std::future::pending().await,
        }
    };
    #[cfg(unix)]
    let terminate = async {
        match tokio::signal::unix::signal(tokio::signal::unix::SignalKind::terminate()) {
            Ok(mut s) => {
                s.recv().await;
            }
            Err(_) => std::future::pending().await,
        }
    };
    #[cfg(not(unix))]
    let terminate = std::future::pending::<()>();
    tokio::select! {
        _ = tokio::signal::ctrl_c() => {}
        _ = terminate => {}
        _ = timeout => {}
    }
}

fn main() -> ExitCode {
    // Colours only on a terminal, and never when NO_COLOR is set (no-color.org).
    let colour = std::io::IsTerminal::is_terminal(&std::io::stderr()) && std::env::var_os("NO_COLOR").is_none();
    tracing_subscriber::fmt()
        .with_writer(std::io::stderr)
        .with_ansi(colour)
        .with_target(false)
        .init();
    let cli = Cli::parse();
    match execute(cli.command) {
        Ok(text) => {
            if !text.is_empty() {
                // A closed stdout (`| head -n 1` after the ready line) is no error of ours.
                let _ = writeln!(std::io::stdout(), "{text}");
            }
            ExitCode::SUCCESS
        }
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::from(2)
        }
    }
}

fn execute(command: Command) -> Result<String, String> {
    match command {
        Command::Run {
            airframe,
            controller,
            gcs,
            api,
            bind_gcs,
            bind_api,
            count,
            autopilot,
            port_base,
            spacing,
            speedup,
            fail_rotor,
            fail,
            sensors,
            signing_key,
            home,
            sysid,
            seed,
            duration,
            log,
            no_log,
            log_profile,
            params,
            link,
        } => {
            let local = |port: u16| {
                port.checked_add(port_base)
                    .map(|p| SocketAddr::from(([127, 0, 0, 1], p)))
                    .ok_or_else(|| format!("--port-base {port_base}: ports end at 65535"))
            };
            let (bind_gcs, bind_api, api) = (
                bind_gcs.map_or_else(|| local(18570), Ok)?,
                bind_api.map_or_else(|| local(14580), Ok)?,
                api.map_or_else(|| local(14540), Ok)?,
            );
            if count == 0 {
                return Err("--count must be at least 1".into());
            }
            if !(spacing.is_finite() && spacing >= 0.0) {
                return Err(format!("--spacing {spacing}: must be a distance in metres >= 0"));
            }
            let params = match params {
                Some(path) => {
                    let origin = path.display().to_string();
                    let text = std::fs::read_to_string(&path).map_err(|e| format!("--params {origin}: {e}"))?;
                    parse_param_file(&text, &origin)
                        .map_err(|e| format!("--params {e}"))?
                        .into_iter()
                        .map(|(line, name, value)| (format!("{origin}:{line}"), name, value))
                        .collect()
                }
                None => Vec::new(),
            };
            let config = RunConfig {
                airframe: AirframeSource::resolve(&airframe).map_err(|e| e.to_string())?,
                controller,
                system_id: if sysid == 0 {
                    return Err("--sysid must be 1 to 255".into());
                } else {
                    sysid
                },
                bind_gcs,
                gcs,
                bind_api,
                api,
                home: parse_home(&home)?,
                seed,
                dt_s: 1e-3,
                log: log_place(log, no_log, port_base),
                log_profile,
                params,
                count,
                personalities: autopilot,
                spacing_m: spacing,
                pace: speedup,
                rotor_failures: fail_rotor,
                sensors,
                sensor_failures: fail,
                signing_key,
                link_impairment: link.config()?,
            };
            if let Some(d) = duration {
                if !(d.is_finite() && d > 0.0) {
                    return Err(format!("--duration {d}: must be a positive number of seconds"));
                }
            }
            let report = runtime::run(config, shutdown_signal(duration), |ready| {
                if let Ok(line) = serde_json::to_string(ready) {
                    let _ = writeln!(std::io::stdout(), "{line}");
                    let _ = std::io::stdout().flush();
                }
            })
            .map_err(|e| e.to_string())?;
            serde_json::to_string(&report).map_err(|e| e.to_string())
        }
        Command::Fly {
            airframe,
            duration,
            altitude,
            seed,
            controller,
            out,
            log,
            sensors,
        } => {
            let src = AirframeSource::resolve(&airframe).map_err(|e| e.to_string())?;
            let opts = FlyOptions {
                duration_s: duration,
                altitude_m: altitude,
                seed,
                controller,
                csv: out,
                ulog: log,
                sensors,
                ..Default::default()
            };
            let summary = fly(&src, &opts).map_err(|e| e.to_string())?;
            serde_json::to_string_pretty(&summary).map_err(|e| e.to_string())
        }
        Command::Sim {
            scenario,
            out,
            csv,
            speedup,
            sensors,
            fail,
        } => {
            let mut scn = Scenario::load(&scenario).map_err(|e| e.to_string())?;
            if let Some(model) = sensors {
                scn.sensors = model;
            }
            if !fail.is_empty() && scn.sensors != rotorpilot::sitl::SensorModel::Suite {
                return Err("--fail: sensor failures need realistic sensors (--sensors realistic)".into());
            }
            for failure in fail {
                scn.rotor_failures.schedule_sensor(failure);
            }
            let summary = simulate_paced(&scn, out.as_deref(), speedup, csv).map_err(|e| e.to_string())?;
            serde_json::to_string_pretty(&summary).map_err(|e| e.to_string())
        }
        Command::Estimate {
            log,
            mass,
            inertia,
            design,
            out,
        } => estimate(&log, mass, &inertia, &design, out.as_deref()),
        Command::Alloc { airframe, json } => {
            let src = AirframeSource::resolve(&airframe).map_err(|e| e.to_string())?;
            let af = Airframe::from_source(&src).map_err(|e| e.to_string())?;
            let allocator = Allocator::new(&af).map_err(|e| format!("{}: rotors: {e}", src.origin))?;
            let report = AllocReport::new(&af, &allocator);
            if json {
                serde_json::to_string(&report).map_err(|e| e.to_string())
            } else {
                Ok(report.to_table())
            }
        }
        Command::Bench {
            airframe,
            json,
            quick,
            logging,
            window,
            max_count,
            first_count,
        } => {
            let airframe = AirframeSource::resolve(&airframe).map_err(|e| e.to_string())?;
            let mut options = if quick {
                rotorpilot::runners::bench::BenchOptions::quick(airframe)
            } else {
                rotorpilot::runners::bench::BenchOptions::full(airframe)
            };
            if let Some(w) = window {
                if !(w.is_finite() && w > 0.0) {
                    return Err(format!("--window {w}: must be a positive number of seconds"));
                }
                options.window_s = w;
            }
            if let Some(n) = max_count {
                options.max_count = n;
            }
            if let Some(n) = first_count {
                if n == 0 {
                    return Err("--first-count must be at least 1".into());
                }
                options.first_count = n;
            }
            if logging {
                let cost = rotorpilot::runners::bench::logging_only(&options).map_err(|e| format!("bench: {e}"))?;
                return if json {
                    serde_json::to_string(&cost).map_err(|e| e.to_string())
                } else {
                    Ok(cost.to_text())
                };
            }
            let report = rotorpilot::runners::bench::run(&options).map_err(|e| format!("bench: {e}"))?;
            if json {
                serde_json::to_string(&report).map_err(|e| e.to_string())
            } else {
                Ok(report.to_text())
            }
        }
        Command::Montecarlo(args) => montecarlo(&args),
        Command::Sweep(args) => sweep(&args),
        Command::Gains { design, json } => {
            let report = GainsReport::new(&design.design(), design.ts).map_err(|e| e.to_string())?;
            if json {
                serde_json::to_string(&report).map_err(|e| e.to_string())
            } else {
                Ok(report.to_text())
            }
        }
    }
}

/// `rotorpilot sweep`: the plan, or the runs flown into `--out`, as JSON.
fn sweep(a: &SweepArgs) -> Result<String, String> {
    use rotorpilot::runners::sweep_run::LoadedSweep;
    let loaded = LoadedSweep::load(&a.sweep).map_err(|e| e.to_string())?;
    let plan = loaded.plan();
    let Some(out) = &a.out else {
        return serde_json::to_string_pretty(&plan).map_err(|e| e.to_string());
    };
    let range = a.runs.clone().unwrap_or(0..loaded.runs.len());
    if range.end > loaded.runs.len() {
        return Err(format!(
            "--runs {}..{}: the sweep has {} runs",
            range.start,
            range.end,
            loaded.runs.len()
        ));
    }
    let jobs = match a.jobs {
        Some(0) => return Err("--jobs must be at least 1".into()),
        Some(n) => n,
        None => std::thread::available_parallelism().map_or(1, usize::from),
    };
    let manifest = loaded.fly_range(range, jobs, out).map_err(|e| e.to_string())?;
    let results = manifest.results.as_ref().ok_or("no results")?;
    let summary = serde_json::json!({
        "runs": results.range[1] - results.range[0],
        "ok": results.ok,
        "failed": results.refused + results.failed + results.panicked,
        "refused": results.refused,
        "panicked": results.panicked,
        "wall_time_s": results.wall_time_s,
        "runs_per_s": results.runs_per_s,
        "jobs": results.jobs,
        "results": out.join("results.parquet").display().to_string(),
    });
    serde_json::to_string_pretty(&summary).map_err(|e| e.to_string())
}

/// `rotorpilot estimate`: reads the log, runs the estimator, writes OUT.csv, returns the JSON.
fn estimate(
    log: &std::path::Path,
    mass: f64,
    inertia: &str,
    args: &DesignArgs,
    out: Option<&std::path::Path>,
) -> Result<String, String> {
    let ts = args.ts;
    let inertia = parse_numbers("--inertia", inertia, "Ixx,Iyy,Izz in kg·m²")?;
    let [ixx, iyy, izz] = inertia[..] else {
        return Err(format!(
            "--inertia: expected 3 numbers Ixx,Iyy,Izz, got {}",
            inertia.len()
        ));
    };
    let gains = args.design().gains(ts).map_err(|e| format!("estimator design: {e}"))?;
    let observer = WrenchObserver::new(mass, Vec3::new(ixx, iyy, izz), gains, ts)
        .map_err(|e| format!("--mass {mass} / --inertia: {e}"))?;
    let origin = log.display().to_string();
    let bytes = std::fs::read(log).map_err(|e| format!("{origin}: cannot read the file: {e}"))?;
    let samples = if bytes.starts_with(&rotorpilot::ulog::encoder::FILE_MAGIC) {
        parse_ulog(&bytes, &origin, ts)
    } else {
        let text = String::from_utf8(bytes).map_err(|e| format!("{origin}: neither a ULog file nor CSV text: {e}"))?;
        parse_log(&text, &origin, ts)
    }
    .map_err(|e| e.to_string())?;
    let rows = replay(&samples, observer);
    if let Some(path) = out {
        std::fs::write(path, estimate_csv(&rows)).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    }
    let report = EstimateReport::new(&rows).ok_or_else(|| format!("{origin}: no samples"))?;
    serde_json::to_string(&report).map_err(|e| e.to_string())
}

/// `rotorpilot montecarlo`: builds the campaign from the options, runs it, returns the table or
/// JSON (the table ends with the wall time, which the JSON leaves out so it is reproducible).
fn montecarlo(a: &MonteCarloArgs) -> Result<String, String> {
    use rotorpilot::runners::montecarlo::{self, Campaign, Criterion, EnvelopeOverrides};
    let controllers = match a.controller.as_str() {
        "all" => ControllerKind::ALL.to_vec(),
        name => vec![name
            .parse::<ControllerKind>()
            .map_err(|e| format!("--controller: {e} or all"))?],
    };
    let max_torque = match &a.max_torque {
        None => None,
        Some(text) => match parse_numbers("--max-torque", text, "T or TX,TY,TZ in N·m")?[..] {
            [t] => Some([t; 3]),
            [x, y, z] => Some([x, y, z]),
            _ => return Err(format!("--max-torque {text:?}: expected T or TX,TY,TZ in N·m")),
        },
    };
    for (name, v) in [("--pos-tol", a.pos_tol), ("--att-tol", a.att_tol)] {
        if !(v.is_finite() && v > 0.0) {
            return Err(format!("{name} {v}: must be a positive number"));
        }
    }
    if a.threads == Some(0) {
        return Err("--threads must be at least 1".into());
    }
    let mut campaign = Campaign::new(AirframeSource::resolve(&a.airframe).map_err(|e| e.to_string())?);
    campaign.controllers = controllers;
    campaign.runs = a.runs;
    campaign.seed = a.seed;
    campaign.duration_s = a.duration;
    campaign.envelope = EnvelopeOverrides {
        max_tilt_deg: a.max_tilt,
        max_rate_rad_s: a.max_rate,
        max_speed_m_s: a.max_speed,
        max_offset_m: a.max_offset,
        max_force_n: a.max_force,
        max_torque_n_m: max_torque,
    };
    campaign.criterion = Criterion {
        position_m: a.pos_tol,
        attitude_rad: a.att_tol.to_radians(),
        window_s: a.window,
    };
    campaign.estimator = (a.est_order > 0).then_some(ChebyshevDesign {
        order: a.est_order,
        ripple_db: a.est_ripple_db,
        passband_rad_s: a.est_wp,
    });
    campaign.compensation = !a.no_compensation;
    campaign.heading = a.heading;
    campaign.rotor_failures = a.fail_rotor.clone();
    if let Some(n) = a.threads {
        campaign.threads = n;
    }
    let wall = std::time::Instant::now();
    let montecarlo::Flown {
        report,
        envelope,
        draws,
        results,
    } = montecarlo::fly(&campaign).map_err(|e| e.to_string())?;
    if let Some(dir) = &a.out {
        use rotorpilot::runners::montecarlo::rows;
        use rotorpilot::sweep::results::columns;
        std::fs::create_dir_all(dir).map_err(|e| format!("--out {}: {e}", dir.display()))?;
        let axes = rows::axes(&campaign.controllers, &envelope);
        let rows = rows::rows(&campaign.controllers, campaign.seed, &draws, &results);
        rotorpilot::runners::sweep_run::parquet::write(&dir.join("results.parquet"), &columns(&axes, &rows))?;
        let text = serde_json::to_string_pretty(&report).map_err(|e| e.to_string())?;
        let path = dir.join("report.json");
        std::fs::write(&path, text + "\n").map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    }
    if a.json {
        serde_json::to_string(&report).map_err(|e| e.to_string())
    } else {
        Ok(format!(
            "{}\n\nwall time {:.1} s on {} thread(s)",
            report.to_text(),
            wall.elapsed().as_secs_f64(),
            campaign.threads
        ))
    }
}
