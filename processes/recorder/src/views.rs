//! Each tapped topic's Foxglove messages, written beside its own channel.

use hopnav_ipc::messages::{
    BodyStates, CellUpdate, CloudHeader, FeaturePoint, ImageHeader, MapHeader, PathHeader,
    PathPoint, PoseEstimate,
};

use crate::recording::foxglove_view as view;
use crate::recording::{FoxgloveTopic, McapRecording};

/// Both robots' true poses.
pub fn truth(recording: &mut McapRecording, states: &BodyStates) {
    recording.record_foxglove(
        FoxgloveTopic::Transforms,
        states.stamp,
        &view::truth(states),
    );
}

/// A VO's pose estimate.
pub fn estimate(recording: &mut McapRecording, pose: &PoseEstimate) {
    if let Some(transforms) = view::estimate(pose) {
        recording.record_foxglove(FoxgloveTopic::Transforms, pose.stamp, &transforms);
    }
}

/// The jumper's image.
pub fn jumper_image(recording: &mut McapRecording, header: &ImageHeader, pixels: &[u8]) {
    if let Some(image) = view::image(header, pixels, 0) {
        recording.record_foxglove(FoxgloveTopic::JumperImage, header.stamp, &image);
    }
}

/// Both views of the rover's stereo pair.
pub fn rover_images(recording: &mut McapRecording, header: &ImageHeader, pixels: &[u8]) {
    let topics = [
        FoxgloveTopic::RoverLeftImage,
        FoxgloveTopic::RoverRightImage,
    ];
    for (view_index, topic) in (0..).zip(topics) {
        if let Some(image) = view::image(header, pixels, view_index) {
            recording.record_foxglove(topic, header.stamp, &image);
        }
    }
}

/// The jumper VO's keyframe cloud.
pub fn jumper_cloud(recording: &mut McapRecording, header: &CloudHeader, points: &[FeaturePoint]) {
    let cloud = view::cloud(header, points);
    recording.record_foxglove(FoxgloveTopic::JumperCloud, header.stamp, &cloud);
}

/// The rover VO's keyframe cloud.
pub fn rover_cloud(recording: &mut McapRecording, header: &CloudHeader, points: &[FeaturePoint]) {
    let cloud = view::cloud(header, points);
    recording.record_foxglove(FoxgloveTopic::RoverCloud, header.stamp, &cloud);
}

/// A whole-map snapshot.
pub fn map(recording: &mut McapRecording, header: &MapHeader, cells: &[CellUpdate]) {
    if let Some(grid) = view::map(header, cells) {
        recording.record_foxglove(FoxgloveTopic::Map, header.stamp, &grid);
    }
}

/// The planner's path.
pub fn path(recording: &mut McapRecording, header: &PathHeader, points: &[PathPoint]) {
    recording.record_foxglove(
        FoxgloveTopic::Path,
        header.stamp,
        &view::path(header, points),
    );
}
