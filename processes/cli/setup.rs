//! What the commands do before they run: load and check the configuration, find the hopnav
//! executable the children are started from. Each prints its error and gives the exit code.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use hopnav_config::HopnavConfig;

use crate::registry;

/// The configuration in `path` (or the defaults), validated; prints the error and gives
/// [`EXIT_CONFIG`](crate::EXIT_CONFIG) when it is unusable.
pub fn load_config(path: Option<&Path>) -> Result<HopnavConfig, ExitCode> {
    let loaded = match path {
        Some(path) => hopnav_config::load_file(path),
        None => hopnav_config::load(None),
    };
    loaded.map_err(|error| {
        eprintln!("error: {error}");
        ExitCode::from(crate::EXIT_CONFIG)
    })
}

/// [`load_config`], then every process section checked (unknown tables are errors).
pub fn load_checked_config(path: Option<&Path>) -> Result<HopnavConfig, ExitCode> {
    let config = load_config(path)?;
    if let Err(error) = registry::check_sections(&config) {
        eprintln!("error: {error}");
        return Err(ExitCode::from(crate::EXIT_CONFIG));
    }
    Ok(config)
}

/// The running hopnav executable; `why` ends the error message's first part, e.g.
/// `" to start children"`.
pub fn own_executable(why: &str) -> Result<PathBuf, ExitCode> {
    std::env::current_exe().map_err(|error| {
        eprintln!("error: cannot find the hopnav executable{why}: {error}");
        ExitCode::FAILURE
    })
}

/// Ends a command that produced `result`: `print` shows the report (exit code success), or
/// the error is printed (failure).
pub fn report_outcome<T, E: std::fmt::Display>(
    result: Result<T, E>,
    print: impl FnOnce(T),
) -> ExitCode {
    match result {
        Ok(report) => {
            print(report);
            ExitCode::SUCCESS
        }
        Err(error) => {
            eprintln!("error: {error}");
            ExitCode::FAILURE
        }
    }
}
