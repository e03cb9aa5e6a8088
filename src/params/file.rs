//! Parameter files for `rotorpilot run --params FILE`: QGroundControl's format (one parameter per
//! line, tab- or space-separated `sysid compid NAME VALUE TYPE`, `#` comments) or plain
//! `NAME VALUE` lines. Pure: text in, `(line, name, value)` out; errors name the line.

use thiserror::Error;

/// A line that is not a parameter assignment.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("{origin}:{line}: {reason}")]
pub struct ParamFileError {
    /// File name.
    pub origin: String,
    /// 1-based line number.
    pub line: usize,
    /// What is wrong.
    pub reason: String,
}

/// Every assignment in `text`, in order.
pub fn parse_param_file(text: &str, origin: &str) -> Result<Vec<(usize, String, f64)>, ParamFileError> {
    let mut out = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = raw.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let err = |reason: String| ParamFileError {
            origin: origin.to_string(),
            line: i + 1,
            reason,
        };
        let fields: Vec<&str> = line.split_whitespace().collect();
        let (name, value) = match fields[..] {
            [name, value] => (name, value),
            [_sys, _comp, name, value, _type] => (name, value),
            _ => {
                return Err(err(format!(
                    "expected `NAME VALUE` or `SYSID COMPID NAME VALUE TYPE`, got {line:?}"
                )))
            }
        };
        let value: f64 = value
            .parse()
            .map_err(|_| err(format!("{name}: value {value:?} is not a number")))?;
        out.push((i + 1, name.to_string(), value));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn qgc_and_plain_lines() {
        let text = "# Onboard parameters for Vehicle 1\n#\n# Stack: PX4\n1\t1\tMIS_TAKEOFF_ALT\t5.000000000000000000\t9\n\nRP_CTRL 2 # passivity\n";
        let p = parse_param_file(text, "x.params").unwrap();
        assert_eq!(
            p,
            vec![(4, "MIS_TAKEOFF_ALT".to_string(), 5.0), (6, "RP_CTRL".to_string(), 2.0)]
        );
        let e = parse_param_file("RP_CTRL two\n", "x.params").unwrap_err();
        assert_eq!((e.line, e.to_string().contains("not a number")), (1, true));
        assert!(parse_param_file("A B C\n", "x").is_err());
    }
}
