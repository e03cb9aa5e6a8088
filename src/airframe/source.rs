//! Where an airframe's text comes from: a preset name or a file path. This is the only file
//! access of the airframe module; parsing stays pure.

use super::presets::{preset_names, preset_text};
use super::AirframeError;

/// The text of an airframe file and the name it goes by in errors.
#[derive(Debug, Clone, PartialEq)]
pub struct AirframeSource {
    /// Preset name or file path.
    pub origin: String,
    /// TOML text.
    pub text: String,
}

impl AirframeSource {
    /// Resolves `name_or_path`: a preset name first, then a file.
    pub fn resolve(name_or_path: &str) -> Result<Self, AirframeError> {
        if let Some(text) = preset_text(name_or_path) {
            return Ok(Self {
                origin: name_or_path.to_string(),
                text: text.to_string(),
            });
        }
        let path = std::path::Path::new(name_or_path);
        match std::fs::read_to_string(path) {
            Ok(text) => Ok(Self {
                origin: name_or_path.to_string(),
                text,
            }),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound && !name_or_path.contains(['/', '.']) => {
                Err(AirframeError::new(
                    name_or_path,
                    "",
                    format!(
                        "no preset of that name and no such file{} (presets: {})",
                        crate::suggest::did_you_mean(name_or_path, super::presets::PRESETS.iter().map(|(n, _)| *n)),
                        preset_names()
                    ),
                ))
            }
            Err(e) => Err(AirframeError::new(
                name_or_path,
                "",
                format!("cannot read the file: {e}"),
            )),
        }
    }
}
