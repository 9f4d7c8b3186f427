//! The channels the recording's tests write: a pose and a camera.

use hopnav_ipc::messages::{ImageHeader, PoseEstimate};
use hopnav_ipc::wire;

use super::ChannelSpec;

/// `hopnav/rover_vo/pose` (channel 0) and `hopnav/camera/jumper` (channel 1).
pub fn pose_and_image() -> Vec<ChannelSpec> {
    vec![
        ChannelSpec {
            topic: "hopnav/rover_vo/pose".into(),
            schema_name: wire::schema_name::<PoseEstimate>(),
            schema_text: wire::schema_text::<PoseEstimate>(),
        },
        ChannelSpec {
            topic: "hopnav/camera/jumper".into(),
            schema_name: wire::slice_schema_name::<ImageHeader, u8>(),
            schema_text: wire::slice_schema_text::<ImageHeader, u8>(),
        },
    ]
}
