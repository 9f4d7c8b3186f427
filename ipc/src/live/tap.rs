//! `hopnav topic hz` and `echo`: an extra subscriber on one topic of a running launch, woken
//! by the topic's events (never polling), with a tick for periodic output.

use std::ops::ControlFlow;
use std::time::Duration;

use iceoryx2::node::Node;
use iceoryx2::port::listener::Listener;
use iceoryx2::prelude::{CallbackProgression, WaitSetBuilder, ZeroCopySend};
use iceoryx2::waitset::WaitSetRunResult;

use super::LiveError;
use super::catalog::{KindVisitor, KnownTopic};
use super::runs::is_running;
use crate::IpcService;
use crate::messages::SampleStamp;
use crate::namespace::Namespace;
use crate::stamp::monotonic_now_ns;
use crate::topics::TopicSpec;
use crate::transport::{
    OpenError, ReceiveError, RejectCounts, SliceSubscriber, Subscriber, ValidSlice,
};
use crate::validate::{Message, SliceHeader};

/// One received, validated sample, as a tool sees it.
pub trait TapSample {
    /// Its stamp.
    fn stamp(&self) -> &SampleStamp;
    /// A readable rendering: every field of a message; the header and the element count of
    /// a slice (images and clouds are summarised, not dumped).
    fn describe(&self) -> String;
    /// Bytes the sample occupies in shared memory: the message, or the header and its
    /// elements (what a transport that copied it would move).
    fn payload_bytes(&self) -> usize;
    /// The sample itself, for [`fixed_message`].
    fn as_any(&self) -> &dyn std::any::Any;
}

/// The message of a sample of a fixed-size topic of type `M` (`None` for another type or a
/// slice topic): for tools that read a message's fields, not only its rendering.
pub fn fixed_message<M: Message + 'static>(sample: &dyn TapSample) -> Option<&M> {
    sample
        .as_any()
        .downcast_ref::<FixedSample<M>>()
        .map(|fixed| &fixed.0)
}

/// Why a watch ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WatchEnd {
    /// The tick callback asked to stop.
    Stopped,
    /// SIGINT or SIGTERM.
    Interrupted,
    /// The launch is gone (its supervisor node died).
    LaunchEnded,
}

/// What a tool does with a watched topic.
pub trait Watcher {
    /// A valid sample arrived at `arrival_ns` (CLOCK_MONOTONIC).
    fn on_sample(&mut self, sample: &dyn TapSample, arrival_ns: u64);
    /// A tick at `now_ns`; `Break` ends the watch.
    fn on_tick(&mut self, now_ns: u64) -> ControlFlow<()>;
}

/// Watches `topic` of the launch of `namespace` as an extra subscriber: `watcher` gets each
/// valid sample as it arrives and a tick every `tick`. Returns why the watch ended and what
/// was rejected.
pub fn watch(
    namespace: &Namespace,
    topic: &KnownTopic,
    tick: Duration,
    watcher: &mut dyn Watcher,
) -> Result<(WatchEnd, RejectCounts), LiveError> {
    let watched = watch_on_own_node(namespace, topic, tick, watcher);
    if matches!(watched, Ok((WatchEnd::LaunchEnded, _))) {
        // The launch removes its namespace's files once no node of it lives; a tool still
        // attached then keeps them, so the last one out (this tool, its node gone now) does.
        namespace.remove_files_if_unused();
    }
    watched
}

/// [`watch`] with its node, ports and WaitSet, all dropped on return.
fn watch_on_own_node(
    namespace: &Namespace,
    topic: &KnownTopic,
    tick: Duration,
    watcher: &mut dyn Watcher,
) -> Result<(WatchEnd, RejectCounts), LiveError> {
    let node = namespace.create_node("topic_tap")?;
    let tap = topic.kind.visit(OpenTap {
        node: &node,
        spec: &topic.spec,
    })?;
    let wait_error = |error: &dyn std::fmt::Debug| LiveError::Iceoryx(format!("wait: {error:?}"));
    let waitset = WaitSetBuilder::new()
        .create::<IpcService>()
        .map_err(|error| wait_error(&error))?;
    let _guard = waitset
        .attach_notification(tap.listener())
        .map_err(|error| wait_error(&error))?;
    let tick_ns = tick.as_nanos().max(1) as u64;
    let mut next_tick_ns = monotonic_now_ns() + tick_ns;
    let end = loop {
        let until_tick_ns = next_tick_ns.saturating_sub(monotonic_now_ns());
        let timeout = Duration::from_nanos(until_tick_ns).max(Duration::from_millis(1));
        match waitset.wait_and_process_once_with_timeout(|_| CallbackProgression::Continue, timeout)
        {
            Ok(WaitSetRunResult::TerminationRequest) => break WatchEnd::Interrupted,
            Ok(_) => {}
            Err(error) => return Err(wait_error(&error)),
        }
        tap.clear_events();
        tap.drain(&mut |sample| watcher.on_sample(sample, monotonic_now_ns()))?;
        let now_ns = monotonic_now_ns();
        if now_ns < next_tick_ns {
            continue;
        }
        while next_tick_ns <= now_ns {
            next_tick_ns += tick_ns;
        }
        if !is_running(namespace) {
            break WatchEnd::LaunchEnded;
        }
        if watcher.on_tick(now_ns).is_break() {
            break WatchEnd::Stopped;
        }
    };
    Ok((end, tap.rejected()))
}

/// A subscriber of any message kind, behind one interface.
trait Tap {
    fn listener(&self) -> &Listener<IpcService>;
    fn clear_events(&self);
    fn drain(&self, on_sample: &mut dyn FnMut(&dyn TapSample)) -> Result<(), ReceiveError>;
    fn rejected(&self) -> RejectCounts;
}

struct FixedSample<M>(M);

impl<M: Message> TapSample for FixedSample<M> {
    fn stamp(&self) -> &SampleStamp {
        self.0.stamp()
    }

    fn describe(&self) -> String {
        format!("{:#?}", self.0)
    }

    fn payload_bytes(&self) -> usize {
        std::mem::size_of::<M>()
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

impl<H: SliceHeader + ZeroCopySend> TapSample for ValidSlice<H>
where
    H::Element: ZeroCopySend,
{
    fn stamp(&self) -> &SampleStamp {
        self.header().stamp()
    }

    fn describe(&self) -> String {
        let element = std::any::type_name::<H::Element>();
        let element = element.rsplit("::").next().unwrap_or(element);
        format!(
            "{:#?}\n[{} × {element}, {} bytes]",
            self.header(),
            self.elements().len(),
            std::mem::size_of_val(self.elements())
        )
    }

    fn payload_bytes(&self) -> usize {
        std::mem::size_of::<H>() + std::mem::size_of_val(self.elements())
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

impl<M: Message + ZeroCopySend> Tap for Subscriber<M> {
    fn listener(&self) -> &Listener<IpcService> {
        Subscriber::listener(self)
    }

    fn clear_events(&self) {
        Subscriber::clear_events(self);
    }

    fn drain(&self, on_sample: &mut dyn FnMut(&dyn TapSample)) -> Result<(), ReceiveError> {
        while let Some(message) = self.receive()? {
            on_sample(&FixedSample(message));
        }
        Ok(())
    }

    fn rejected(&self) -> RejectCounts {
        Subscriber::rejected(self)
    }
}

impl<H: SliceHeader + ZeroCopySend> Tap for SliceSubscriber<H>
where
    H::Element: ZeroCopySend,
{
    fn listener(&self) -> &Listener<IpcService> {
        SliceSubscriber::listener(self)
    }

    fn clear_events(&self) {
        SliceSubscriber::clear_events(self);
    }

    fn drain(&self, on_sample: &mut dyn FnMut(&dyn TapSample)) -> Result<(), ReceiveError> {
        // Each sample is read in place and dropped at once, back to its publisher.
        while let Some(sample) = self.receive()? {
            on_sample(&sample);
        }
        Ok(())
    }

    fn rejected(&self) -> RejectCounts {
        SliceSubscriber::rejected(self)
    }
}

/// Opens the tap subscriber of a topic's kind.
struct OpenTap<'a> {
    node: &'a Node<IpcService>,
    spec: &'a TopicSpec,
}

impl KindVisitor for OpenTap<'_> {
    type Output = Result<Box<dyn Tap>, OpenError>;

    fn fixed<M: Message + ZeroCopySend>(self) -> Self::Output {
        Ok(Box::new(Subscriber::<M>::open_tap(self.node, self.spec)?))
    }

    fn slice<H: SliceHeader + ZeroCopySend>(self) -> Self::Output
    where
        H::Element: ZeroCopySend,
    {
        Ok(Box::new(SliceSubscriber::<H>::open_tap(
            self.node, self.spec,
        )?))
    }
}
