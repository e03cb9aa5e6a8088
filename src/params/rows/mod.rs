//! Every parameter, declared once: one [`ParamDef`] row each, grouped by what it acts on, and
//! [`rows`], which puts the groups in wire order (index `i` of PARAM_VALUE is the `i`-th row;
//! the order is fixed so clients that cache indices keep working). Pure.
//!
//! # Layout
//! - `flight.rs`: take-off, landing, speeds, accelerations, headings, auto-disarm, land detector,
//!   return destination.
//! - `control.rs`: control law, compensation, tilt limit, guards, air mode.
//! - `estimator.rs`: the wrench estimator's design.
//! - `gains.rs`: every gain of the three laws, per axis.
//! - `failsafe.rs`: link and offboard loss, geofence, battery, failure injection.
//! - `plant.rs`: the plant's ground and ceiling effect, and the simulated wind.
//! - `sticks.rs`: the stick modes: sources, stick loss, take-over, stick shaping.
//! - `follow.rs`: follow-me.
//! - `navigation_filter.rs`: the navigation filter (EKF2_*).
//! - `logger.rs`: the flight logs (SDLOG_MODE).
//! - `imu_aiding.rs`: which aids the navigation filter uses (gravity vector, GNSS,
//!   magnetometer), arming without GPS, the switches of the pre-arm checks and the geofence.
//! - `motors.rs`: motor failures: the reaction, the ESC check, the allocation around them.

/// Declares one [`ParamDef`](super::ParamDef): name, wire type, `[min, max]`, unit, scope
/// ([`Scope`](super::Scope) variant), description, then how it reads and writes the settings:
/// - `value PATH`: the setting at `settings.PATH`, as it is;
/// - `degrees PATH`: a setting in radians, shown in degrees;
/// - `flag PATH`: a `bool`, 0 or 1;
/// - `action TYPE PATH`: an action enum with `TryFrom<i32>` (codes it lacks are refused);
/// - `field FIELD of PATH or DEFAULT`: field `FIELD` of the optional setting at `settings.PATH`,
///   `DEFAULT.FIELD` while that is `None` (a write then changes nothing);
/// - `GET, SET`: explicit functions.
macro_rules! row {
    ($name:expr, $kind:ident, [$min:expr, $max:expr], $unit:literal, $scope:ident, $desc:expr,
     value $($path:ident).+) => {
        row!($name, $kind, [$min, $max], $unit, $scope, $desc,
            |s| s.$($path).+,
            |s, v| {
                s.$($path).+ = v;
                Ok(())
            })
    };
    ($name:expr, $kind:ident, [$min:expr, $max:expr], $unit:literal, $scope:ident, $desc:expr,
     degrees $($path:ident).+) => {
        row!($name, $kind, [$min, $max], $unit, $scope, $desc,
            |s| s.$($path).+.to_degrees(),
            |s, v| {
                s.$($path).+ = v.to_radians();
                Ok(())
            })
    };
    ($name:expr, $kind:ident, [$min:expr, $max:expr], $unit:literal, $scope:ident, $desc:expr,
     flag $($path:ident).+) => {
        row!($name, $kind, [$min, $max], $unit, $scope, $desc,
            |s| f64::from(u8::from(s.$($path).+)),
            |s, v| {
                s.$($path).+ = v != 0.0;
                Ok(())
            })
    };
    ($name:expr, $kind:ident, [$min:expr, $max:expr], $unit:literal, $scope:ident, $desc:expr,
     action $action:ident $($path:ident).+) => {
        $crate::params::ParamDef {
            choices: Some($action::codes),
            ..row!($name, $kind, [$min, $max], $unit, $scope, $desc,
                |s| f64::from(s.$($path).+),
                |s, v| {
                    s.$($path).+ = $action::try_from(v as i32).map_err(|e| e.to_string())?;
                    Ok(())
                })
        }
    };
    ($name:expr, $kind:ident, [$min:expr, $max:expr], $unit:literal, $scope:ident, $desc:expr,
     field $field:ident of $($path:ident).+ or $default:ident) => {
        row!($name, $kind, [$min, $max], $unit, $scope, $desc,
            |s| s.$($path).+.map_or($default.$field, |d| d.$field),
            |s, v| {
                if let Some(d) = &mut s.$($path).+ {
                    d.$field = v;
                }
                Ok(())
            })
    };
    ($name:expr, $kind:ident, [$min:expr, $max:expr], $unit:literal, $scope:ident, $desc:expr,
     $get:expr, $set:expr) => {
        $crate::params::ParamDef {
            name: $name,
            kind: $crate::params::ParamType::$kind,
            min: $min,
            max: $max,
            unit: $unit,
            scope: $crate::params::Scope::$scope,
            description: $desc,
            choices: None,
            get: $get,
            set: $set,
        }
    };
}

mod control;
mod estimator;
mod failsafe;
mod flight;
mod follow;
mod gains;
mod imu_aiding;
mod logger;
mod motors;
mod navigation_filter;
mod plant;
mod sticks;

use super::ParamDef;

/// The groups in wire order.
static GROUPS: [&[ParamDef]; 32] = [
    flight::TAKEOFF_AND_RETURN,
    control::LAW,
    estimator::DESIGN,
    control::LIMITS,
    gains::GEOMETRIC,
    gains::HIERARCHICAL,
    gains::PASSIVITY_SIGMA,
    gains::PASSIVITY,
    control::GUARDS,
    failsafe::LINK_LOSS,
    plant::EFFECTS,
    flight::SPEED_CAPS,
    failsafe::FAILSAFES,
    flight::MOTION,
    flight::RETURN,
    sticks::LOSS,
    sticks::SHAPING,
    follow::FOLLOW,
    plant::WIND,
    failsafe::NAVIGATION_LOSS,
    navigation_filter::NAV_FILTER,
    flight::MISSION,
    logger::LOGGER,
    failsafe::DELAY,
    flight::HEADING,
    flight::RETURN_CONE,
    motors::MOTOR_FAILURE,
    control::AIRMODE,
    flight::AUTO_VERTICAL,
    flight::RETURN_APPROACH,
    imu_aiding::AIDING_SOURCES,
    imu_aiding::SWITCHES,
];

/// Every parameter, in wire order. Decoding applies the rows in this order, so a row may rely
/// on an earlier one (`RP_EST_ORDER` switches the estimator on before its ripple and edge).
pub fn rows() -> impl Iterator<Item = &'static ParamDef> + Clone {
    GROUPS.iter().flat_map(|group| group.iter())
}

#[cfg(test)]
mod tests;
