//! The shell's commands, answered from the vehicle's latest state and parameter table as PX4's
//! commands print them: `help`; `ver all` (name, version, build string); `param show [NAME|PREFIX*]`;
//! `param set NAME VALUE` (handed to the vehicle like a PARAM_SET, answered when it replies);
//! `commander status` (arming, mode, landed state, failsafes); `listener TOPIC` for
//! `vehicle_local_position`, `vehicle_attitude`, `battery_status`; a `#` comment does nothing;
//! anything else is an invalid command, in PX4 SITL's `pxh` words (`Pxh::process_line`). Pure.

use crate::math::{UnitQuat, Vec3};
use crate::params::{ParamTable, ParamType};
use crate::telemetry::Snapshot;

/// What a command needs to read.
#[derive(Debug, Clone, Copy)]
pub struct Context<'a> {
    /// The parameter table as it is.
    pub params: &'a ParamTable,
    /// The vehicle's latest state.
    pub snapshot: &'a Snapshot,
}

/// What a line does.
#[derive(Debug, Clone, PartialEq)]
pub enum ShellOutcome {
    /// Print this (each line ends with `\n`).
    Text(String),
    /// Ask the vehicle to set `name` to `value`; print [`param_set_text`] of its answer.
    SetParam {
        /// Parameter name.
        name: String,
        /// New value.
        value: f64,
    },
}

/// The builtin commands, sorted as `pxh`'s `help` lists them (`help` itself is not one).
const COMMANDS: [&str; 4] = ["commander", "listener", "param", "ver"];

/// The value of parameter `index` as PX4's `param` prints it: an integer, or 4 decimals.
fn shown(params: &ParamTable, index: usize) -> String {
    match params.get(index) {
        Some((def, v)) if def.kind == ParamType::Int32 => format!("{}", v as i64),
        Some((_, v)) => format!("{v:.4}"),
        None => String::new(),
    }
}

/// What the shell prints once the vehicle answered `param set NAME`: the value before and
/// after (PX4's `curr: … -> new: …`) or why it was refused.
pub fn param_set_text(
    params_before: &ParamTable,
    params_after: &ParamTable,
    name: &str,
    result: Result<(), String>,
) -> String {
    match (result, params_before.index_of(name)) {
        (Ok(()), Some(i)) => format!(
            "{name}: curr: {} -> new: {}\n",
            shown(params_before, i),
            shown(params_after, i)
        ),
        (Ok(()), None) => format!("{name}: set\n"),
        (Err(why), _) => format!("ERROR: param set {name} refused: {why}\n"),
    }
}

/// The outcome of one command `line`.
pub fn run(line: &str, ctx: Context) -> ShellOutcome {
    let words: Vec<&str> = line.split_whitespace().collect();
    let text = match words.as_slice() {
        [] => String::new(),
        ["help", ..] => {
            let mut t = String::from("Builtin Commands:\n");
            for name in COMMANDS {
                t += &format!("  {name}\n");
            }
            t
        }
        ["ver", "all"] | ["ver", "fw"] => format!(
            "HW arch: ROTORPILOT_SITL\nFW git tag: v{v}\nFW version: {v} (rotorpilot, PX4-compatible SITL)\nOS: rotorpilot\n",
            v = env!("CARGO_PKG_VERSION")
        ),
        ["ver", ..] => "usage: ver {all|fw}\n".to_string(),
        ["param", "show"] => param_show(ctx.params, None),
        ["param", "show", pattern] => param_show(ctx.params, Some(pattern)),
        ["param", "set", name, value] => return param_set(ctx.params, name, value),
        ["param", ..] => "usage: param show [NAME|PREFIX*] | param set NAME VALUE\n".to_string(),
        ["commander", "status"] => commander_status(ctx),
        ["commander", ..] => "usage: commander status\n".to_string(),
        ["listener", topic, ..] => listener(ctx.snapshot, topic),
        ["listener"] => "usage: listener <topic>\n".to_string(),
        [comment, ..] if comment.starts_with('#') => String::new(),
        [command, ..] => format!("Invalid command: {command}\ntype 'help' for a list of commands\n"),
    };
    ShellOutcome::Text(text)
}

fn param_set(params: &ParamTable, name: &str, value: &str) -> ShellOutcome {
    let Some(index) = params.index_of(name) else {
        return ShellOutcome::Text(format!("ERROR: Parameter {name} not found.\n"));
    };
    match value.parse::<f64>() {
        Ok(v) if v.is_finite() => ShellOutcome::SetParam {
            name: name.to_string(),
            value: v,
        },
        _ => ShellOutcome::Text(format!(
            "ERROR: {value} is not a number (param set {name} VALUE; now {})\n",
            shown(params, index)
        )),
    }
}

/// `param show`: every parameter whose name is `pattern` (or starts with it before a `*`),
/// case-insensitively, then the count.
fn param_show(params: &ParamTable, pattern: Option<&str>) -> String {
    let matches = |name: &str| match pattern {
        None => true,
        Some(p) => match p.strip_suffix('*') {
            Some(prefix) => name.to_ascii_uppercase().starts_with(&prefix.to_ascii_uppercase()),
            None => name.eq_ignore_ascii_case(p),
        },
    };
    let mut t = String::from("Symbols: x = used, + = saved, * = unsaved\n");
    for i in 0..params.len() {
        if let Some((def, _)) = params.get(i).filter(|(d, _)| matches(d.name)) {
            t += &format!("x   {} [{i},{i}] : {}\n", def.name, shown(params, i));
        }
    }
    t + &format!("\n {}/{} parameters used.\n", params.len(), params.len())
}

fn commander_status(ctx: Context) -> String {
    let s = ctx.snapshot;
    let fs = &ctx.params.current().commander.failsafe;
    let battery = s.battery.fraction;
    let level = if battery < fs.battery_emergency {
        "emergency"
    } else if battery < fs.battery_critical {
        "critical"
    } else if battery < fs.battery_low {
        "low"
    } else {
        "none"
    };
    let (main, sub) = s.mode.px4();
    format!(
        "arming state: {}\nnav state: {} ({}, main {main} sub {sub})\nlanded state: {:?}\n\
         failsafes: geofence breached: {}, battery warning: {level} ({:.0} % remaining)\n",
        if s.armed { "ARMED" } else { "STANDBY" },
        s.mode.name(),
        s.mode.ui_name(),
        s.landed,
        if s.geofence_breached { "yes" } else { "no" },
        battery * 100.0,
    )
}

/// `listener TOPIC`: one sample of the uORB-like view of the snapshot.
fn listener(s: &Snapshot, topic: &str) -> String {
    let stamp = (s.t_s * 1e6) as u64;
    let head = format!("\nTOPIC: {topic}\n {topic}\n    timestamp: {stamp} (0 us ago)\n");
    let v3 = |name: &str, v: &Vec3| format!("    {name}: [{:.4}, {:.4}, {:.4}]\n", v.x, v.y, v.z);
    match topic {
        "vehicle_local_position" => {
            head + &format!(
                "    x: {:.4}\n    y: {:.4}\n    z: {:.4}\n    vx: {:.4}\n    vy: {:.4}\n    vz: {:.4}\n    heading: {:.4}\n",
                s.pos_w.x, s.pos_w.y, s.pos_w.z, s.vel_w.x, s.vel_w.y, s.vel_w.z, s.eta.z
            ) + &format!(
                "    ref_lat: {:.7}\n    ref_lon: {:.7}\n    ref_alt: {:.3}\n",
                s.home.lat_deg, s.home.lon_deg, s.home.alt_amsl_m
            )
        }
        "vehicle_attitude" => {
            let q = UnitQuat::from_euler_angles(s.eta.x, s.eta.y, s.eta.z);
            head + &format!("    q: [{:.4}, {:.4}, {:.4}, {:.4}]\n", q.w, q.i, q.j, q.k)
                + &v3("rpy (deg)", &s.eta.map(f64::to_degrees))
                + &v3("angular_velocity", &s.omega_b)
        }
        "battery_status" => {
            let b = &s.battery;
            head + &format!(
                "    voltage_v: {:.3}\n    current_a: {:.3}\n    discharged_mah: {:.1}\n    remaining: {:.3}\n    cell_count: {}\n",
                b.cell_v * f64::from(b.cells),
                b.current_a,
                b.consumed_mah,
                b.fraction,
                b.cells
            )
        }
        other => format!("listener: topic {other} not found (vehicle_local_position, vehicle_attitude, battery_status)\n"),
    }
}

#[cfg(test)]
#[path = "commands_tests.rs"]
mod tests;
