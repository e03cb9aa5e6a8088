//! "Did you mean …?" for names a user mistyped (airframe presets, control laws, parameters, TOML
//! keys and kinds): the closest known name by edit distance, ignoring case, when it is close
//! enough to be a typo. Pure.

/// Levenshtein distance between `a` and `b`, ignoring ASCII case.
fn distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().map(|c| c.to_ascii_lowercase()).collect();
    let b: Vec<char> = b.chars().map(|c| c.to_ascii_lowercase()).collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.iter().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let substitute = diagonal + usize::from(ca != cb);
            diagonal = row[j + 1];
            row[j + 1] = substitute.min(row[j] + 1).min(diagonal + 1);
        }
    }
    row[b.len()]
}

/// The candidate closest to `name` if it is within a third of the longer name's length (at least
/// 1, at most 3 edits), else `None`.
pub fn closest<'a>(name: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let limit = |c: &str| (name.chars().count().max(c.chars().count()) / 3).clamp(1, 3);
    candidates
        .into_iter()
        .map(|c| (distance(name, c), c))
        .filter(|(d, c)| *d <= limit(c))
        .min_by_key(|(d, _)| *d)
        .map(|(_, c)| c)
}

/// `"; did you mean NAME?"` for the closest candidate, or nothing.
pub fn did_you_mean<'a>(name: &str, candidates: impl IntoIterator<Item = &'a str>) -> String {
    closest(name, candidates).map_or_else(String::new, |c| format!("; did you mean {c}?"))
}

/// The place (`line N`, or empty when unknown) and the reason of a TOML error in `text`, with a
/// "did you mean" when serde names an unknown field or variant and the ones it expected.
pub fn toml_error(text: &str, e: &toml::de::Error) -> (String, String) {
    let place = e.span().map_or_else(String::new, |s| {
        format!("line {}", text[..s.start.min(text.len())].matches('\n').count() + 1)
    });
    let message = e.message().trim();
    (place, format!("{message}{}", unknown_name_hint(message)))
}

/// "; did you mean …?" for serde's "unknown field `x`, expected one of `a`, `b`" (or variant).
fn unknown_name_hint(message: &str) -> String {
    let quoted: Vec<&str> = message.split('`').skip(1).step_by(2).collect();
    match quoted.split_first() {
        Some((name, expected)) if message.starts_with("unknown ") => did_you_mean(name, expected.iter().copied()),
        _ => String::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn typos_find_their_name_and_strangers_find_none() {
        let names = ["quad_x", "hexa_x", "octo", "fsr_quad"];
        assert_eq!(closest("quadx", names), Some("quad_x"));
        assert_eq!(closest("QUAD_X", names), Some("quad_x"));
        assert_eq!(closest("hexa", names), Some("hexa_x"));
        assert_eq!(closest("helicopter", names), None);
        assert_eq!(
            did_you_mean("MPC_XY_VEL_MX", ["MPC_XY_VEL_MAX"]),
            "; did you mean MPC_XY_VEL_MAX?"
        );
        assert_eq!(did_you_mean("zzz", ["MPC_XY_VEL_MAX"]), "");
    }

    #[test]
    fn unknown_toml_keys_and_variants_get_a_suggestion() {
        let text = "duraton = 3\n";
        #[derive(Debug, serde::Deserialize)]
        #[serde(deny_unknown_fields)]
        #[allow(dead_code)]
        struct File {
            duration: f64,
        }
        let e = toml::from_str::<File>(text).unwrap_err();
        let (place, reason) = toml_error(text, &e);
        assert_eq!(place, "line 1");
        assert!(reason.ends_with("; did you mean duration?"), "{reason}");
        assert_eq!(
            unknown_name_hint("unknown variant `hoover`, expected one of `hover`, `circle`"),
            "; did you mean hover?"
        );
        assert_eq!(unknown_name_hint("invalid type: string"), "");
    }

    #[test]
    fn distance_counts_edits() {
        assert_eq!(distance("kitten", "sitting"), 3);
        assert_eq!(distance("", "abc"), 3);
        assert_eq!(distance("same", "same"), 0);
    }
}
