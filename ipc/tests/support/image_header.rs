//! A valid Mono8 image header for tests. Shared by the `validate` unit tests and
//! `ipc/tests/transport.rs` (through `#[path]`); the including module has the message types
//! in scope.

use super::{CameraIntrinsics, ImageHeader, PixelFormat, Robot};

/// A packed Mono8 header of `view_count` views of `width_px × height_px` from the jumper.
pub fn image_header(width_px: u32, height_px: u32, view_count: u32) -> ImageHeader {
    ImageHeader {
        intrinsics: CameraIntrinsics {
            fx_px: 386.3,
            fy_px: 386.3,
            cx_px: 160.0,
            cy_px: 160.0,
        },
        width_px,
        height_px,
        stride_bytes: width_px,
        format: PixelFormat::Mono8.code(),
        view_count,
        robot: Robot::Jumper.code(),
        ..ImageHeader::default()
    }
}
