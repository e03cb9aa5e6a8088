//! The plant's aerodynamic effects near surfaces, switched on or off (contact always stays), and
//! the simulated wind.

use crate::params::ParamDef;

/// Ground and ceiling effect (indices 56–57).
pub(super) static EFFECTS: &[ParamDef] = &[
    row!(
        "RP_GND_EFFECT",
        Int32,
        [0.0, 1.0],
        "",
        Plant,
        "1: the plant's ground effect, as the airframe file configures it, is on (ground contact stays either way)",
        flag ground_effect
    ),
    row!(
        "RP_CEIL_EFFECT",
        Int32,
        [0.0, 1.0],
        "",
        Plant,
        "1: the plant's ceiling effect, as the airframe file configures it, is on",
        flag ceiling_effect
    ),
];

/// The simulated wind (appended after the follow-me group).
pub(super) static WIND: &[ParamDef] = &[
    row!(
        "SIH_WIND_N",
        Real32,
        [-30.0, 30.0],
        "m/s",
        Plant,
        "Mean wind toward north, as PX4 SIH; replaces the airframe's mean wind once changed",
        value wind.north_m_s
    ),
    row!(
        "SIH_WIND_E",
        Real32,
        [-30.0, 30.0],
        "m/s",
        Plant,
        "Mean wind toward east, as PX4 SIH; replaces the airframe's mean wind once changed",
        value wind.east_m_s
    ),
    row!(
        "RP_WIND_TURB",
        Real32,
        [0.0, 30.0],
        "m/s",
        Plant,
        "Dryden turbulence intensity W20 (wind speed at 20 ft, MIL-F-8785C); 0: none",
        value wind.turbulence_w20_m_s
    ),
];
