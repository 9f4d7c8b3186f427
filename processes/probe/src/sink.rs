//! `probe_sink`: stage 1, verifies every probe sample and measures its delivery latency.

use hopnav_ipc::messages::{FrameTick, ImageHeader};
use hopnav_ipc::process_loop::{Process, ProcessContext};
use hopnav_ipc::stamp::monotonic_now_ns;
use hopnav_ipc::topics;
use hopnav_ipc::transport::SliceSubscriber;

use crate::ProbeError;
use crate::pattern::first_mismatch;

/// Receives the probe images and checks them byte for byte.
pub struct ProbeSink {
    subscriber: SliceSubscriber<ImageHeader>,
    corrupt_payloads: u64,
    missing_frames: u64,
    latencies_ns: Vec<u64>,
}

/// What the sink saw over its life.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SinkSummary {
    /// Samples whose payload differed from the frame's pattern.
    pub corrupt_payloads: u64,
    /// Released frames for which no sample had arrived.
    pub missing_frames: u64,
    /// Samples received and verified.
    pub verified: u64,
}

impl ProbeSink {
    /// A sink on the probe topic; `expected_frames` sizes the latency record up front.
    pub fn open(context: &ProcessContext, expected_frames: usize) -> Result<Self, ProbeError> {
        Ok(Self {
            subscriber: SliceSubscriber::open(&context.node, &topics::PROBE_IMAGE)?,
            corrupt_payloads: 0,
            missing_frames: 0,
            latencies_ns: Vec::with_capacity(expected_frames.min(1 << 20)),
        })
    }

    /// Counts so far.
    pub fn summary(&self) -> SinkSummary {
        SinkSummary {
            corrupt_payloads: self.corrupt_payloads,
            missing_frames: self.missing_frames,
            verified: self.latencies_ns.len() as u64,
        }
    }
}

impl Process for ProbeSink {
    type Error = ProbeError;

    fn new(context: &ProcessContext) -> Result<Self, ProbeError> {
        let config = hopnav_config::load_file(&context.identity.config_path)?;
        Self::open(context, config.run.frames as usize)
    }

    fn step(&mut self, _context: &ProcessContext, tick: &FrameTick) -> Result<(), ProbeError> {
        self.subscriber.clear_events();
        let mut got_this_frame = false;
        while let Some(sample) = self.subscriber.receive()? {
            let received_ns = monotonic_now_ns();
            let header = sample.header();
            if first_mismatch(header.stamp.frame_index, sample.elements()).is_some() {
                self.corrupt_payloads += 1;
                continue;
            }
            got_this_frame |= header.stamp.frame_index == tick.stamp.frame_index;
            if self.latencies_ns.len() < self.latencies_ns.capacity() {
                self.latencies_ns
                    .push(received_ns.saturating_sub(header.stamp.publish_stamp_ns));
            }
        }
        if !got_this_frame {
            self.missing_frames += 1;
        }
        Ok(())
    }

    fn rejected_samples(&self) -> u64 {
        self.subscriber.rejected().total() + self.corrupt_payloads
    }

    fn stop(&mut self, context: &ProcessContext) {
        let summary = self.summary();
        let mut sorted = self.latencies_ns.clone();
        sorted.sort_unstable();
        let p50_us = sorted.get(sorted.len() / 2).copied().unwrap_or(0) as f64 / 1e3;
        eprintln!(
            "[{}] verified {} probe images, {} corrupt, {} missing, delivery p50 {p50_us:.1} us",
            context.identity.name,
            summary.verified,
            summary.corrupt_payloads,
            summary.missing_frames
        );
    }
}
