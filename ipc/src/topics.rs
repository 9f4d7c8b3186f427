//! Every topic name and its quality of service, in one place.
//!
//! A topic is an iceoryx2 publish-subscribe service plus an event service of the same name:
//! publishers notify after sending, so subscribers wait on events and never poll. Every side
//! opens a topic with the same [`TopicSpec`], so whoever comes first creates it right.

use std::borrow::Cow;

/// Name and quality of service of one topic.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TopicSpec {
    /// iceoryx2 service name (unique within a launch's namespace).
    pub name: Cow<'static, str>,
    /// Samples a late subscriber receives on connect (restarted processes recover from it).
    pub history_size: usize,
    /// Samples buffered per subscriber; the oldest is overwritten when full.
    pub subscriber_buffer: usize,
    /// Publishers at once, counting a restarted process's new port before the dead one is
    /// cleaned.
    pub max_publishers: usize,
    /// Subscribers at once.
    pub max_subscribers: usize,
}

impl TopicSpec {
    const fn fixed(name: &'static str, history_size: usize, subscriber_buffer: usize) -> Self {
        Self {
            name: Cow::Borrowed(name),
            history_size,
            subscriber_buffer,
            max_publishers: 4,
            max_subscribers: 8,
        }
    }

    /// A feature-cloud topic: a deep history for a restarted mapper, and few subscribers
    /// (the mapper and the recorder, each with a restart overlapping, plus two spare), as
    /// each one's buffer is as deep.
    const fn cloud(name: &'static str) -> Self {
        Self {
            name: Cow::Borrowed(name),
            history_size: 24,
            subscriber_buffer: 24,
            max_publishers: 4,
            max_subscribers: 6,
        }
    }

    /// Nodes that may hold a port of this topic at once.
    pub fn max_nodes(&self) -> usize {
        (self.max_publishers + self.max_subscribers) * 2
    }
}

/// Process → supervisor heartbeats; every process publishes here.
pub const HEARTBEAT: TopicSpec = TopicSpec {
    name: Cow::Borrowed("hopnav/heartbeat"),
    history_size: 0,
    subscriber_buffer: 256,
    max_publishers: 40,
    max_subscribers: 4,
};

/// Supervisor → one process: that process's frame releases and shutdown.
pub fn step(process_name: &str) -> TopicSpec {
    TopicSpec {
        name: Cow::Owned(format!("hopnav/step/{process_name}")),
        history_size: 1,
        subscriber_buffer: 4,
        max_publishers: 2,
        max_subscribers: 2,
    }
}

/// Latency probe: one image-sized sample per frame.
pub const PROBE_IMAGE: TopicSpec = TopicSpec::fixed("hopnav/probe_source/image", 1, 2);
/// physics: ground-truth body states (evaluation and rendering only).
pub const BODY_STATES: TopicSpec = TopicSpec::fixed("hopnav/physics/body_states", 1, 4);
/// physics: the jumper's altimeter.
pub const ALTIMETER: TopicSpec = TopicSpec::fixed("hopnav/physics/altimeter", 1, 8);
/// physics: the rover's IMU.
pub const IMU: TopicSpec = TopicSpec::fixed("hopnav/physics/imu", 1, 8);
/// camera: the jumper's rear-facing mono image.
pub const JUMPER_IMAGE: TopicSpec = TopicSpec::fixed("hopnav/camera/jumper", 1, 2);
/// camera: the rover's stereo pair. History 4: a restarted rover_vo finds the pair its last
/// published pose was measured on, and measures the motion from there.
pub const ROVER_STEREO: TopicSpec = TopicSpec::fixed("hopnav/camera/rover_stereo", 4, 4);
/// jumper_vo: estimated jumper pose, every frame.
pub const JUMPER_POSE: TopicSpec = TopicSpec::fixed("hopnav/jumper_vo/pose", 1, 8);
/// rover_vo: estimated rover pose, every frame.
pub const ROVER_POSE: TopicSpec = TopicSpec::fixed("hopnav/rover_vo/pose", 1, 8);
/// jumper_vo: world-frame feature cloud, each keyframe. History 24 (with the rover's): a
/// restarted mapper restores a snapshot up to `snapshot_every_frames` old and takes in the
/// clouds published since from here.
pub const JUMPER_CLOUD: TopicSpec = TopicSpec::cloud("hopnav/jumper_vo/cloud");
/// rover_vo: world-frame feature cloud, each keyframe (history: see [`JUMPER_CLOUD`]).
pub const ROVER_CLOUD: TopicSpec = TopicSpec::cloud("hopnav/rover_vo/cloud");
/// mapper: changed cells only.
pub const MAP_UPDATES: TopicSpec = TopicSpec::fixed("hopnav/mapper/cells", 0, 16);
/// mapper: every known cell, every few frames. History 1: a restarted planner reads the
/// whole map at once, and a planner that missed updates resynchronises.
pub const MAP_SNAPSHOT: TopicSpec = TopicSpec::fixed("hopnav/mapper/snapshot", 1, 2);
/// planner: the current path.
pub const PATH: TopicSpec = TopicSpec::fixed("hopnav/planner/path", 1, 2);
/// planner → physics: rover drive command.
pub const DRIVE_COMMAND: TopicSpec = TopicSpec::fixed("hopnav/planner/drive", 1, 4);
/// planner → physics: jump request.
pub const JUMP_REQUEST: TopicSpec = TopicSpec::fixed("hopnav/planner/jump", 1, 4);
/// physics → its own restart: both bodies and the bookkeeping behind them (hop cycle, rover
/// controller, sensor noise), every frame.
pub const PHYSICS_STATE: TopicSpec = TopicSpec::fixed("hopnav/physics/state", 1, 4);
/// physics → jumper VO: a hop was launched (commanded attitude and velocity).
pub const HOP_LAUNCH: TopicSpec = TopicSpec::fixed("hopnav/physics/hop_launch", 1, 4);
/// supervisor → a restarted jumper_vo: the last pose the jumper VO published. A publisher's
/// history dies with its process, so the supervisor relays each pose here and its publisher's
/// history hands the last one to the restarted process.
pub const RESUME_JUMPER_POSE: TopicSpec = TopicSpec::fixed("hopnav/resume/jumper_vo/pose", 1, 2);
/// supervisor → a restarted jumper_vo: the last hop launch (physics publishes launches only
/// when they happen, so its own history reaches a new subscriber only at the next launch).
pub const RESUME_HOP_LAUNCH: TopicSpec =
    TopicSpec::fixed("hopnav/resume/jumper_vo/hop_launch", 1, 2);
/// supervisor → a restarted rover_vo: the last pose the rover VO published.
pub const RESUME_ROVER_POSE: TopicSpec = TopicSpec::fixed("hopnav/resume/rover_vo/pose", 1, 2);
/// supervisor → a restarted physics: the last [`PHYSICS_STATE`] sample physics published.
pub const RESUME_PHYSICS_STATE: TopicSpec = TopicSpec::fixed("hopnav/resume/physics/state", 1, 2);
/// supervisor → all: launch-wide control.
pub const CONTROL: TopicSpec = TopicSpec::fixed("hopnav/control", 1, 4);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn topic_names_are_unique() {
        let all = [
            &HEARTBEAT,
            &PROBE_IMAGE,
            &BODY_STATES,
            &ALTIMETER,
            &IMU,
            &JUMPER_IMAGE,
            &ROVER_STEREO,
            &JUMPER_POSE,
            &ROVER_POSE,
            &JUMPER_CLOUD,
            &ROVER_CLOUD,
            &MAP_UPDATES,
            &MAP_SNAPSHOT,
            &PATH,
            &DRIVE_COMMAND,
            &JUMP_REQUEST,
            &HOP_LAUNCH,
            &CONTROL,
            &RESUME_JUMPER_POSE,
            &RESUME_HOP_LAUNCH,
            &RESUME_ROVER_POSE,
            &PHYSICS_STATE,
            &RESUME_PHYSICS_STATE,
        ];
        let mut names: Vec<_> = all.iter().map(|spec| spec.name.clone()).collect();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), all.len());
        assert_ne!(step("a").name, step("b").name);
    }
}
