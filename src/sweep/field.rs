//! Scenario fields by path: `estimator.order`, `initial.position[2]`, `airframe.overrides.plant.wind.velocity[1]`
//! (docs/sweep.md §1). Setting one creates the tables on the way; the scenario's own checks then
//! refuse a field that does not exist. Pure.

use super::SweepError;

/// One step of a path: a table key or an array index.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Step {
    Key(String),
    Index(usize),
}

/// The steps of `path`, or why it is not a path.
fn parse(path: &str) -> Result<Vec<Step>, SweepError> {
    let bad = |why: &str| SweepError::Invalid(format!("field `{path}`: {why}"));
    let mut steps = Vec::new();
    for part in path.split('.') {
        let (key, mut rest) = part.split_at(part.find('[').unwrap_or(part.len()));
        if key.is_empty() || !key.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-') {
            return Err(bad("expected names joined by dots, each with optional [index]"));
        }
        steps.push(Step::Key(key.to_string()));
        while !rest.is_empty() {
            let close = rest.find(']').ok_or_else(|| bad("unclosed ["))?;
            let index = rest[1..close]
                .parse::<usize>()
                .map_err(|_| bad("an index is a whole number"))?;
            steps.push(Step::Index(index));
            rest = &rest[close + 1..];
            if !rest.is_empty() && !rest.starts_with('[') {
                return Err(bad("text after ]"));
            }
        }
    }
    Ok(steps)
}

/// Checks that `path` is a well-formed field path.
pub fn check(path: &str) -> Result<(), SweepError> {
    parse(path).map(|_| ())
}

/// Sets the field at `path` of `table` to `value`, creating missing tables on the way; an index
/// must name an element of an existing array.
pub fn set(table: &mut toml::Table, path: &str, value: toml::Value) -> Result<(), SweepError> {
    let steps = parse(path)?;
    let missing = |what: &str| SweepError::Invalid(format!("field `{path}`: {what}"));
    let mut slot: &mut toml::Value = match &steps[0] {
        Step::Key(k) => table
            .entry(k.clone())
            .or_insert_with(|| toml::Value::Table(toml::Table::new())),
        Step::Index(_) => return Err(missing("starts with an index")),
    };
    for step in &steps[1..] {
        slot = match (step, slot) {
            (Step::Key(k), toml::Value::Table(t)) => t
                .entry(k.clone())
                .or_insert_with(|| toml::Value::Table(toml::Table::new())),
            (Step::Index(i), toml::Value::Array(a)) => {
                let len = a.len();
                a.get_mut(*i)
                    .ok_or_else(|| missing(&format!("index {i} beyond the array's {len} elements")))?
            }
            (Step::Key(k), _) => return Err(missing(&format!("`{k}` is inside a value that is not a table"))),
            (Step::Index(i), _) => return Err(missing(&format!("[{i}] indexes a value that is not an array"))),
        };
    }
    *slot = value;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_and_indices_set_existing_and_new_fields() {
        let mut t: toml::Table = toml::from_str("[initial]\nposition = [0.0, 0.0, -1.0]\n").unwrap();
        set(&mut t, "initial.position[2]", toml::Value::Float(-3.0)).unwrap();
        set(&mut t, "estimator.order", toml::Value::Integer(4)).unwrap();
        assert_eq!(t["initial"]["position"][2].as_float(), Some(-3.0));
        assert_eq!(t["estimator"]["order"].as_integer(), Some(4));
    }

    #[test]
    fn bad_paths_name_what_is_wrong() {
        let mut t: toml::Table = toml::from_str("duration = 5.0\n[initial]\nposition = [0.0]\n").unwrap();
        let err = |p: &str| set(&mut t.clone(), p, toml::Value::Integer(1)).unwrap_err().to_string();
        assert!(err("initial.position[3]").contains("index 3 beyond the array's 1 elements"));
        assert!(err("duration.x").contains("`x` is inside a value that is not a table"));
        assert!(err("initial.position[a]").contains("whole number"));
        assert!(err("a..b").contains("names joined by dots"));
        assert!(err("initial.position[0").contains("unclosed"));
        set(&mut t, "duration", toml::Value::Float(9.0)).unwrap();
        assert_eq!(t["duration"].as_float(), Some(9.0));
    }
}
