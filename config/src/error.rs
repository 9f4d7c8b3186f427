//! What can go wrong with a configuration; every variant says where.

/// A configuration that cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum ConfigError {
    /// The file could not be read.
    #[error("cannot read config file {path}: {message}")]
    Io {
        /// Path given.
        path: String,
        /// OS reason.
        message: String,
    },
    /// The text is not valid TOML.
    #[error("{origin} is not valid TOML: {message}")]
    Syntax {
        /// Which text.
        origin: &'static str,
        /// Parser message with line and column.
        message: String,
    },
    /// A key is unknown or its value has the wrong type.
    #[error("config key {key}: {message}")]
    Schema {
        /// Dotted path of the key.
        key: String,
        /// What is wrong.
        message: String,
    },
    /// A value is outside its allowed range.
    #[error("config key {key} = {value} is out of range: allowed {allowed}")]
    OutOfRange {
        /// Dotted path of the key.
        key: String,
        /// The value found.
        value: String,
        /// The allowed range or set.
        allowed: String,
    },
    /// The configuration could not be written back as TOML.
    #[error("cannot serialize config: {0}")]
    Serialize(String),
}

/// A failed range check of a process's own table, as the launcher reports any config error.
impl From<crate::range::OutOfRange> for ConfigError {
    fn from(rejected: crate::range::OutOfRange) -> Self {
        Self::OutOfRange {
            key: rejected.key,
            value: rejected.value,
            allowed: rejected.range,
        }
    }
}
