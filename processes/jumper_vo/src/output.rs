//! Per-frame input and output of [`crate::pipeline::JumperVo`].

use crate::cloud::WorldPoint;
use hopnav_vision::image::ImageView;
use hopnav_vision::two_view::MotionModel;
use nalgebra::Isometry3;

/// One camera frame with the altimeter sample taken with it.
#[derive(Debug, Clone, Copy)]
pub struct FrameInput<'a> {
    /// Frame counter.
    pub frame_index: u64,
    /// Sim time, seconds. The first frame processed is taken as the launch instant.
    pub t_s: f64,
    /// 8-bit grayscale image.
    pub image: ImageView<'a>,
    /// Altimeter reading (body altitude), metres; `None` or non-finite when missing.
    pub altimeter_m: Option<f64>,
}

/// What produced the pose of a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VoStatus {
    /// First frame: the pose is the given initial pose.
    Initializing,
    /// Vision estimate against the keyframe.
    Tracking,
    /// Too few features or no geometry: ballistic propagation (low confidence).
    Propagating,
    /// Touched down: position held, tracking re-initialized.
    Landed,
    /// Input rejected (non-finite or non-increasing time): last pose repeated.
    Rejected,
}

/// Result of one frame.
#[derive(Debug, Clone, PartialEq)]
pub struct VoOutput {
    /// Frame counter of the input.
    pub frame_index: u64,
    /// Time of the input, seconds.
    pub t_s: f64,
    /// Estimated body pose.
    pub world_from_body: Isometry3<f64>,
    /// 0 (no information) … 1 (many inliers).
    pub confidence: f64,
    /// What produced the pose.
    pub status: VoStatus,
    /// This frame became a keyframe.
    pub is_keyframe: bool,
    /// Features tracked into this frame.
    pub tracked_features: usize,
    /// RANSAC inliers of the model used (0 without a vision estimate).
    pub inliers: usize,
    /// Metres per unit VO translation (the camera displacement from the keyframe), if any.
    pub scale: Option<f64>,
    /// Two-view model used, if any.
    pub model: Option<MotionModel>,
    /// Triangulated world-frame points (keyframes only).
    pub cloud: Option<Vec<WorldPoint>>,
    /// The camera every point of `cloud` was triangulated to: this keyframe's (the other view
    /// of each point is an older keyframe's, see `cloud_track_keyframes`). The depth sigmas are
    /// ranges from it, and evaluation recovers each point's viewing ray from it.
    pub cloud_world_from_camera: Option<Isometry3<f64>>,
    /// σ of the position relative to the hop's launch point, metres (the square root of its
    /// covariance's trace): it grows while the VO coasts without ground and after a landing
    /// by the slide's scatter; NaN while unknown. The launch point's own error is not in it.
    pub position_sigma_m: f64,
}
