//! One parameter's declaration: name, wire type, range, unit, meaning, the part of the vehicle it
//! applies to, and how it reads and writes [`VehicleSettings`]. Pure.

use std::fmt;

use super::VehicleSettings;

/// How a parameter travels (MAV_PARAM_TYPE).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ParamType {
    /// 32-bit signed integer (byte-wise in the float field).
    Int32,
    /// 32-bit float.
    Real32,
}

impl ParamType {
    /// MAVLink's name for the type (`INT32`, `REAL32`).
    pub fn name(self) -> &'static str {
        match self {
            Self::Int32 => "INT32",
            Self::Real32 => "REAL32",
        }
    }
}

/// The part of the vehicle a parameter acts on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scope {
    /// Arming, modes, take-off, auto-disarm.
    Commander,
    /// Speeds, accelerations, heights and headings of the AUTO paths and offboard setpoints.
    Navigation,
    /// On the ground or in the air.
    LandDetector,
    /// What the vehicle does when something goes wrong.
    Failsafe,
    /// How the stick modes read the sticks.
    Sticks,
    /// The pack the energy gauge counts against.
    Battery,
    /// The control law, its gains and guards.
    Controller,
    /// The wrench estimator.
    Estimator,
    /// The simulated vehicle.
    Plant,
    /// The navigation filter (EKF2_*).
    NavFilter,
    /// The flight logs (SDLOG_*).
    Logger,
}

impl fmt::Display for Scope {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Commander => "commander",
            Self::Navigation => "navigation",
            Self::LandDetector => "land detector",
            Self::Failsafe => "failsafe",
            Self::Sticks => "sticks",
            Self::Battery => "battery",
            Self::Controller => "controller",
            Self::Estimator => "estimator",
            Self::Plant => "plant",
            Self::NavFilter => "navigation filter",
            Self::Logger => "logger",
        })
    }
}

/// The codes of an INT32 choice, each with its meaning, by code.
pub type Codes = fn() -> Vec<(i32, &'static str)>;

/// One parameter, declared once (in `params::rows`): everything the table, the MAVLink parameter
/// protocol and docs/parameters.md need to know about it.
#[derive(Debug, Clone, Copy)]
pub struct ParamDef {
    /// Name (≤ 16 characters: MAVLink's `param_id`).
    pub name: &'static str,
    /// Wire type.
    pub kind: ParamType,
    /// Smallest value, in the parameter's unit.
    pub min: f64,
    /// Largest value, in the parameter's unit.
    pub max: f64,
    /// Unit of the value (`m/s`, `deg`; empty for codes, switches and fractions).
    pub unit: &'static str,
    /// What it acts on.
    pub scope: Scope,
    /// What it means, in one line.
    pub description: &'static str,
    /// The codes an INT32 choice accepts, each with its meaning (`(1, "hold")`); other codes
    /// in `[min, max]` are refused by the setter.
    pub choices: Option<Codes>,
    /// The value of the parameter in `settings`, in the parameter's unit.
    pub get: fn(&VehicleSettings) -> f64,
    /// Writes a value already checked against the type and range into `settings`; a code that
    /// names nothing (a hole in a choice's range) is refused with the reason.
    pub set: fn(&mut VehicleSettings, f64) -> Result<(), String>,
}

impl PartialEq for ParamDef {
    /// Names are unique, so a parameter is its name.
    fn eq(&self, other: &Self) -> bool {
        self.name == other.name
    }
}

impl ParamDef {
    /// Why `value` cannot be this parameter's value before it reaches the setter: not a finite
    /// number, not an integer for an INT32, or outside `[min, max]`.
    pub fn check(&self, value: f64) -> Result<(), String> {
        if !value.is_finite() {
            return Err(format!("{value} is not a number"));
        }
        if self.kind == ParamType::Int32 && value.fract() != 0.0 {
            return Err(format!("{value} is not an integer"));
        }
        if value < self.min || value > self.max {
            return Err(format!("{value} outside [{}, {}]", self.min, self.max));
        }
        Ok(())
    }
}
