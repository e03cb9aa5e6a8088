//! `[plant.wind]` of an airframe file, validated into [`WindSettings`].
//!
//! ```toml
//! [plant.wind]
//! velocity = [0.0, 5.0, 0.0]   # [m/s] the air's velocity, NED (here: from the west)
//! turbulence = 5.0             # [m/s] Dryden intensity W20; omit for none
//! [[plant.wind.gust]]
//! start = 10.0                 # [s]
//! duration = 2.0               # [s]
//! velocity = [3.0, 0.0, 0.0]   # [m/s] peak, NED
//! ```

use super::{Gust, WindSettings};
use crate::file_schema::FileWind;
use crate::params::ParamsError;
use crate::validate::{non_negative, positive, required, vec3, Checker};

/// The wind an airframe file configures; calm without a `[plant.wind]` table.
pub(crate) fn wind_settings(check: &Checker, wind: Option<&FileWind>) -> Result<WindSettings, ParamsError> {
    let Some(wind) = wind else {
        return Ok(WindSettings::default());
    };
    let mean_w = match wind.velocity.clone() {
        Some(v) => vec3(check, v, "plant.wind.velocity")?,
        None => nalgebra::Vector3::zeros(),
    };
    let turbulence_w20_m_s = match wind.turbulence {
        Some(w20) => Some(non_negative(check, w20, "plant.wind.turbulence")?).filter(|w| *w > 0.0),
        None => None,
    };
    let mut gusts = Vec::new();
    for (i, g) in wind.gust.iter().flatten().enumerate() {
        let field = |f: &str| format!("plant.wind.gust[{i}].{f}");
        gusts.push(Gust {
            start_s: non_negative(check, required(check, g.start, &field("start"))?, &field("start"))?,
            duration_s: positive(
                check,
                required(check, g.duration, &field("duration"))?,
                &field("duration"),
            )?,
            peak_w: vec3(
                check,
                required(check, g.velocity.clone(), &field("velocity"))?,
                &field("velocity"),
            )?,
        });
    }
    Ok(WindSettings {
        mean_w,
        turbulence_w20_m_s,
        gusts,
    })
}
