//! What a recording holds, handed from the recorder to the launch's summary through
//! `recording.json` in the run folder.

use std::io::Write;
use std::path::Path;

use serde::{Deserialize, Serialize};

/// File name of the summary in the run folder (beside `config.toml`).
pub const SUMMARY_FILE: &str = "recording.json";

/// What one channel holds and what it lost.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct ChannelSummary {
    /// Topic name.
    pub topic: String,
    /// Schema name.
    pub schema: String,
    /// Messages written.
    pub messages: u64,
    /// Samples the recorder never saw (gaps in the publisher's sequence).
    pub missed: u64,
    /// Samples that failed validation or repeated a sequence.
    pub rejected: u64,
}

/// What a recording holds.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct RecordingSummary {
    /// The MCAP file.
    pub path: String,
    /// Its size, bytes.
    pub file_size_bytes: u64,
    /// Per channel.
    pub channels: Vec<ChannelSummary>,
    /// Why the recording stopped early, if it did.
    pub error: Option<String>,
}

impl RecordingSummary {
    /// Messages written, all channels.
    pub fn messages(&self) -> u64 {
        self.channels.iter().map(|channel| channel.messages).sum()
    }

    /// Samples missed or rejected, all channels.
    pub fn drops(&self) -> u64 {
        self.channels
            .iter()
            .map(|channel| channel.missed + channel.rejected)
            .sum()
    }

    /// Writes the summary into `run_dir`.
    pub fn write_into(&self, run_dir: &Path) -> std::io::Result<()> {
        let text = serde_json::to_string_pretty(self).map_err(std::io::Error::other)?;
        std::fs::write(run_dir.join(SUMMARY_FILE), text)
    }

    /// The summary a recorder left in `run_dir`, if any.
    pub fn read_from(run_dir: &Path) -> Option<Self> {
        let text = std::fs::read_to_string(run_dir.join(SUMMARY_FILE)).ok()?;
        serde_json::from_str(&text).ok()
    }

    /// One line for the launch's summary: size, messages per channel, drops, and the error.
    pub fn print_line(&self, out: &mut impl Write) -> std::io::Result<()> {
        let per_channel: Vec<String> = self
            .channels
            .iter()
            .filter(|channel| channel.messages + channel.missed + channel.rejected > 0)
            .map(|channel| {
                let name = channel
                    .topic
                    .strip_prefix("hopnav/")
                    .unwrap_or(&channel.topic);
                format!("{name} {}", channel.messages)
            })
            .collect();
        let missed: u64 = self.channels.iter().map(|channel| channel.missed).sum();
        write!(
            out,
            "record: {} {:.1} MB, {} messages, drops {} (missed {missed}, rejected {}); {}",
            self.path,
            self.file_size_bytes as f64 / 1e6,
            self.messages(),
            self.drops(),
            self.drops() - missed,
            per_channel.join(", ")
        )?;
        match &self.error {
            Some(error) => writeln!(out, "; FAILED: {error}"),
            None => writeln!(out),
        }
    }
}
