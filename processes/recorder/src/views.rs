//! Each tapped topic's Foxglove messages, for the recording's Foxglove channels and the live
//! viewer. A view converts a sample only for a topic someone takes ([`Outputs::send`]).

use hopnav_ipc::messages::{
    BodyStates, CellUpdate, CloudHeader, FeaturePoint, ImageHeader, MapHeader, PathHeader,
    PathPoint, PoseEstimate,
};

use crate::foxglove_out::Outputs;
use crate::recording::FoxgloveTopic;
use crate::recording::foxglove_view as view;

/// Both robots' true poses.
pub fn truth(outputs: &mut Outputs, states: &BodyStates) {
    outputs.send(FoxgloveTopic::Transforms, states.stamp, || {
        Some(view::truth(states))
    });
}

/// A VO's pose estimate.
pub fn estimate(outputs: &mut Outputs, pose: &PoseEstimate) {
    outputs.send(FoxgloveTopic::Transforms, pose.stamp, || {
        view::estimate(pose)
    });
}

/// The jumper's image.
pub fn jumper_image(outputs: &mut Outputs, header: &ImageHeader, pixels: &[u8]) {
    outputs.send(FoxgloveTopic::JumperImage, header.stamp, || {
        view::image(header, pixels, 0)
    });
}

/// Both views of the rover's stereo pair.
pub fn rover_images(outputs: &mut Outputs, header: &ImageHeader, pixels: &[u8]) {
    let topics = [
        FoxgloveTopic::RoverLeftImage,
        FoxgloveTopic::RoverRightImage,
    ];
    for (view_index, topic) in (0..).zip(topics) {
        outputs.send(topic, header.stamp, || {
            view::image(header, pixels, view_index)
        });
    }
}

/// The jumper VO's keyframe cloud.
pub fn jumper_cloud(outputs: &mut Outputs, header: &CloudHeader, points: &[FeaturePoint]) {
    outputs.send(FoxgloveTopic::JumperCloud, header.stamp, || {
        Some(view::cloud(header, points))
    });
}

/// The rover VO's keyframe cloud.
pub fn rover_cloud(outputs: &mut Outputs, header: &CloudHeader, points: &[FeaturePoint]) {
    outputs.send(FoxgloveTopic::RoverCloud, header.stamp, || {
        Some(view::cloud(header, points))
    });
}

/// A whole-map snapshot.
pub fn map(outputs: &mut Outputs, header: &MapHeader, cells: &[CellUpdate]) {
    outputs.send(FoxgloveTopic::Map, header.stamp, || {
        view::map(header, cells)
    });
}

/// The planner's path.
pub fn path(outputs: &mut Outputs, header: &PathHeader, points: &[PathPoint]) {
    outputs.send(FoxgloveTopic::Path, header.stamp, || {
        Some(view::path(header, points))
    });
}
