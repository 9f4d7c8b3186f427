//! Key-by-key override of one TOML table by another.

/// Overrides `base` with `overrides`: tables merge recursively, every other value replaces.
pub fn deep_merge(base: &mut toml::Table, overrides: toml::Table) {
    for (key, value) in overrides {
        match (base.get_mut(&key), value) {
            (Some(toml::Value::Table(base_table)), toml::Value::Table(override_table)) => {
                deep_merge(base_table, override_table);
            }
            (_, value) => {
                base.insert(key, value);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nested_tables_merge_and_scalars_replace() {
        let mut base: toml::Table = "[a]\nx = 1\ny = 2\n[b]\nz = 3\n".parse().expect("base");
        let overrides: toml::Table = "[a]\ny = 20\n[c]\nw = 4\n".parse().expect("override");
        deep_merge(&mut base, overrides);
        assert_eq!(base["a"]["x"].as_integer(), Some(1));
        assert_eq!(base["a"]["y"].as_integer(), Some(20));
        assert_eq!(base["b"]["z"].as_integer(), Some(3));
        assert_eq!(base["c"]["w"].as_integer(), Some(4));
    }
}
