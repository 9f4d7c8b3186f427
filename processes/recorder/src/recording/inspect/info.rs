//! What a recording holds, as [`super::inspect`] found it.

use std::collections::BTreeMap;

use serde::Serialize;

/// One channel of a recording.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct ChannelInfo {
    /// Topic, e.g. `hopnav/rover_vo/pose` or `/foxglove/tf`.
    pub topic: String,
    /// Schema name, e.g. `hopnav.PoseEstimate.v2` (empty for a channel without a schema).
    pub schema: String,
    /// The schema's encoding, e.g. `hopnav/layout` or `protobuf`.
    pub schema_encoding: String,
    /// The messages' encoding, e.g. `hopnav/repr-c` or `protobuf`.
    pub message_encoding: String,
    /// Messages on the channel.
    pub messages: u64,
}

/// A hopnav recording's contents.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct RecordingInfo {
    /// The file's size.
    pub size_bytes: u64,
    /// Whether every message was read (each chunk's CRC checked, counts from the data) or
    /// only the summary section.
    pub every_message_read: bool,
    /// Messages in the file.
    pub messages: u64,
    /// Compressed chunks in the file.
    pub chunks: u32,
    /// Log time of the first and last message (sim time), none in a recording without any.
    pub span_ns: Option<(u64, u64)>,
    /// Channels, sorted by topic.
    pub channels: Vec<ChannelInfo>,
    /// Metadata records by name (`hopnav.launch`: run id and config; `hopnav.build`: commit
    /// and version).
    pub metadata: BTreeMap<String, BTreeMap<String, String>>,
}

impl RecordingInfo {
    /// A metadata entry, e.g. `("hopnav.build", "commit")`.
    pub fn metadata_entry(&self, record: &str, key: &str) -> Option<&str> {
        self.metadata.get(record)?.get(key).map(String::as_str)
    }

    /// Seconds between the first and the last message.
    pub fn duration_s(&self) -> f64 {
        self.span_ns
            .map_or(0.0, |(start, end)| end.saturating_sub(start) as f64 * 1e-9)
    }
}
