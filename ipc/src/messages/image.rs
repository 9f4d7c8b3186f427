//! camera → VO: image user header. Pixels travel as a `[u8]` slice drawn in place.

use iceoryx2::prelude::ZeroCopySend;

use super::{SampleStamp, coded_enum};

coded_enum! {
    /// Pixel layout of an image slice.
    PixelFormat {
        /// One 8-bit grey value per pixel.
        Mono8 = 1,
    }
}

/// Pinhole intrinsics of the camera that drew an image, pixels.
#[repr(C)]
#[derive(Debug, Default, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("hopnav::CameraIntrinsics")]
pub struct CameraIntrinsics {
    /// Focal length along x, pixels.
    pub fx_px: f64,
    /// Focal length along y, pixels.
    pub fy_px: f64,
    /// Principal point x, pixels.
    pub cx_px: f64,
    /// Principal point y, pixels.
    pub cy_px: f64,
}

/// User header of an image sample. A stereo pair is two views stacked in one slice, left first.
#[repr(C)]
#[derive(Debug, Default, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("hopnav::ImageHeader")]
pub struct ImageHeader {
    /// Frame identity and timing.
    pub stamp: SampleStamp,
    /// Intrinsics shared by all views in the sample.
    pub intrinsics: CameraIntrinsics,
    /// `body_from_camera` of the (left) camera on its robot: the mount, known onboard.
    pub body_from_camera: super::Pose3,
    /// Stereo baseline along camera x, metres (0 for mono).
    pub baseline_m: f64,
    /// Time the producer spent drawing or filling the pixels, nanoseconds.
    pub fill_time_ns: u64,
    /// Width of one view, pixels.
    pub width_px: u32,
    /// Height of one view, pixels.
    pub height_px: u32,
    /// Bytes from one row to the next.
    pub stride_bytes: u32,
    /// A [`PixelFormat`] code.
    pub format: u32,
    /// Views in the slice: 1 for mono, 2 for a stereo pair.
    pub view_count: u32,
    /// A [`Robot`](super::Robot) code: whose camera.
    pub robot: u32,
}

impl ImageHeader {
    /// Bytes one view occupies.
    pub fn view_len_bytes(&self) -> usize {
        (self.stride_bytes as usize).saturating_mul(self.height_px as usize)
    }

    /// Bytes the whole slice must hold (saturates instead of overflowing on corrupt headers).
    pub fn expected_len_bytes(&self) -> usize {
        self.view_len_bytes()
            .saturating_mul(self.view_count as usize)
    }
}

const _: () = assert!(size_of::<CameraIntrinsics>() == 32);
const _: () = assert!(size_of::<ImageHeader>() == 160);
