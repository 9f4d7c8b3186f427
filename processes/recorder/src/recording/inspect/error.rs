//! Why a file is not a recording this build can read.

/// Why [`super::inspect`] refused a file: each variant names what is wrong with it.
#[derive(Debug, thiserror::Error)]
pub enum InspectError {
    /// The file cannot be read.
    #[error("cannot read {path}: {source}")]
    Read {
        /// The file.
        path: String,
        /// OS error.
        source: std::io::Error,
    },
    /// The file does not start with MCAP's magic bytes.
    #[error("not an MCAP file: it does not start with the MCAP magic bytes")]
    NotMcap,
    /// The file starts as MCAP but stops before its footer.
    #[error(
        "truncated: the file ends after {size_bytes} bytes without the MCAP footer (a recording \
         whose recorder was killed, or an incomplete copy)"
    )]
    Truncated {
        /// The file's size.
        size_bytes: u64,
    },
    /// A record, chunk or index of the file is damaged.
    #[error("corrupt: {reason}")]
    Corrupt {
        /// What the reader found.
        reason: String,
    },
    /// A valid MCAP file that hopnav did not write.
    #[error("an MCAP file, but not a hopnav recording (profile {profile:?}, expected \"hopnav\")")]
    NotHopnav {
        /// The profile its header names.
        profile: String,
    },
    /// A hopnav channel whose messages have another layout than this build's.
    #[error(
        "channel {topic}: schema {schema} holds {type_name} layout v{recorded_version}, this \
         build reads v{current_version}: recorded by another version of hopnav (inspect it \
         with the build of its commit)"
    )]
    OtherVersion {
        /// The channel's topic.
        topic: String,
        /// The channel's schema name.
        schema: String,
        /// The message type whose layout differs.
        type_name: String,
        /// Its layout version in the file.
        recorded_version: u32,
        /// Its layout version in this build.
        current_version: u32,
    },
    /// A hopnav channel whose schema names no message type this build knows.
    #[error("channel {topic}: schema {schema:?} names no hopnav message type this build knows")]
    UnknownSchema {
        /// The channel's topic.
        topic: String,
        /// The channel's schema name (empty without a schema).
        schema: String,
    },
}

/// A reader's error as [`InspectError::Corrupt`], with its causes.
pub(super) fn corrupt(error: &mcap::McapError) -> InspectError {
    InspectError::Corrupt {
        reason: crate::error_chain::error_chain(error),
    }
}
