//! Why a launch could not start or had to stop.

use std::path::PathBuf;

/// A launch that failed before its frame loop could run, or a setup problem.
#[derive(Debug, thiserror::Error)]
pub enum LaunchError {
    /// A fault to inject cannot be executed in this launch.
    #[error("config key faults.inject: {0}")]
    Fault(String),
    /// The config names a process this binary cannot run.
    #[error("config key processes.{name}: unknown process (known: {known})")]
    UnknownProcess {
        /// The name in the config.
        name: String,
        /// Comma-separated known names.
        known: String,
    },
    /// The run folder could not be written.
    #[error("cannot write run folder {path}: {source}")]
    RunDir {
        /// Folder.
        path: PathBuf,
        /// OS error.
        source: std::io::Error,
    },
    /// The configuration could not be written for the children.
    #[error(transparent)]
    Config(#[from] hopnav_config::ConfigError),
    /// The iceoryx2 namespace could not be set up.
    #[error(transparent)]
    Namespace(#[from] hopnav_ipc::namespace::NamespaceError),
    /// A supervisor port could not be opened.
    #[error(transparent)]
    Open(#[from] hopnav_ipc::transport::OpenError),
    /// A child could not be started.
    #[error("cannot start process {name}: {source}")]
    Spawn {
        /// Process name.
        name: String,
        /// OS error.
        source: std::io::Error,
    },
    /// Some processes did not report ready in time.
    #[error("processes not ready after {timeout_s} s (run.startup_timeout_s): {names}")]
    StartupTimeout {
        /// Comma-separated names.
        names: String,
        /// The timeout.
        timeout_s: f64,
    },
    /// A process died before it reported ready.
    #[error("process {name} {reason} before reporting ready")]
    DiedAtStartup {
        /// Process name.
        name: String,
        /// How it ended.
        reason: String,
    },
    /// Waiting for events failed.
    #[error("supervisor wait failed: {0}")]
    Wait(String),
    /// SIGINT or SIGTERM arrived before the frame loop ran (before or during start-up).
    #[error("interrupted (SIGINT or SIGTERM) before the launch ran")]
    Interrupted,
}
