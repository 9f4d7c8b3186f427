//! VO → mapper, planner, evaluation: estimated poses.

use iceoryx2::prelude::ZeroCopySend;

use super::{Pose3, Robot, SampleStamp};

/// A 6-DOF pose estimate of one robot.
#[repr(C)]
#[derive(Debug, Default, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("hopnav::PoseEstimate")]
pub struct PoseEstimate {
    /// Frame identity and timing.
    pub stamp: SampleStamp,
    /// Estimated `world_from_body`.
    pub world_from_body: Pose3,
    /// Confidence in [0, 1]; below 0.5 the pose is propagated, not measured.
    pub confidence: f64,
    /// Metric scale factor applied to the monocular translation (1 for stereo).
    pub scale: f64,
    /// Tracked features used for this estimate.
    pub tracked_features: u32,
    /// A [`Robot`](super::Robot) code.
    pub robot: u32,
    /// 1 if this frame became a keyframe.
    pub is_keyframe: u32,
    /// A [`PoseQuality`] code: what the estimate rests on (0 when the producer does not say).
    pub quality: u32,
    /// σ of the position relative to where the robot's current motion segment started (a
    /// hop's launch point), metres; negative when the producer does not say.
    pub position_sigma_m: f64,
}

/// What a pose estimate rests on, for consumers that weigh it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u32)]
pub enum PoseQuality {
    /// Not said (older producers).
    Unknown = 0,
    /// Measured by vision this frame.
    Measured = 1,
    /// Coasting: the camera saw no usable ground (sky, blur, a tumble) and the pose is
    /// propagated by the motion model; its error grows until vision returns.
    Coasting = 2,
    /// At rest after a landing: held, not measured.
    AtRest = 3,
    /// The first frame: the given starting pose.
    Initial = 4,
    /// The input was rejected: the last pose repeated.
    Repeated = 5,
}

impl PoseQuality {
    /// The quality a code names (`Unknown` for codes it does not know).
    pub fn from_code(code: u32) -> Self {
        match code {
            1 => Self::Measured,
            2 => Self::Coasting,
            3 => Self::AtRest,
            4 => Self::Initial,
            5 => Self::Repeated,
            _ => Self::Unknown,
        }
    }
}

const _: () = assert!(size_of::<PoseEstimate>() == 128);

impl PoseEstimate {
    /// A VO's estimate of `robot`'s pose on the frame `frame` stamps (its index and simulated
    /// time; the transport adds the sequence and the publish time).
    pub fn from_vo(
        robot: Robot,
        frame: &SampleStamp,
        world_from_body: Pose3,
        confidence: f64,
        scale: f64,
        tracked_features: usize,
        is_keyframe: bool,
    ) -> Self {
        Self {
            stamp: frame.for_same_frame(),
            world_from_body,
            confidence,
            scale,
            tracked_features: tracked_features as u32,
            robot: robot.code(),
            is_keyframe: u32::from(is_keyframe),
            quality: PoseQuality::Unknown as u32,
            position_sigma_m: -1.0,
        }
    }

    /// The same estimate with its position σ (metres; NaN or negative: not said).
    pub fn with_position_sigma(mut self, sigma_m: f64) -> Self {
        self.position_sigma_m = if sigma_m >= 0.0 && sigma_m.is_finite() {
            sigma_m
        } else {
            -1.0
        };
        self
    }

    /// The same estimate, saying what it rests on.
    pub fn with_quality(mut self, quality: PoseQuality) -> Self {
        self.quality = quality as u32;
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_quality_code_names_its_quality_and_unknown_codes_are_unknown() {
        for quality in [
            PoseQuality::Unknown,
            PoseQuality::Measured,
            PoseQuality::Coasting,
            PoseQuality::AtRest,
            PoseQuality::Initial,
            PoseQuality::Repeated,
        ] {
            assert_eq!(PoseQuality::from_code(quality as u32), quality);
        }
        assert_eq!(PoseQuality::from_code(99), PoseQuality::Unknown);
        let pose = PoseEstimate::from_vo(
            Robot::Jumper,
            &SampleStamp::default(),
            Pose3::default(),
            0.1,
            1.0,
            0,
            true,
        )
        .with_quality(PoseQuality::Coasting);
        assert_eq!(PoseQuality::from_code(pose.quality), PoseQuality::Coasting);
        assert_eq!(pose.position_sigma_m, -1.0);
        assert_eq!(pose.with_position_sigma(0.3).position_sigma_m, 0.3);
        assert_eq!(pose.with_position_sigma(f64::NAN).position_sigma_m, -1.0);
    }
}
