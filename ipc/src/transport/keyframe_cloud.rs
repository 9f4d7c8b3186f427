//! Sending a VO's keyframe cloud: the header announcing the points, then the points, as
//! many as the port holds.

use super::{SendError, SlicePublisher};
use crate::messages::{CloudHeader, FeaturePoint, Pose3, Robot, SampleStamp};

impl SlicePublisher<CloudHeader> {
    /// Sends `robot`'s keyframe cloud of `point_count` points seen from `world_from_camera`
    /// on the frame `frame` stamps, cut to the port's largest slice; `point(index)` gives each
    /// point.
    pub fn send_keyframe_cloud(
        &mut self,
        robot: Robot,
        frame: &SampleStamp,
        world_from_camera: Pose3,
        keyframe_index: u64,
        point_count: usize,
        point: impl FnMut(usize) -> FeaturePoint,
    ) -> Result<usize, SendError> {
        let len = point_count.min(self.max_len());
        self.send_from_fn(
            len,
            |header| {
                *header =
                    CloudHeader::keyframe(robot, frame, world_from_camera, len, keyframe_index);
            },
            point,
        )
    }
}
