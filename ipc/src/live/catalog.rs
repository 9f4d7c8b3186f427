//! Every hopnav topic a tool can open, with the message type it carries: a topic's type is
//! needed to open it (iceoryx2 checks it), so the tools dispatch on [`MessageKind`].

use iceoryx2::prelude::ZeroCopySend;

use crate::messages::{
    AltimeterSample, BodyStates, CloudHeader, Control, DriveCommand, FrameTick, Heartbeat,
    HopLaunch, ImageHeader, ImuSample, JumpRequest, MapHeader, PathHeader, PhysicsState,
    PoseEstimate,
};
use crate::topics::{self, TopicSpec};
use crate::validate::{Message, SliceHeader};

/// The message type of a topic.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[allow(missing_docs)] // each variant is named after its message type
pub enum MessageKind {
    Heartbeat,
    FrameTick,
    BodyStates,
    AltimeterSample,
    ImuSample,
    HopLaunch,
    PhysicsState,
    PoseEstimate,
    DriveCommand,
    JumpRequest,
    Control,
    Image,
    Cloud,
    Map,
    Path,
}

/// Code generic over a topic's message type, called with the type of a [`MessageKind`].
pub trait KindVisitor {
    /// What the visit gives.
    type Output;
    /// Visits a topic of fixed-size `M`.
    fn fixed<M: Message + ZeroCopySend>(self) -> Self::Output;
    /// Visits a topic of `H` headers with `[H::Element]` slices.
    fn slice<H: SliceHeader + ZeroCopySend>(self) -> Self::Output
    where
        H::Element: ZeroCopySend;
}

impl MessageKind {
    /// Calls `visitor` with this kind's message type.
    pub fn visit<V: KindVisitor>(self, visitor: V) -> V::Output {
        match self {
            Self::Heartbeat => visitor.fixed::<Heartbeat>(),
            Self::FrameTick => visitor.fixed::<FrameTick>(),
            Self::BodyStates => visitor.fixed::<BodyStates>(),
            Self::AltimeterSample => visitor.fixed::<AltimeterSample>(),
            Self::ImuSample => visitor.fixed::<ImuSample>(),
            Self::HopLaunch => visitor.fixed::<HopLaunch>(),
            Self::PhysicsState => visitor.fixed::<PhysicsState>(),
            Self::PoseEstimate => visitor.fixed::<PoseEstimate>(),
            Self::DriveCommand => visitor.fixed::<DriveCommand>(),
            Self::JumpRequest => visitor.fixed::<JumpRequest>(),
            Self::Control => visitor.fixed::<Control>(),
            Self::Image => visitor.slice::<ImageHeader>(),
            Self::Cloud => visitor.slice::<CloudHeader>(),
            Self::Map => visitor.slice::<MapHeader>(),
            Self::Path => visitor.slice::<PathHeader>(),
        }
    }
}

/// A topic name with its quality of service and message type.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct KnownTopic {
    /// Name and quality of service, as the graph opens it.
    pub spec: TopicSpec,
    /// What it carries.
    pub kind: MessageKind,
}

/// Every fixed topic of [`crate::topics`] with its message type (the per-process step topics
/// are matched by their prefix in [`known_topic`]).
fn fixed_topics() -> [(TopicSpec, MessageKind); 23] {
    use MessageKind as K;
    [
        (topics::HEARTBEAT, K::Heartbeat),
        (topics::BODY_STATES, K::BodyStates),
        (topics::ALTIMETER, K::AltimeterSample),
        (topics::IMU, K::ImuSample),
        (topics::HOP_LAUNCH, K::HopLaunch),
        (topics::PHYSICS_STATE, K::PhysicsState),
        (topics::JUMPER_IMAGE, K::Image),
        (topics::ROVER_STEREO, K::Image),
        (topics::JUMPER_POSE, K::PoseEstimate),
        (topics::ROVER_POSE, K::PoseEstimate),
        (topics::JUMPER_CLOUD, K::Cloud),
        (topics::ROVER_CLOUD, K::Cloud),
        (topics::MAP_UPDATES, K::Map),
        (topics::MAP_SNAPSHOT, K::Map),
        (topics::PATH, K::Path),
        (topics::DRIVE_COMMAND, K::DriveCommand),
        (topics::JUMP_REQUEST, K::JumpRequest),
        (topics::RESUME_PHYSICS_STATE, K::PhysicsState),
        (topics::RESUME_JUMPER_POSE, K::PoseEstimate),
        (topics::RESUME_HOP_LAUNCH, K::HopLaunch),
        (topics::RESUME_ROVER_POSE, K::PoseEstimate),
        (topics::PROBE_IMAGE, K::Image),
        (topics::CONTROL, K::Control),
    ]
}

/// Prefix of the supervisor's per-process step topics ([`topics::step`]).
const STEP_PREFIX: &str = "hopnav/step/";

/// The topic named `name`, if hopnav has one by that name.
pub fn known_topic(name: &str) -> Option<KnownTopic> {
    if let Some(process) = name.strip_prefix(STEP_PREFIX) {
        return (!process.is_empty()).then(|| KnownTopic {
            spec: topics::step(process),
            kind: MessageKind::FrameTick,
        });
    }
    fixed_topics()
        .into_iter()
        .find(|(spec, _)| spec.name == name)
        .map(|(spec, kind)| KnownTopic { spec, kind })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_topic_of_the_graph_is_known_with_its_type() {
        let camera = known_topic("hopnav/camera/jumper").unwrap();
        assert_eq!(camera.kind, MessageKind::Image);
        assert_eq!(camera.spec, topics::JUMPER_IMAGE);
        assert_eq!(
            known_topic("hopnav/rover_vo/pose").unwrap().kind,
            MessageKind::PoseEstimate
        );
        let step = known_topic("hopnav/step/camera").unwrap();
        assert_eq!(step.spec, topics::step("camera"));
        assert_eq!(known_topic("hopnav/step/"), None);
        assert_eq!(known_topic("hopnav/nothing"), None);
    }

    #[test]
    fn the_catalog_names_each_topic_once() {
        let mut names: Vec<_> = fixed_topics().iter().map(|(s, _)| s.name.clone()).collect();
        let count = names.len();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), count);
    }
}
