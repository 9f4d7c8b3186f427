//! Reads a recording back without IPC: checks that it is a complete hopnav recording this
//! build reads and summarises it (`hopnav recording info`). Any bytes give an info or an
//! [`InspectError`] that names the problem, never a panic (fuzzed: `fuzz/fuzz_targets/
//! recording_inspect.rs`).
//!
//! ```no_run
//! use hopnav_recorder::recording::inspect::{Depth, inspect_file};
//!
//! let info = inspect_file("mission.mcap".as_ref(), Depth::EveryMessage)?;
//! println!("{} messages over {:.1} s", info.messages, info.duration_s());
//! # Ok::<(), hopnav_recorder::recording::inspect::InspectError>(())
//! ```

mod bounds;
mod error;
mod info;
mod schema_version;
mod structure;

use std::collections::BTreeMap;
use std::path::Path;

use hopnav_ipc::wire;
use mcap::records::{Record, Statistics};
use mcap::sans_io::{LinearReadEvent, LinearReader, LinearReaderOptions};

pub use error::InspectError;
use error::corrupt;
pub use info::{ChannelInfo, RecordingInfo};

/// How much of the file to read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Depth {
    /// The summary section only: fast, but a damaged chunk goes unnoticed.
    Summary,
    /// Every message: each chunk's CRC is checked and the counts come from the data.
    EveryMessage,
}

/// The profile hopnav's writer puts into the MCAP header.
pub const PROFILE: &str = "hopnav";

/// The footer record's size: opcode, length, summary start, summary offset start, CRC.
const FOOTER_BYTES: usize = 1 + 8 + 8 + 8 + 4;

/// The largest decompressed chunk accepted below the file's own size: hopnav's chunks hold
/// at most a few MB (a map snapshot is 1.6 MB), and a corrupt size must not allocate GiBs.
const MIN_RECORD_LIMIT_BYTES: usize = 64 << 20;

/// Reads the file at `path` (whole, into memory) and inspects it.
pub fn inspect_file(path: &Path, depth: Depth) -> Result<RecordingInfo, InspectError> {
    let bytes = std::fs::read(path).map_err(|source| InspectError::Read {
        path: path.display().to_string(),
        source,
    })?;
    inspect(&bytes, depth)
}

/// Checks that `bytes` are a complete hopnav recording whose hopnav channels this build reads,
/// and summarises them.
pub fn inspect(bytes: &[u8], depth: Depth) -> Result<RecordingInfo, InspectError> {
    if !bytes.starts_with(mcap::MAGIC) {
        return Err(InspectError::NotMcap);
    }
    if bytes.len() < 2 * mcap::MAGIC.len() + FOOTER_BYTES || !bytes.ends_with(mcap::MAGIC) {
        return Err(InspectError::Truncated {
            size_bytes: bytes.len() as u64,
        });
    }
    let profile = match parse_record_at(bytes, mcap::MAGIC.len())? {
        Record::Header(header) => header.profile,
        _ => {
            return Err(InspectError::Corrupt {
                reason: "the first record is not the MCAP header".to_owned(),
            });
        }
    };
    if profile != PROFILE {
        return Err(InspectError::NotHopnav { profile });
    }
    let records_end = bytes.len() - mcap::MAGIC.len();
    let mut contents = Contents::default();
    match depth {
        Depth::EveryMessage => {
            structure::check(&bytes[mcap::MAGIC.len()..records_end])?;
            scan(bytes, false, &mut contents)?;
        }
        Depth::Summary => {
            let summary_start = summary_start(bytes)?;
            structure::check(&bytes[summary_start..records_end])?;
            scan(&bytes[summary_start..], true, &mut contents)?;
            for (offset, length) in std::mem::take(&mut contents.metadata_at) {
                let record = usize::try_from(offset)
                    .ok()
                    .filter(|_| length >= 9)
                    .map(|offset| parse_record_at(bytes, offset))
                    .transpose()?;
                let Some(Record::Metadata(metadata)) = record else {
                    return Err(InspectError::Corrupt {
                        reason: format!("the metadata index points at no metadata ({offset})"),
                    });
                };
                contents.metadata.insert(metadata.name, metadata.metadata);
            }
        }
    }
    contents.into_info(bytes.len() as u64, depth)
}

/// Where the summary section starts, from the footer.
fn summary_start(bytes: &[u8]) -> Result<usize, InspectError> {
    let footer_at = bytes.len() - mcap::MAGIC.len() - FOOTER_BYTES;
    let start = match parse_record_at(bytes, footer_at)? {
        Record::Footer(footer) => footer.summary_start,
        _ => {
            return Err(InspectError::Corrupt {
                reason: "no footer record before the closing magic".to_owned(),
            });
        }
    };
    usize::try_from(start)
        .ok()
        .filter(|&start| start >= mcap::MAGIC.len() && start <= footer_at)
        .ok_or_else(|| InspectError::Corrupt {
            reason: format!("no summary section (the footer says it starts at {start})"),
        })
}

/// The record starting at `offset` (opcode, u64 length, body), its lengths checked.
fn parse_record_at(bytes: &[u8], offset: usize) -> Result<Record<'_>, InspectError> {
    let truncated = || InspectError::Corrupt {
        reason: format!("a record at byte {offset} runs past the end of the file"),
    };
    let (&opcode, rest) = bytes
        .get(offset..)
        .and_then(<[u8]>::split_first)
        .ok_or_else(truncated)?;
    let (length, rest) = rest.split_first_chunk::<8>().ok_or_else(truncated)?;
    let body = usize::try_from(u64::from_le_bytes(*length))
        .ok()
        .and_then(|length| rest.get(..length))
        .ok_or_else(truncated)?;
    bounds::check(opcode, body)?;
    mcap::parse_record(opcode, body).map_err(|error| corrupt(&error))
}

/// What the records of a file (or of its summary section) say.
#[derive(Default)]
struct Contents {
    /// Schema id: name and encoding.
    schemas: BTreeMap<u16, (String, String)>,
    /// Channel id: topic, schema id, message encoding.
    channels: BTreeMap<u16, (String, u16, String)>,
    /// Messages read per channel id.
    messages: BTreeMap<u16, u64>,
    /// Log time of the first and last message read.
    span_ns: Option<(u64, u64)>,
    statistics: Option<Statistics>,
    metadata: BTreeMap<String, BTreeMap<String, String>>,
    /// Where the metadata records lie (offset, length), from the summary's index.
    metadata_at: Vec<(u64, u64)>,
}

impl Contents {
    fn add(&mut self, record: Record<'_>) {
        match record {
            Record::Schema { header, .. } => {
                self.schemas
                    .insert(header.id, (header.name, header.encoding));
            }
            Record::Channel(channel) => {
                self.channels.insert(
                    channel.id,
                    (channel.topic, channel.schema_id, channel.message_encoding),
                );
            }
            Record::Message { header, .. } => {
                *self.messages.entry(header.channel_id).or_insert(0) += 1;
                let time = header.log_time;
                let (first, last) = self.span_ns.get_or_insert((time, time));
                (*first, *last) = ((*first).min(time), (*last).max(time));
            }
            Record::Statistics(statistics) => self.statistics = Some(statistics),
            Record::Metadata(metadata) => {
                self.metadata.insert(metadata.name, metadata.metadata);
            }
            Record::MetadataIndex(index) => self.metadata_at.push((index.offset, index.length)),
            _ => {}
        }
    }

    fn into_info(self, size_bytes: u64, depth: Depth) -> Result<RecordingInfo, InspectError> {
        let statistics = self.statistics.ok_or_else(|| InspectError::Corrupt {
            reason: "no statistics record in the summary".to_owned(),
        })?;
        let mut summarised = statistics.channel_message_counts.clone();
        summarised.retain(|_, messages| *messages > 0);
        let (counts, span_ns) = match depth {
            Depth::EveryMessage => {
                if self.messages != summarised {
                    return Err(InspectError::Corrupt {
                        reason: format!(
                            "the summary counts messages per channel id {summarised:?}, the \
                             data holds {:?}",
                            self.messages
                        ),
                    });
                }
                (self.messages, self.span_ns)
            }
            Depth::Summary => (
                summarised,
                (statistics.message_count > 0)
                    .then_some((statistics.message_start_time, statistics.message_end_time)),
            ),
        };
        let mut channels = Vec::with_capacity(self.channels.len());
        for (id, (topic, schema_id, message_encoding)) in self.channels {
            let (schema, schema_encoding) =
                self.schemas.get(&schema_id).cloned().unwrap_or_default();
            if message_encoding == wire::MESSAGE_ENCODING {
                schema_version::check(&topic, &schema)?;
            }
            channels.push(ChannelInfo {
                topic,
                schema,
                schema_encoding,
                message_encoding,
                messages: counts.get(&id).copied().unwrap_or(0),
            });
        }
        channels.sort_by(|a, b| a.topic.cmp(&b.topic));
        Ok(RecordingInfo {
            size_bytes,
            every_message_read: depth == Depth::EveryMessage,
            // A corrupt summary may count anything: saturate rather than overflow.
            messages: counts.values().fold(0, |sum, &n| sum.saturating_add(n)),
            chunks: statistics.chunk_count,
            span_ns,
            channels,
            metadata: self.metadata,
        })
    }
}

/// Reads every record of `bytes` (a whole file, or its summary section when `summary_only`),
/// decompressing chunks and checking their CRCs, into `contents`.
fn scan(bytes: &[u8], summary_only: bool, contents: &mut Contents) -> Result<(), InspectError> {
    let options = LinearReaderOptions::default()
        .with_skip_start_magic(summary_only)
        .with_prevalidate_chunk_crcs(true)
        .with_validate_data_section_crc(!summary_only)
        .with_validate_summary_section_crc(!summary_only)
        .with_record_length_limit(bytes.len().max(MIN_RECORD_LIMIT_BYTES));
    let mut reader = LinearReader::new_with_options(options);
    let mut unread = bytes;
    while let Some(event) = reader.next_event() {
        match event.map_err(|error| corrupt(&error))? {
            LinearReadEvent::ReadRequest(wanted) => {
                let length = wanted.min(unread.len());
                reader.insert(length).copy_from_slice(&unread[..length]);
                reader.notify_read(length);
                unread = &unread[length..];
            }
            LinearReadEvent::Record { opcode, data } => {
                bounds::check(opcode, data)?;
                contents.add(mcap::parse_record(opcode, data).map_err(|error| corrupt(&error))?);
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests;
