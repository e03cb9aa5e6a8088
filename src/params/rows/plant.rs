//! The plant's aerodynamic effects near surfaces, switched on or off (contact always stays).

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
