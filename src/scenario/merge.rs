//! Deep merge of TOML tables: tables merge key by key, anything else is replaced.

/// Merges `over` into `base`.
pub fn merge_tables(base: &mut toml::Table, over: &toml::Table) {
    for (key, value) in over {
        match (base.get_mut(key), value) {
            (Some(toml::Value::Table(b)), toml::Value::Table(o)) => merge_tables(b, o),
            _ => {
                base.insert(key.clone(), value.clone());
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nested_tables_merge_and_values_replace() {
        let mut base: toml::Table = toml::from_str("a = 1\n[v]\nmass = 1.5\ninertia = [1, 2, 3]\n").unwrap();
        let over: toml::Table = toml::from_str("[v]\nmass = 1.7\n[fc]\nmass = 1.5\n").unwrap();
        merge_tables(&mut base, &over);
        assert_eq!(base["v"]["mass"].as_float(), Some(1.7));
        assert_eq!(base["v"]["inertia"].as_array().map(Vec::len), Some(3));
        assert_eq!(base["fc"]["mass"].as_float(), Some(1.5));
        assert_eq!(base["a"].as_integer(), Some(1));
    }
}
