//! Any bytes in shared memory, read as any message or slice header with any slice after it,
//! give `Ok` or a `Rejection`; `Ok` means the checks the consumers rely on hold.
//!
//! Input: one selector byte, then the header's bytes, then the slice's bytes (whole elements;
//! a trailing partial element is dropped). Short inputs are zero-padded.
#![no_main]

use std::mem::size_of;

use hopnav_ipc::messages::{
    AltimeterSample, BodyStates, CellClass, CellUpdate, CloudHeader, Control, DriveCommand,
    FeaturePoint, FrameTick, Heartbeat, HopLaunch, ImageHeader, ImuSample, JumpRequest, MapHeader,
    PathHeader, PathPoint, PhysicsState, PoseEstimate,
};
use hopnav_ipc::validate::{Message, SequenceGuard, SliceHeader};
use libfuzzer_sys::fuzz_target;

// The raw-bytes messages are those of ipc's corrupt-sample tests: one safety argument.
#[path = "../../ipc/tests/support/plain_old_data.rs"]
mod plain_old_data;

use plain_old_data::{PlainOldData, take};

/// The whole elements in `bytes`.
fn elements<T: PlainOldData>(mut bytes: &[u8]) -> Vec<T> {
    let mut out = Vec::with_capacity(bytes.len() / size_of::<T>());
    while bytes.len() >= size_of::<T>() {
        let (element, rest) = take::<T>(bytes);
        out.push(element);
        bytes = rest;
    }
    out
}

fn message<T: PlainOldData + Message>(bytes: &[u8]) {
    let (message, _) = take::<T>(bytes);
    let _ = message.validate();
}

fuzz_target!(|data: &[u8]| {
    let Some((&selector, bytes)) = data.split_first() else {
        return;
    };
    match selector % 16 {
        0 => message::<FrameTick>(bytes),
        1 => message::<Heartbeat>(bytes),
        2 => message::<BodyStates>(bytes),
        3 => message::<AltimeterSample>(bytes),
        4 => message::<ImuSample>(bytes),
        5 => message::<PoseEstimate>(bytes),
        6 => message::<DriveCommand>(bytes),
        7 => message::<JumpRequest>(bytes),
        8 => message::<HopLaunch>(bytes),
        9 => message::<Control>(bytes),
        10 => {
            let (header, pixels) = take::<ImageHeader>(bytes);
            let _ = header.view_len_bytes();
            if header.validate_slice(pixels).is_ok() {
                assert_eq!(pixels.len(), header.expected_len_bytes());
                assert!(header.stride_bytes >= header.width_px && header.height_px > 0);
            }
        }
        11 => {
            let (header, rest) = take::<CloudHeader>(bytes);
            let points = elements::<FeaturePoint>(rest);
            if header.validate_slice(&points).is_ok() {
                assert_eq!(header.point_count as usize, points.len());
                assert!(points.iter().all(FeaturePoint::is_valid));
            }
        }
        12 => {
            let (header, rest) = take::<MapHeader>(bytes);
            let cells = elements::<CellUpdate>(rest);
            if header.validate_slice(&cells).is_ok() {
                assert_eq!(header.update_count as usize, cells.len());
                assert!(cells.iter().all(|cell| cell.x < header.width_cells
                    && cell.y < header.height_cells
                    && CellClass::from_code(cell.class).is_some()));
            }
        }
        13 => {
            let (header, rest) = take::<PathHeader>(bytes);
            let points = elements::<PathPoint>(rest);
            if header.validate_slice(&points).is_ok() {
                assert_eq!(header.validate(), Ok(()));
                assert_eq!(header.point_count as usize, points.len());
            }
        }
        14 => message::<PhysicsState>(bytes),
        _ => {
            // A sequence of (origin, sequence) pairs through a small guard.
            let (capacity, rest) = rest_u8(bytes);
            let mut guard = SequenceGuard::new(usize::from(capacity % 8));
            for chunk in rest.chunks_exact(9) {
                let sequence = u64::from_le_bytes(chunk[1..].try_into().expect("8 bytes"));
                let _ = guard.check(chunk[0] % 8, sequence);
            }
        }
    }
});

fn rest_u8(bytes: &[u8]) -> (u8, &[u8]) {
    match bytes.split_first() {
        Some((&first, rest)) => (first, rest),
        None => (0, bytes),
    }
}
