//! The Foxglove channels a recording holds beside hopnav's own ([`super::foxglove_view`]
//! makes their messages).

use foxglove::Encode;
use foxglove::messages::{FrameTransforms, Grid, PointCloud, PosesInFrame, RawImage};

/// One Foxglove channel of a recording.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FoxgloveTopic {
    /// The jumper's camera.
    JumperImage,
    /// The rover's left camera.
    RoverLeftImage,
    /// The rover's right camera.
    RoverRightImage,
    /// The jumper VO's keyframe clouds.
    JumperCloud,
    /// The rover VO's keyframe clouds.
    RoverCloud,
    /// Both robots' frames: the VOs' estimates and the physics' truth.
    Transforms,
    /// The mapper's whole-map snapshots.
    Map,
    /// The planner's path.
    Path,
}

impl FoxgloveTopic {
    /// Every channel, in the order the recording creates them.
    pub const ALL: [Self; 8] = [
        Self::JumperImage,
        Self::RoverLeftImage,
        Self::RoverRightImage,
        Self::JumperCloud,
        Self::RoverCloud,
        Self::Transforms,
        Self::Map,
        Self::Path,
    ];

    /// Its place in [`Self::ALL`] (the order of declaration).
    pub fn index(self) -> usize {
        self as usize
    }

    /// Whether it carries camera images (left out by `[recorder] images = false`).
    pub fn is_image(self) -> bool {
        matches!(
            self,
            Self::JumperImage | Self::RoverLeftImage | Self::RoverRightImage
        )
    }

    /// The channel's topic in the file (under `/foxglove/`, apart from hopnav's own).
    pub fn topic(self) -> &'static str {
        match self {
            Self::JumperImage => "/foxglove/jumper/image",
            Self::RoverLeftImage => "/foxglove/rover/left_image",
            Self::RoverRightImage => "/foxglove/rover/right_image",
            Self::JumperCloud => "/foxglove/jumper/cloud",
            Self::RoverCloud => "/foxglove/rover/cloud",
            Self::Transforms => "/foxglove/tf",
            Self::Map => "/foxglove/map",
            Self::Path => "/foxglove/planner/path",
        }
    }

    /// The schema of its messages (Foxglove's protobuf definition).
    pub fn schema(self) -> Option<foxglove::Schema> {
        match self {
            Self::JumperImage | Self::RoverLeftImage | Self::RoverRightImage => {
                RawImage::get_schema()
            }
            Self::JumperCloud | Self::RoverCloud => PointCloud::get_schema(),
            Self::Transforms => FrameTransforms::get_schema(),
            Self::Map => Grid::get_schema(),
            Self::Path => PosesInFrame::get_schema(),
        }
    }

    /// The message encoding of its channel.
    pub fn message_encoding(self) -> String {
        // Every schema above is one of Foxglove's protobuf messages.
        RawImage::get_message_encoding()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_channel_stands_at_its_index() {
        for (index, topic) in FoxgloveTopic::ALL.into_iter().enumerate() {
            assert_eq!(topic.index(), index);
        }
    }

    #[test]
    fn every_channel_has_a_protobuf_schema_and_a_topic_of_its_own() {
        let mut topics: Vec<&str> = FoxgloveTopic::ALL.iter().map(|t| t.topic()).collect();
        topics.sort_unstable();
        topics.dedup();
        assert_eq!(topics.len(), FoxgloveTopic::ALL.len());
        for topic in FoxgloveTopic::ALL {
            let schema = topic.schema().expect("schema");
            assert_eq!(schema.encoding, "protobuf");
            assert!(schema.name.starts_with("foxglove."), "{}", schema.name);
            assert_eq!(topic.message_encoding(), "protobuf");
        }
    }
}
