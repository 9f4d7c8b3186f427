//! Where a sample's Foxglove messages go: the recording's Foxglove channels, the live
//! viewer's, or both. Each message is converted and encoded once, and only if someone takes
//! it.

use foxglove::Encode;
use hopnav_ipc::messages::SampleStamp;

use crate::recording::{FoxgloveTopic, McapRecording};
use crate::viewer::Viewer;

/// The recording and the viewer, either of which may be absent.
pub struct Outputs {
    /// The MCAP file (`--record`).
    pub recording: Option<McapRecording>,
    /// The live view (`--viewer`).
    pub viewer: Option<Viewer>,
    /// One encoded message, reused.
    encoded: Vec<u8>,
}

impl Outputs {
    /// Writes into `recording` and/or serves on `viewer`.
    pub fn new(recording: Option<McapRecording>, viewer: Option<Viewer>) -> Self {
        Self {
            recording,
            viewer,
            encoded: Vec::new(),
        }
    }

    /// Whether the recording writes `topic` or a viewer client subscribes to it.
    pub fn wants(&self, topic: FoxgloveTopic) -> bool {
        self.recording
            .as_ref()
            .is_some_and(|recording| recording.wants_foxglove(topic))
            || self
                .viewer
                .as_ref()
                .is_some_and(|viewer| viewer.wants(topic))
    }

    /// Converts a sample with `convert` (none: nothing to show) and sends it on `topic`, if
    /// anyone takes that topic.
    pub fn send<M: Encode>(
        &mut self,
        topic: FoxgloveTopic,
        stamp: SampleStamp,
        convert: impl FnOnce() -> Option<M>,
    ) {
        if !self.wants(topic) {
            return;
        }
        let Some(message) = convert() else {
            return;
        };
        self.encoded.clear();
        if message.encode(&mut self.encoded).is_err() {
            // A protobuf message encodes into a growable buffer; nothing is lost if not.
            return;
        }
        if let Some(recording) = &mut self.recording {
            recording.record_foxglove_encoded(topic, stamp, &self.encoded);
        }
        if let Some(viewer) = &self.viewer
            && viewer.wants(topic)
        {
            viewer.send(topic, stamp, &self.encoded);
        }
    }
}
