//! Writes samples into an MCAP file and counts what it wrote and what it missed.

use std::collections::BTreeMap;
use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Seek, Write};
use std::path::{Path, PathBuf};

use hopnav_ipc::messages::SampleStamp;
use hopnav_ipc::validate::{Message, SliceHeader};
use hopnav_ipc::wire::{self, WireBytes};

use super::content::RecordingContent;
use super::foxglove_channels::FoxgloveTopic;
use super::summary::{ChannelSummary, RecordingSummary};
use crate::error_chain::error_chain;
use crate::{RecorderError, RecordingError};

/// One channel to create: its topic and the schema of its messages.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ChannelSpec {
    /// Topic name, e.g. `hopnav/camera/jumper`.
    pub topic: String,
    /// Schema name with type and layout version, e.g. `hopnav.ImageHeader.v1+u8[]`.
    pub schema_name: String,
    /// Human-readable layout, the schema's data.
    pub schema_text: String,
}

/// What one channel received.
#[derive(Debug)]
struct ChannelCount {
    spec: ChannelSpec,
    mcap_id: u16,
    messages: u64,
    /// Samples skipped in the publisher's sequence: overwritten before the recorder read
    /// them, or dropped upstream.
    missed: u64,
    last_sequence: Option<u64>,
}

impl ChannelCount {
    fn note_sequence(&mut self, sequence: u64) {
        // A lower sequence is a restarted publisher counting afresh: no gap to count.
        if let Some(last) = self.last_sequence
            && sequence > last
        {
            self.missed += sequence - last - 1;
        }
        self.last_sequence = Some(sequence);
    }
}

/// An MCAP file being written (into `W`: a buffered file, or a test's sink).
pub struct McapRecording<W: Write + Seek = BufWriter<File>> {
    path: PathBuf,
    writer: Option<mcap::Writer<W>>,
    channels: Vec<ChannelCount>,
    /// The Foxglove channels' MCAP ids and message counts, indexed like
    /// [`FoxgloveTopic::ALL`]; `None` for a channel the recording leaves out.
    foxglove: Vec<Option<(u16, u64)>>,
    /// Why the recording stopped early.
    failure: Option<String>,
    /// One message's bytes, reused.
    buffer: Vec<u8>,
}

/// The writer's error and its causes (an I/O error says what the OS refused).
fn describe(error: &mcap::McapError) -> String {
    error_chain(error)
}

/// Turns an OS error on the recording `path` into [`RecordingError::Unwritable`].
fn unwritable(path: &Path) -> impl Fn(std::io::Error) -> RecorderError + '_ {
    move |source| {
        RecorderError::Own(RecordingError::Unwritable {
            path: path.display().to_string(),
            source,
        })
    }
}

/// Checks that `path` can be written as a recording, creating nothing that was not there.
pub fn check_writable(path: &Path) -> Result<(), RecorderError> {
    let refused = unwritable(path);
    if path.is_dir() {
        return Err(refused(std::io::Error::new(
            std::io::ErrorKind::IsADirectory,
            "is a folder, not a file",
        )));
    }
    let existed = path.exists();
    OpenOptions::new()
        .write(true)
        .create(true)
        .truncate(false)
        .open(path)
        .map_err(&refused)?;
    if !existed {
        std::fs::remove_file(path).map_err(&refused)?;
    }
    Ok(())
}

impl McapRecording {
    /// Creates `path` with one channel per spec (indexed as given), the Foxglove channels
    /// `content` asks for, and the metadata records.
    pub fn create(
        path: &Path,
        channels: &[ChannelSpec],
        content: RecordingContent,
        metadata: &[(&str, BTreeMap<String, String>)],
    ) -> Result<Self, RecorderError> {
        let file = File::create(path).map_err(unwritable(path))?;
        Self::into_sink(path, BufWriter::new(file), channels, content, metadata)
    }
}

impl<W: Write + Seek> McapRecording<W> {
    /// Starts a recording named `path` in `sink`.
    pub fn into_sink(
        path: &Path,
        sink: W,
        channels: &[ChannelSpec],
        content: RecordingContent,
        metadata: &[(&str, BTreeMap<String, String>)],
    ) -> Result<Self, RecorderError> {
        let mcap_error = |error: mcap::McapError| {
            RecorderError::Own(RecordingError::Mcap {
                path: path.display().to_string(),
                reason: describe(&error),
            })
        };
        let mut writer = mcap::WriteOptions::new()
            .compression(Some(mcap::Compression::Lz4))
            .profile("hopnav")
            .create(sink)
            .map_err(mcap_error)?;
        let mut counts = Vec::with_capacity(channels.len());
        for spec in channels {
            let schema_id = writer
                .add_schema(
                    &spec.schema_name,
                    wire::SCHEMA_ENCODING,
                    spec.schema_text.as_bytes(),
                )
                .map_err(mcap_error)?;
            let mcap_id = writer
                .add_channel(
                    schema_id,
                    &spec.topic,
                    wire::MESSAGE_ENCODING,
                    &BTreeMap::new(),
                )
                .map_err(mcap_error)?;
            counts.push(ChannelCount {
                spec: spec.clone(),
                mcap_id,
                messages: 0,
                missed: 0,
                last_sequence: None,
            });
        }
        let mut foxglove_ids = vec![None; FoxgloveTopic::ALL.len()];
        for topic in content.foxglove_topics() {
            let schema_id = match topic.schema() {
                Some(schema) => writer
                    .add_schema(&schema.name, &schema.encoding, &schema.data)
                    .map_err(mcap_error)?,
                None => 0,
            };
            let mcap_id = writer
                .add_channel(
                    schema_id,
                    topic.topic(),
                    &topic.message_encoding(),
                    &BTreeMap::new(),
                )
                .map_err(mcap_error)?;
            foxglove_ids[topic.index()] = Some((mcap_id, 0));
        }
        for (name, entries) in metadata {
            writer
                .write_metadata(&mcap::records::Metadata {
                    name: (*name).to_owned(),
                    metadata: entries.clone(),
                })
                .map_err(mcap_error)?;
        }
        Ok(Self {
            path: path.to_owned(),
            writer: Some(writer),
            channels: counts,
            foxglove: foxglove_ids,
            failure: None,
            buffer: Vec::new(),
        })
    }

    /// Records a fixed-size message on channel `channel`.
    pub fn record_message<M: Message + WireBytes>(&mut self, channel: usize, message: &M) {
        self.buffer.clear();
        self.buffer.extend_from_slice(wire::bytes_of(message));
        self.write(channel, *message.stamp());
    }

    /// Records a slice sample (header, then elements) on channel `channel`.
    pub fn record_slice<H: SliceHeader + WireBytes>(
        &mut self,
        channel: usize,
        header: &H,
        elements: &[H::Element],
    ) where
        H::Element: WireBytes,
    {
        self.buffer.clear();
        self.buffer.extend_from_slice(wire::bytes_of(header));
        self.buffer.extend_from_slice(wire::slice_bytes(elements));
        self.write(channel, *header.stamp());
    }

    /// Whether the recording has the Foxglove channel `topic` (and still writes): converting
    /// a sample for it is worth it.
    pub fn wants_foxglove(&self, topic: FoxgloveTopic) -> bool {
        matches!(self.foxglove.get(topic.index()), Some(Some(_))) && self.writer.is_some()
    }

    /// Records `message` on the Foxglove channel `topic` at the sample's sim time (nothing
    /// when the recording leaves that channel out).
    pub fn record_foxglove(
        &mut self,
        topic: FoxgloveTopic,
        stamp: SampleStamp,
        message: &impl foxglove::Encode,
    ) {
        let mut encoded = std::mem::take(&mut self.buffer);
        encoded.clear();
        // A protobuf message encodes into a growable buffer; nothing is lost if not.
        if message.encode(&mut encoded).is_ok() {
            self.record_foxglove_encoded(topic, stamp, &encoded);
        }
        self.buffer = encoded;
    }

    /// Records an encoded message on the Foxglove channel `topic` at the sample's sim time
    /// (nothing when the recording leaves that channel out).
    pub fn record_foxglove_encoded(
        &mut self,
        topic: FoxgloveTopic,
        stamp: SampleStamp,
        encoded: &[u8],
    ) {
        let index = topic.index();
        let Some(&Some((mcap_id, _))) = self.foxglove.get(index) else {
            return;
        };
        if self.write_bytes(mcap_id, stamp, encoded)
            && let Some(Some((_, messages))) = self.foxglove.get_mut(index)
        {
            *messages += 1;
        }
    }

    /// Writes `data` on MCAP channel `mcap_id`; false (and the recording stopped) on a write
    /// error.
    fn write_bytes(&mut self, mcap_id: u16, stamp: SampleStamp, data: &[u8]) -> bool {
        let Some(writer) = &mut self.writer else {
            return false;
        };
        let header = mcap::records::MessageHeader {
            channel_id: mcap_id,
            sequence: u32::try_from(stamp.frame_index).unwrap_or(u32::MAX),
            log_time: stamp.sim_time_ns,
            publish_time: stamp.sim_time_ns,
        };
        match writer.write_to_known_channel(&header, data) {
            Ok(()) => true,
            Err(error) => {
                self.fail(&error);
                false
            }
        }
    }

    /// Writes `self.buffer` stamped with the sample's sim time and frame.
    fn write(&mut self, channel: usize, stamp: SampleStamp) {
        let Some(count) = self.channels.get_mut(channel) else {
            return;
        };
        count.note_sequence(stamp.sequence);
        let mcap_id = count.mcap_id;
        let bytes = std::mem::take(&mut self.buffer);
        if self.write_bytes(mcap_id, stamp, &bytes) {
            self.channels[channel].messages += 1;
        }
        self.buffer = bytes;
    }

    /// Stops recording after a write error; the file keeps what was written before it.
    fn fail(&mut self, error: &mcap::McapError) {
        let reason = format!(
            "recording {} stopped: {}",
            self.path.display(),
            describe(error)
        );
        eprintln!("[recorder] {reason}");
        self.failure = Some(reason);
        // Dropping the writer tries to finish the file; after a write error that may fail too.
        self.writer = None;
    }

    /// Whether the recording still writes.
    pub fn is_writing(&self) -> bool {
        self.writer.is_some()
    }

    /// Finishes the file (summary section, footer) and returns what was recorded;
    /// `rejected` is the subscribers' rejection counts per channel.
    pub fn finish(&mut self, rejected: &[u64]) -> RecordingSummary {
        if let Some(mut writer) = self.writer.take()
            && let Err(error) = writer.finish()
        {
            let reason = format!(
                "recording {} could not be finished: {}",
                self.path.display(),
                describe(&error)
            );
            eprintln!("[recorder] {reason}");
            self.failure = Some(reason);
        }
        let file_size_bytes = std::fs::metadata(&self.path).map_or(0, |meta| meta.len());
        RecordingSummary {
            path: self.path.display().to_string(),
            file_size_bytes,
            channels: self
                .channels
                .iter()
                .enumerate()
                .map(|(index, count)| ChannelSummary {
                    topic: count.spec.topic.clone(),
                    schema: count.spec.schema_name.clone(),
                    messages: count.messages,
                    missed: count.missed,
                    rejected: rejected.get(index).copied().unwrap_or(0),
                })
                .chain(self.foxglove.iter().zip(FoxgloveTopic::ALL).filter_map(
                    |(&created, topic)| {
                        let (_, messages) = created?;
                        Some(ChannelSummary {
                            topic: topic.topic().to_owned(),
                            schema: topic
                                .schema()
                                .map_or_else(String::new, |schema| schema.name),
                            messages,
                            missed: 0,
                            rejected: 0,
                        })
                    },
                ))
                .collect(),
            error: self.failure.clone(),
        }
    }
}

#[cfg(test)]
mod tests;
