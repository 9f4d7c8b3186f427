//! The targets `hopnav compare --expect FILE` judges. Without the file no verdict is printed:
//! the comparison only reports its figures.
//!
//! The file is TOML; every table and key is optional, but it must set at least one target.
//! Each target judges every "cooperative vs rover-only" comparison of the run (the base's, and
//! each variant's), on the median of the per-seed ratios over the seeds both modes reached B:
//!
//! ```toml
//! [paths]
//! cooperative_shorter_by_percent = 15    # cooperative's path at least 15 % shorter (0..100)
//! [replans]
//! fewer_by_percent = 20                  # cooperative needs at least 20 % fewer (0..=100)
//! [route_changes]
//! fewer_by_percent = 10                  # replans that moved the route, at least 10 % fewer
//! [success]
//! cooperative_at_least_rover_only = true # cooperative reaches B on at least as many seeds
//! ```

use std::fmt;
use std::path::{Path, PathBuf};

/// The targets of one `--expect` file.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Expectations {
    /// `[paths] cooperative_shorter_by_percent`.
    pub path_shorter_by_percent: Option<f64>,
    /// `[replans] fewer_by_percent`.
    pub replans_fewer_by_percent: Option<f64>,
    /// `[route_changes] fewer_by_percent`.
    pub route_changes_fewer_by_percent: Option<f64>,
    /// `[success] cooperative_at_least_rover_only` (false: not judged).
    pub success_at_least_rover_only: bool,
}

/// A targets file that cannot be used.
#[derive(Debug)]
pub struct ExpectError {
    /// The file given to `--expect`.
    pub path: PathBuf,
    /// What is wrong, naming the key.
    pub message: String,
}

impl fmt::Display for ExpectError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "targets file {}: {}", self.path.display(), self.message)
    }
}

impl std::error::Error for ExpectError {}

/// The value a key takes.
#[derive(Clone, Copy)]
enum KeyKind {
    /// A number of percent, at least 0 and at most (or below) 100.
    Percent {
        below_100: bool,
    },
    Bool,
}

/// Every table, its keys and their kinds.
const SCHEMA: &[(&str, &[(&str, KeyKind)])] = &[
    (
        "paths",
        &[(
            "cooperative_shorter_by_percent",
            KeyKind::Percent { below_100: true },
        )],
    ),
    (
        "replans",
        &[("fewer_by_percent", KeyKind::Percent { below_100: false })],
    ),
    (
        "route_changes",
        &[("fewer_by_percent", KeyKind::Percent { below_100: false })],
    ),
    (
        "success",
        &[("cooperative_at_least_rover_only", KeyKind::Bool)],
    ),
];

fn known_keys(keys: &[(&str, KeyKind)]) -> String {
    keys.iter()
        .map(|(key, _)| *key)
        .collect::<Vec<_>>()
        .join(", ")
}

/// A checked value: a percent or a flag.
enum Checked {
    Percent(f64),
    Bool(bool),
}

fn check(key: &str, kind: KeyKind, value: &toml::Value) -> Result<Checked, String> {
    match kind {
        KeyKind::Bool => value
            .as_bool()
            .map(Checked::Bool)
            .ok_or_else(|| format!("{key} must be true or false, found {}", value.type_str())),
        KeyKind::Percent { below_100 } => {
            let percent = value
                .as_float()
                .or_else(|| value.as_integer().map(|i| i as f64))
                .ok_or_else(|| format!("{key} must be a number, found {}", value.type_str()))?;
            let in_range = percent.is_finite()
                && percent >= 0.0
                && (percent < 100.0 || (!below_100 && percent == 100.0));
            if in_range {
                Ok(Checked::Percent(percent))
            } else {
                let upper = if below_100 {
                    "below 100"
                } else {
                    "at most 100"
                };
                Err(format!("{key} = {percent} must be at least 0 and {upper}"))
            }
        }
    }
}

/// Parses the text of a targets file.
pub fn parse(text: &str) -> Result<Expectations, String> {
    let table: toml::Table = text
        .parse()
        .map_err(|error| format!("not valid TOML: {error}"))?;
    let mut expect = Expectations::default();
    let mut targets = 0;
    for (name, value) in &table {
        let Some((_, keys)) = SCHEMA.iter().find(|(known, _)| known == name) else {
            let tables: Vec<&str> = SCHEMA.iter().map(|(known, _)| *known).collect();
            return Err(format!(
                "unknown table [{name}] (known tables: {})",
                tables.join(", ")
            ));
        };
        let Some(entries) = value.as_table() else {
            return Err(format!(
                "{name} must be a table [{name}], found {}",
                value.type_str()
            ));
        };
        for (key, value) in entries {
            let path = format!("{name}.{key}");
            let Some((_, kind)) = keys.iter().find(|(known, _)| known == key) else {
                return Err(format!(
                    "unknown key {path} (known keys of [{name}]: {})",
                    known_keys(keys)
                ));
            };
            match (name.as_str(), check(&path, *kind, value)?) {
                ("paths", Checked::Percent(p)) => expect.path_shorter_by_percent = Some(p),
                ("replans", Checked::Percent(p)) => expect.replans_fewer_by_percent = Some(p),
                ("route_changes", Checked::Percent(p)) => {
                    expect.route_changes_fewer_by_percent = Some(p);
                }
                (_, Checked::Bool(flag)) => expect.success_at_least_rover_only = flag,
                _ => return Err(format!("{path}: unexpected value")),
            }
            targets += 1;
        }
    }
    if targets == 0 {
        return Err("sets no target (see `hopnav compare --help` for its keys)".to_owned());
    }
    Ok(expect)
}

/// Reads and parses the targets file at `path`.
pub fn load(path: &Path) -> Result<Expectations, ExpectError> {
    let error = |message| ExpectError {
        path: path.to_owned(),
        message,
    };
    let text = std::fs::read_to_string(path).map_err(|e| error(format!("cannot read: {e}")))?;
    parse(&text).map_err(error)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_valid_targets_file_sets_each_target() {
        let expect = parse(
            "[paths]\ncooperative_shorter_by_percent = 15\n[replans]\nfewer_by_percent = 20.5\n\
             [route_changes]\nfewer_by_percent = 100\n[success]\ncooperative_at_least_rover_only = true\n",
        )
        .expect("valid");
        assert_eq!(
            expect,
            Expectations {
                path_shorter_by_percent: Some(15.0),
                replans_fewer_by_percent: Some(20.5),
                route_changes_fewer_by_percent: Some(100.0),
                success_at_least_rover_only: true,
            }
        );
        let paths_only = parse("[paths]\ncooperative_shorter_by_percent = 0\n").expect("one");
        assert_eq!(paths_only.replans_fewer_by_percent, None);
        assert!(!paths_only.success_at_least_rover_only);
    }

    /// `text` is rejected with an error that contains every one of `parts`.
    fn assert_rejected_naming(text: &str, parts: &[&str]) {
        let error = parse(text).expect_err("must be rejected");
        for part in parts {
            assert!(error.contains(part), "{part}: {error}");
        }
    }

    #[test]
    fn unknown_tables_and_keys_are_named() {
        assert_rejected_naming(
            "[paths]\nshorter_by_percent = 15\n",
            &[
                "unknown key paths.shorter_by_percent",
                "cooperative_shorter_by_percent",
            ],
        );
        assert_rejected_naming(
            "[path]\ncooperative_shorter_by_percent = 15\n",
            &["unknown table [path]"],
        );
        assert_rejected_naming("paths = 15\n", &["must be a table"]);
    }

    #[test]
    fn wrong_types_and_ranges_are_named() {
        assert_rejected_naming(
            "[replans]\nfewer_by_percent = \"20\"\n",
            &["replans.fewer_by_percent must be a number, found string"],
        );
        assert_rejected_naming(
            "[success]\ncooperative_at_least_rover_only = 1\n",
            &["must be true or false"],
        );
        assert_rejected_naming(
            "[paths]\ncooperative_shorter_by_percent = 100\n",
            &["below 100"],
        );
        assert_rejected_naming("[replans]\nfewer_by_percent = -5\n", &["at least 0"]);
        assert_rejected_naming("[paths\n", &["not valid TOML"]);
        assert_rejected_naming("", &["sets no target"]);
    }

    #[test]
    fn a_missing_file_names_the_file() {
        let error = load(Path::new("/nonexistent/targets.toml")).expect_err("missing");
        assert!(
            error
                .to_string()
                .starts_with("targets file /nonexistent/targets.toml: cannot read"),
            "{error}"
        );
    }
}
