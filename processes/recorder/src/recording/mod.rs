//! The MCAP recording (`hopnav launch --record FILE.mcap`): every tapped topic as its own
//! channel, each message in hopnav's wire encoding ([`hopnav_ipc::wire`]: the bytes as they
//! lie in shared memory, so a replay is lossless), lz4-compressed chunks, and the launch's
//! config and the build's commit as metadata. Beside them, unless the config turns them off,
//! the same data in Foxglove's well-known messages ([`foxglove_view`]), so the file opens in
//! Foxglove with its images, clouds, frames, map and path.
//!
//! A write error (a full disk) stops the recording, not the recorder: it is named on stderr
//! and in the summary, and the mission goes on.

mod content;
mod foxglove_channels;
pub mod foxglove_view;
pub mod inspect;
mod summary;
#[cfg(test)]
mod test_channels;
mod writer;

pub use content::RecordingContent;
pub use foxglove_channels::FoxgloveTopic;
pub use summary::{ChannelSummary, RecordingSummary};
pub use writer::{ChannelSpec, McapRecording, check_writable};

/// The commit the binary was built from, `unknown` without git at build time.
pub const BUILD_COMMIT: &str = match option_env!("HOPNAV_GIT_COMMIT") {
    Some(commit) => commit,
    None => "unknown",
};
