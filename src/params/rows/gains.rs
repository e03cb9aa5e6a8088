//! Every gain of the three laws (`RP_GEO_*`, `RP_HIE_*`, `RP_PAS_*`), one parameter per axis, in
//! the units of `control::gains`. Gains in force and torque units scale with the airframe's mass
//! and inertia ([`ControllerGains::for_vehicle`](crate::control::ControllerGains::for_vehicle)),
//! so their defaults depend on the airframe. Any value ≤ 0 is refused by the whole-table check.

use crate::params::ParamDef;

/// The rows of 3-vector gains `gains.LAW.FIELD`, one per axis: `[LAW.FIELD, NAME, UNIT,
/// DESCRIPTION, AXES]` declares `NAME_SUFFIX` for the x, y and z components, described as
/// `DESCRIPTION LABEL`; AXES is `xyz` (suffixes X, Y, Z; labels x, y, z) or `rpy` (R, P, Y;
/// roll, pitch, yaw).
macro_rules! per_axis {
    (@rows [$($out:tt)*]) => { &[$($out)*] };
    (@rows $out:tt [$law:ident . $field:ident, $prefix:literal, $unit:literal, $desc:literal, xyz] $($rest:tt)*) => {
        per_axis!(@rows $out [$law.$field, $prefix, $unit, $desc, "X" "x", "Y" "y", "Z" "z"] $($rest)*)
    };
    (@rows $out:tt [$law:ident . $field:ident, $prefix:literal, $unit:literal, $desc:literal, rpy] $($rest:tt)*) => {
        per_axis!(@rows $out [$law.$field, $prefix, $unit, $desc, "R" "roll", "P" "pitch", "Y" "yaw"] $($rest)*)
    };
    (@rows [$($out:tt)*] [$law:ident . $field:ident, $prefix:literal, $unit:literal, $desc:literal,
        $sx:literal $lx:literal, $sy:literal $ly:literal, $sz:literal $lz:literal] $($rest:tt)*) => {
        per_axis!(@rows [$($out)*
            row!(concat!($prefix, "_", $sx), Real32, [0.0, 1e6], $unit, Controller, concat!($desc, " ", $lx),
                value gains.$law.$field.x),
            row!(concat!($prefix, "_", $sy), Real32, [0.0, 1e6], $unit, Controller, concat!($desc, " ", $ly),
                value gains.$law.$field.y),
            row!(concat!($prefix, "_", $sz), Real32, [0.0, 1e6], $unit, Controller, concat!($desc, " ", $lz),
                value gains.$law.$field.z),
        ] $($rest)*)
    };
    ($($gain:tt),+ $(,)?) => { per_axis!(@rows [] $($gain)+) };
}

/// Geometric law (indices 14–25).
pub(super) static GEOMETRIC: &[ParamDef] = per_axis![
    [
        geometric.kp,
        "RP_GEO_KP",
        "N/m",
        "Geometric K_p: position stiffness (scales with the mass), world",
        xyz
    ],
    [
        geometric.kv,
        "RP_GEO_KV",
        "N·s/m",
        "Geometric K_v: velocity damping (scales with the mass), world",
        xyz
    ],
    [
        geometric.kr,
        "RP_GEO_KR",
        "N·m/rad",
        "Geometric K_R: attitude stiffness (scales with the inertia), body",
        xyz
    ],
    [
        geometric.komega,
        "RP_GEO_KW",
        "N·m·s/rad",
        "Geometric K_ω: rate damping (scales with the inertia), body",
        xyz
    ],
];

/// Hierarchical law, per unit mass and inertia (indices 26–37).
pub(super) static HIERARCHICAL: &[ParamDef] = per_axis![
    [
        hierarchical.kp,
        "RP_HIE_KP",
        "1/s²",
        "Hierarchical K_P: position stiffness per unit mass, world",
        xyz
    ],
    [
        hierarchical.kd,
        "RP_HIE_KD",
        "1/s",
        "Hierarchical K_D: velocity damping per unit mass, world",
        xyz
    ],
    [
        hierarchical.k_eta,
        "RP_HIE_KETA",
        "1/s²",
        "Hierarchical K_η: attitude stiffness per unit inertia,",
        rpy
    ],
    [
        hierarchical.k_eta_dot,
        "RP_HIE_KETAD",
        "1/s",
        "Hierarchical K_η̇: attitude-rate damping per unit inertia,",
        rpy
    ],
];

/// Passivity law's coupling σ (index 38).
pub(super) static PASSIVITY_SIGMA: &[ParamDef] = &[row!(
    "RP_PAS_SIGMA",
    Real32,
    [0.0, 1e3],
    "1/s",
    Controller,
    "Passivity σ: coupling of the attitude error with its rate in the sliding variable",
    value gains.passivity.sigma
)];

/// Passivity law's dampings and stiffnesses (indices 39–50).
pub(super) static PASSIVITY: &[ParamDef] = per_axis![
    [
        passivity.d_a,
        "RP_PAS_DA",
        "N·m·s/rad",
        "Passivity D_a: angular damping (scales with the inertia),",
        rpy
    ],
    [
        passivity.k_a,
        "RP_PAS_KA",
        "N·m/rad",
        "Passivity K_a: angular stiffness (scales with the inertia),",
        rpy
    ],
    [
        passivity.d_o,
        "RP_PAS_DO",
        "N·s/m",
        "Passivity D_o: linear damping (scales with the mass), world",
        xyz
    ],
    [
        passivity.k_o,
        "RP_PAS_KO",
        "N/m",
        "Passivity K_o: linear stiffness (scales with the mass), world",
        xyz
    ],
];
