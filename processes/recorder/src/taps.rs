//! Every topic the recorder reads, each with the index of its recording channel.
//!
//! The relays (`hopnav/resume/…`) repeat topics listed here, and heartbeats and frame steps are
//! the supervisor's bookkeeping, so none of them is tapped.

use hopnav_ipc::messages::{
    AltimeterSample, BodyStates, CloudHeader, Control, DriveCommand, HopLaunch, ImageHeader,
    ImuSample, JumpRequest, MapHeader, PathHeader, PhysicsState, PoseEstimate,
};
use hopnav_ipc::process_loop::ProcessContext;
use hopnav_ipc::topics::{self, TopicSpec};
use hopnav_ipc::transport::{SliceSubscriber, Subscriber, ValidSlice, ZeroCopySend};
use hopnav_ipc::validate::{Message, SliceHeader};
use hopnav_ipc::wire::{self, WireBytes};

use crate::RecorderError;
use crate::foxglove_out::Outputs;
use crate::recording::ChannelSpec;
use crate::views;

/// A subscriber of one tapped topic, the index of its recording channel (none when the
/// recording leaves the topic out), and its Foxglove messages (for the recording and the
/// viewer).
pub struct Tap<P: TapPort> {
    subscriber: P,
    channel: Option<usize>,
    view: Option<P::View>,
}

/// A tap of fixed-size messages.
pub type MessageTap<M> = Tap<Subscriber<M>>;
/// A tap of slices.
pub type SliceTap<H> = Tap<SliceSubscriber<H>>;

/// What a tap needs of its subscriber: to open it, the schema it records under, and its count
/// of rejected samples.
pub trait TapPort: Sized {
    /// Sends a sample's Foxglove messages to whoever takes them.
    type View: Copy;
    fn open_port(context: &ProcessContext, spec: &TopicSpec) -> Result<Self, RecorderError>;
    /// Schema name and text of the recorded samples.
    fn schema() -> (String, String);
    fn rejected_total(&self) -> u64;
}

/// A message's Foxglove messages to the recording and the viewer.
pub type MessageView<M> = fn(&mut Outputs, &M);
/// A slice's Foxglove messages to the recording and the viewer.
pub type SliceView<H> = fn(&mut Outputs, &H, &[<H as SliceHeader>::Element]);

impl<M: Message + ZeroCopySend + WireBytes> TapPort for Subscriber<M> {
    type View = MessageView<M>;

    fn open_port(context: &ProcessContext, spec: &TopicSpec) -> Result<Self, RecorderError> {
        Ok(Subscriber::open(&context.node, spec)?)
    }

    fn schema() -> (String, String) {
        (wire::schema_name::<M>(), wire::schema_text::<M>())
    }

    fn rejected_total(&self) -> u64 {
        self.rejected().total()
    }
}

impl<H: SliceHeader + ZeroCopySend + WireBytes> TapPort for SliceSubscriber<H>
where
    H::Element: ZeroCopySend + WireBytes,
{
    type View = SliceView<H>;

    fn open_port(context: &ProcessContext, spec: &TopicSpec) -> Result<Self, RecorderError> {
        Ok(SliceSubscriber::open(&context.node, spec)?)
    }

    fn schema() -> (String, String) {
        (
            wire::slice_schema_name::<H, H::Element>(),
            wire::slice_schema_text::<H, H::Element>(),
        )
    }

    fn rejected_total(&self) -> u64 {
        self.rejected().total()
    }
}

impl<P: TapPort> Tap<P> {
    /// Opens the subscriber of topic `spec` and adds its recording channel to `channels`.
    fn open(
        context: &ProcessContext,
        spec: &TopicSpec,
        channels: &mut Vec<ChannelSpec>,
    ) -> Result<Self, RecorderError> {
        Self::open_if(context, spec, channels, true)
    }

    /// Opens the subscriber of topic `spec` (the dataset may need it) and adds its recording
    /// channel to `channels` only if `recorded`.
    fn open_if(
        context: &ProcessContext,
        spec: &TopicSpec,
        channels: &mut Vec<ChannelSpec>,
        recorded: bool,
    ) -> Result<Self, RecorderError> {
        let subscriber = P::open_port(context, spec)?;
        let channel = recorded.then(|| {
            let (schema_name, schema_text) = P::schema();
            channels.push(ChannelSpec {
                topic: spec.name.to_string(),
                schema_name,
                schema_text,
            });
            channels.len() - 1
        });
        Ok(Self {
            subscriber,
            channel,
            view: None,
        })
    }

    /// The tap, sending `view`'s Foxglove messages of each sample.
    fn with_view(self, view: P::View) -> Self {
        Self {
            view: Some(view),
            ..self
        }
    }

    fn channel_and_rejected(&self) -> (Option<usize>, u64) {
        (self.channel, self.subscriber.rejected_total())
    }
}

impl<M: Message + ZeroCopySend + WireBytes> MessageTap<M> {
    /// Records every pending sample, sends its Foxglove messages and hands each to `also`.
    pub fn drain(
        &self,
        outputs: &mut Outputs,
        mut also: impl FnMut(&M) -> Result<(), RecorderError>,
    ) -> Result<(), RecorderError> {
        while let Some(message) = self.subscriber.receive()? {
            if let (Some(recording), Some(channel)) = (&mut outputs.recording, self.channel) {
                recording.record_message(channel, &message);
            }
            if let Some(view) = self.view {
                view(outputs, &message);
            }
            also(&message)?;
        }
        Ok(())
    }
}

impl<H: SliceHeader + ZeroCopySend + WireBytes> SliceTap<H>
where
    H::Element: ZeroCopySend + WireBytes,
{
    /// Records every pending sample (read in place), sends its Foxglove messages and hands
    /// each to `also`.
    pub fn drain(
        &self,
        outputs: &mut Outputs,
        mut also: impl FnMut(&ValidSlice<H>) -> Result<(), RecorderError>,
    ) -> Result<(), RecorderError> {
        while let Some(sample) = self.subscriber.receive()? {
            if let (Some(recording), Some(channel)) = (&mut outputs.recording, self.channel) {
                recording.record_slice(channel, sample.header(), sample.elements());
            }
            if let Some(view) = self.view {
                view(outputs, sample.header(), sample.elements());
            }
            also(&sample)?;
        }
        Ok(())
    }
}

/// The tapped topics, in the order of their channels.
#[allow(missing_docs)] // each field is named after its topic
pub struct Taps {
    pub body_states: MessageTap<BodyStates>,
    pub altimeter: MessageTap<AltimeterSample>,
    pub imu: MessageTap<ImuSample>,
    pub physics_state: MessageTap<PhysicsState>,
    pub hop_launches: MessageTap<HopLaunch>,
    pub jumper_images: SliceTap<ImageHeader>,
    pub rover_stereo: SliceTap<ImageHeader>,
    pub jumper_poses: MessageTap<PoseEstimate>,
    pub rover_poses: MessageTap<PoseEstimate>,
    pub jumper_clouds: SliceTap<CloudHeader>,
    pub rover_clouds: SliceTap<CloudHeader>,
    pub map_updates: SliceTap<MapHeader>,
    pub map_snapshots: SliceTap<MapHeader>,
    pub paths: SliceTap<PathHeader>,
    pub drive_commands: MessageTap<DriveCommand>,
    pub jump_requests: MessageTap<JumpRequest>,
    pub control: MessageTap<Control>,
}

impl Taps {
    /// Opens a subscriber on every tapped topic; returns the taps and their channels, indexed
    /// as the taps name them (without the cameras' unless `images`).
    pub fn open(
        context: &ProcessContext,
        images: bool,
    ) -> Result<(Self, Vec<ChannelSpec>), RecorderError> {
        let mut channels = Vec::new();
        let taps = Self {
            body_states: MessageTap::open(context, &topics::BODY_STATES, &mut channels)?
                .with_view(views::truth),
            altimeter: MessageTap::open(context, &topics::ALTIMETER, &mut channels)?,
            imu: MessageTap::open(context, &topics::IMU, &mut channels)?,
            physics_state: MessageTap::open(context, &topics::PHYSICS_STATE, &mut channels)?,
            hop_launches: MessageTap::open(context, &topics::HOP_LAUNCH, &mut channels)?,
            jumper_images: SliceTap::open_if(
                context,
                &topics::JUMPER_IMAGE,
                &mut channels,
                images,
            )?
            .with_view(views::jumper_image),
            rover_stereo: SliceTap::open_if(context, &topics::ROVER_STEREO, &mut channels, images)?
                .with_view(views::rover_images),
            jumper_poses: MessageTap::open(context, &topics::JUMPER_POSE, &mut channels)?
                .with_view(views::estimate),
            rover_poses: MessageTap::open(context, &topics::ROVER_POSE, &mut channels)?
                .with_view(views::estimate),
            jumper_clouds: SliceTap::open(context, &topics::JUMPER_CLOUD, &mut channels)?
                .with_view(views::jumper_cloud),
            rover_clouds: SliceTap::open(context, &topics::ROVER_CLOUD, &mut channels)?
                .with_view(views::rover_cloud),
            map_updates: SliceTap::open(context, &topics::MAP_UPDATES, &mut channels)?,
            map_snapshots: SliceTap::open(context, &topics::MAP_SNAPSHOT, &mut channels)?
                .with_view(views::map),
            paths: SliceTap::open(context, &topics::PATH, &mut channels)?.with_view(views::path),
            drive_commands: MessageTap::open(context, &topics::DRIVE_COMMAND, &mut channels)?,
            jump_requests: MessageTap::open(context, &topics::JUMP_REQUEST, &mut channels)?,
            control: MessageTap::open(context, &topics::CONTROL, &mut channels)?,
        };
        Ok((taps, channels))
    }

    /// Samples rejected per recorded channel (invalid or out of sequence), indexed like the
    /// channels.
    pub fn rejected_per_channel(&self) -> Vec<u64> {
        self.rejected_per_tap()
            .into_iter()
            .filter_map(|(channel, rejected)| channel.map(|_| rejected))
            .collect()
    }

    /// Samples rejected by every tap, recorded or not.
    pub fn rejected_total(&self) -> u64 {
        self.rejected_per_tap()
            .into_iter()
            .map(|(_, rejected)| rejected)
            .sum()
    }

    /// Each tap's recording channel and rejected samples, in the order of the channels.
    fn rejected_per_tap(&self) -> [(Option<usize>, u64); 17] {
        [
            self.body_states.channel_and_rejected(),
            self.altimeter.channel_and_rejected(),
            self.imu.channel_and_rejected(),
            self.physics_state.channel_and_rejected(),
            self.hop_launches.channel_and_rejected(),
            self.jumper_images.channel_and_rejected(),
            self.rover_stereo.channel_and_rejected(),
            self.jumper_poses.channel_and_rejected(),
            self.rover_poses.channel_and_rejected(),
            self.jumper_clouds.channel_and_rejected(),
            self.rover_clouds.channel_and_rejected(),
            self.map_updates.channel_and_rejected(),
            self.map_snapshots.channel_and_rejected(),
            self.paths.channel_and_rejected(),
            self.drive_commands.channel_and_rejected(),
            self.jump_requests.channel_and_rejected(),
            self.control.channel_and_rejected(),
        ]
    }
}
