//! `hopnav defaults`: the whole default configuration, every key with its value.
//!
//! Each default is written once. The runtime's own tables (`[run]`, `[processes.*]`,
//! `[mission]`, …) have theirs in the embedded `config/default.toml`; each process library's
//! table (`[world]`, `[physics]`, `[mapper]`, …) has them in its Rust `Default`, and the
//! embedded file holds only what the default mission sets differently (its A and B). This
//! command merges the two, so a user sees every value in one place.

use std::process::ExitCode;

use clap::Args;
use serde::Serialize;

#[derive(Debug, Args)]
pub struct DefaultsArgs {
    /// Print only this top-level table (e.g. `mapper`, `physics`, `run`).
    #[arg(long, value_name = "TABLE")]
    table: Option<String>,
}

/// Every process library's defaults, as the TOML tables they parse.
pub fn library_defaults() -> Result<toml::Table, String> {
    let mut tables = toml::Table::new();
    insert(&mut tables, "world", &hopnav_world::WorldConfig::default())?;
    insert(
        &mut tables,
        "camera",
        &hopnav_camera::CameraSection::default(),
    )?;
    insert(
        &mut tables,
        "physics",
        &hopnav_physics::PhysicsConfig::default(),
    )?;
    insert(
        &mut tables,
        "jumper_vo",
        &hopnav_jumper_vo::config::JumperVoConfig::default(),
    )?;
    insert(
        &mut tables,
        "rover_vo",
        &hopnav_rover_vo::config::RoverVoConfig::default(),
    )?;
    insert(
        &mut tables,
        "mapper",
        &hopnav_mapper::config::MapperConfig::default(),
    )?;
    insert(
        &mut tables,
        "planner",
        &hopnav_planner::mission::NavigatorConfig::default(),
    )?;
    Ok(tables)
}

fn insert(tables: &mut toml::Table, name: &str, value: &impl Serialize) -> Result<(), String> {
    let value = toml::Value::try_from(value).map_err(|error| format!("[{name}]: {error}"))?;
    tables.insert(name.to_owned(), value);
    Ok(())
}

/// The embedded defaults merged over every library's: the configuration `hopnav launch`
/// runs with no file.
pub fn effective_defaults() -> Result<toml::Table, String> {
    let mut merged = library_defaults()?;
    let embedded: toml::Table = hopnav_config::DEFAULT_TOML
        .parse()
        .map_err(|error| format!("embedded defaults: {error}"))?;
    hopnav_config::deep_merge(&mut merged, embedded);
    Ok(merged)
}

pub fn run(args: DefaultsArgs) -> ExitCode {
    let merged = match effective_defaults() {
        Ok(merged) => merged,
        Err(error) => {
            eprintln!("error: {error}");
            return ExitCode::FAILURE;
        }
    };
    let shown = match &args.table {
        None => merged,
        Some(name) => match merged.get(name) {
            Some(value) => toml::Table::from_iter([(name.clone(), value.clone())]),
            None => {
                let known: Vec<&str> = merged.keys().map(String::as_str).collect();
                eprintln!(
                    "error: no table [{name}]; the tables are: {}",
                    known.join(", ")
                );
                return ExitCode::from(crate::EXIT_CONFIG);
            }
        },
    };
    match toml::to_string_pretty(&shown) {
        Ok(text) => {
            print!("{text}");
            ExitCode::SUCCESS
        }
        Err(error) => {
            eprintln!("error: cannot print the defaults: {error}");
            ExitCode::FAILURE
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The dotted keys under `table` whose value `defaults` already has.
    fn repeated(prefix: &str, table: &toml::Table, defaults: &toml::Table, out: &mut Vec<String>) {
        for (key, value) in table {
            let path = format!("{prefix}.{key}");
            match (value, defaults.get(key)) {
                (toml::Value::Table(inner), Some(toml::Value::Table(default_inner))) => {
                    repeated(&path, inner, default_inner, out);
                }
                (value, Some(default)) if value == default => out.push(path),
                (toml::Value::Float(a), Some(toml::Value::Float(b))) if (a - b).abs() < 1e-12 => {
                    out.push(path)
                }
                _ => {}
            }
        }
    }

    #[test]
    fn the_embedded_file_repeats_no_library_default() {
        let libraries = library_defaults().expect("every library's defaults serialize");
        let embedded: toml::Table = hopnav_config::DEFAULT_TOML.parse().expect("embedded");
        let mut repeats = Vec::new();
        for (name, defaults) in &libraries {
            if let (Some(toml::Value::Table(table)), toml::Value::Table(defaults)) =
                (embedded.get(name), defaults)
            {
                repeated(name, table, defaults, &mut repeats);
            }
        }
        assert!(
            repeats.is_empty(),
            "config/default.toml repeats these library defaults (keep each default once, in \
             the library's Default): {repeats:#?}"
        );
    }

    #[test]
    fn the_merged_defaults_are_a_valid_launch_config() {
        let merged = effective_defaults().expect("defaults");
        let text = toml::to_string(&merged).expect("printable");
        let config = hopnav_config::load(Some(&text)).expect("loads");
        crate::registry::check_sections(&config).expect("every library accepts its defaults");
        // Every library table is there, with the runtime's own tables beside them.
        for name in ["world", "physics", "mapper", "planner", "run", "processes"] {
            assert!(merged.contains_key(name), "{name} missing");
        }
    }
}
