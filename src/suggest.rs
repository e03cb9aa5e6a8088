//! "Did you mean …?" for names a user mistyped (airframe presets, control laws, parameters): the
//! closest known name by edit distance, ignoring case, when it is close enough to be a typo.
//! Pure.

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

/// The candidate closest to `name` if it is within a third of the name's length (at least 1, at
/// most 3 edits), else `None`.
pub fn closest<'a>(name: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let limit = (name.chars().count() / 3).clamp(1, 3);
    candidates
        .into_iter()
        .map(|c| (distance(name, c), c))
        .filter(|(d, _)| *d <= limit)
        .min_by_key(|(d, _)| *d)
        .map(|(_, c)| c)
}

/// `"; did you mean NAME?"` for the closest candidate, or nothing.
pub fn did_you_mean<'a>(name: &str, candidates: impl IntoIterator<Item = &'a str>) -> String {
    closest(name, candidates).map_or_else(String::new, |c| format!("; did you mean {c}?"))
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
    fn distance_counts_edits() {
        assert_eq!(distance("kitten", "sitting"), 3);
        assert_eq!(distance("", "abc"), 3);
        assert_eq!(distance("same", "same"), 0);
    }
}
