//! `probe_source`: stage 0, one image-sized sample per frame.

use hopnav_ipc::messages::{CameraIntrinsics, FrameTick, ImageHeader, PixelFormat};
use hopnav_ipc::process_loop::{Process, ProcessContext};
use hopnav_ipc::stamp::monotonic_now_ns;
use hopnav_ipc::topics;
use hopnav_ipc::transport::SlicePublisher;

use crate::ProbeError;
use crate::pattern::pattern_byte;

/// Writes the frame's pattern straight into a loaned sample and publishes it.
pub struct ProbeSource {
    publisher: SlicePublisher<ImageHeader>,
    width_px: u32,
    height_px: u32,
}

impl ProbeSource {
    /// A source for `width_px` × `height_px` Mono8 images.
    pub fn open(
        context: &ProcessContext,
        width_px: u32,
        height_px: u32,
    ) -> Result<Self, ProbeError> {
        let len = width_px as usize * height_px as usize;
        Ok(Self {
            publisher: SlicePublisher::open(&context.node, &topics::PROBE_IMAGE, len)?,
            width_px,
            height_px,
        })
    }
}

impl Process for ProbeSource {
    type Error = ProbeError;

    fn new(context: &ProcessContext) -> Result<Self, ProbeError> {
        let config = hopnav_config::load_file(&context.identity.config_path)?;
        Self::open(context, config.probe.width_px, config.probe.height_px)
    }

    fn step(&mut self, _context: &ProcessContext, tick: &FrameTick) -> Result<(), ProbeError> {
        let frame_index = tick.stamp.frame_index;
        let (width_px, height_px) = (self.width_px, self.height_px);
        let fill_started_ns = monotonic_now_ns();
        let len = width_px as usize * height_px as usize;
        self.publisher.send_from_fn(
            len,
            |header| {
                *header = ImageHeader {
                    intrinsics: CameraIntrinsics {
                        fx_px: 1.0,
                        fy_px: 1.0,
                        cx_px: f64::from(width_px) / 2.0,
                        cy_px: f64::from(height_px) / 2.0,
                    },
                    width_px,
                    height_px,
                    stride_bytes: width_px,
                    format: PixelFormat::Mono8.code(),
                    view_count: 1,
                    ..ImageHeader::default()
                };
                header.stamp.frame_index = frame_index;
                header.stamp.sim_time_ns = tick.stamp.sim_time_ns;
                // Called after the pixels are written: this is the loan-to-filled time.
                header.fill_time_ns = monotonic_now_ns().saturating_sub(fill_started_ns);
            },
            |index| pattern_byte(frame_index, index),
        )?;
        Ok(())
    }
}
