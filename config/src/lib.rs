//! hopnav's configuration: TOML defaults embedded in the binary, overridden key by key by a
//! user file, deserialized with the path of any bad key, and validated against ranges.
//!
//! ```
//! let config = hopnav_config::load(Some("[run]\nframes = 12\n")).expect("valid");
//! assert_eq!(config.run.frames, 12);
//! assert_eq!(config.run.frame_rate_hz, 10.0); // from the embedded defaults
//!
//! let error = hopnav_config::load(Some("[run]\nframe_rate_hz = -1.0\n")).unwrap_err();
//! assert!(error.to_string().contains("run.frame_rate_hz"));
//! ```
#![warn(missing_docs)]

mod error;
pub mod fault;
mod merge;
pub mod range;
mod schema;
mod validate;

use std::path::Path;

pub use error::ConfigError;
pub use merge::deep_merge;
pub use schema::{
    HopnavConfig, MissionConfig, MissionMode, ProbeConfig, ProcessConfig, RecorderConfig,
    RestartConfig, RestartPolicy, RunConfig, WatchdogConfig,
};

/// The embedded default configuration.
pub const DEFAULT_TOML: &str = include_str!("../default.toml");

/// Loads the defaults overridden by `override_toml` (if any) and validates the result.
pub fn load(override_toml: Option<&str>) -> Result<HopnavConfig, ConfigError> {
    let mut table = parse_table(DEFAULT_TOML, "embedded defaults")?;
    if let Some(text) = override_toml {
        merge::deep_merge(&mut table, parse_table(text, "config file")?);
    }
    let config: HopnavConfig = serde_path_to_error::deserialize(toml::Value::Table(table))
        .map_err(|error| ConfigError::Schema {
            key: error.path().to_string(),
            message: error.inner().to_string(),
        })?;
    validate::validate(&config)?;
    Ok(config)
}

/// Loads the defaults overridden by the TOML file at `path`.
pub fn load_file(path: &Path) -> Result<HopnavConfig, ConfigError> {
    let text = std::fs::read_to_string(path).map_err(|error| ConfigError::Io {
        path: path.display().to_string(),
        message: error.to_string(),
    })?;
    load(Some(&text))
}

/// Parses the process-specific table `[name]` (absent = empty, so the type's serde defaults
/// apply). A bad key is reported with its full path, e.g. `physics.jumper.launch_speed_mps`.
pub fn parse_section<T: serde::de::DeserializeOwned>(
    config: &HopnavConfig,
    name: &str,
) -> Result<T, ConfigError> {
    let table = match config.sections.get(name) {
        Some(toml::Value::Table(table)) => table.clone(),
        Some(other) => {
            return Err(ConfigError::Schema {
                key: name.to_owned(),
                message: format!("expected a table, found {}", other.type_str()),
            });
        }
        None => toml::Table::new(),
    };
    serde_path_to_error::deserialize(toml::Value::Table(table)).map_err(|error| {
        let path = error.path().to_string();
        ConfigError::Schema {
            key: if path == "." {
                name.to_owned()
            } else {
                format!("{name}.{path}")
            },
            message: error.inner().to_string(),
        }
    })
}

/// The number at `[table] path…` of another process's section (an integer reads as a
/// float), for a reader that needs one value of it without parsing the whole section;
/// `None` when absent or not a number. The owning process validates it.
pub fn number_at(config: &HopnavConfig, table: &str, path: &[&str]) -> Option<f64> {
    let mut value = config.sections.get(table)?;
    for key in path {
        value = value.get(*key)?;
    }
    value
        .as_float()
        .or_else(|| value.as_integer().map(|i| i as f64))
}

/// Rejects top-level tables that no process library knows (a typo like `[phsyics]`).
pub fn check_section_names(config: &HopnavConfig, known: &[&str]) -> Result<(), ConfigError> {
    match config
        .sections
        .keys()
        .find(|name| !known.contains(&name.as_str()))
    {
        Some(unknown) => Err(ConfigError::Schema {
            key: unknown.clone(),
            message: format!(
                "unknown config table (known tables: run, watchdog, restart, processes, probe, recorder, mission, faults, {})",
                known.join(", ")
            ),
        }),
        None => Ok(()),
    }
}

/// Prefixes the key of a library's own validation error with its section name.
pub fn in_section(
    name: &str,
    key: &str,
    value: impl std::fmt::Display,
    allowed: impl std::fmt::Display,
) -> ConfigError {
    ConfigError::OutOfRange {
        key: format!("{name}.{key}"),
        value: value.to_string(),
        allowed: allowed.to_string(),
    }
}

/// The configuration as TOML (written next to each run's report and read by the children).
pub fn to_toml(config: &HopnavConfig) -> Result<String, ConfigError> {
    toml::to_string_pretty(config).map_err(|error| ConfigError::Serialize(error.to_string()))
}

fn parse_table(text: &str, origin: &'static str) -> Result<toml::Table, ConfigError> {
    text.parse::<toml::Table>()
        .map_err(|error| ConfigError::Syntax {
            origin,
            message: error.to_string(),
        })
}
