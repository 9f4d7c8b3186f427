//! A consumer must survive any sample a crashed or faulty producer leaves in shared memory:
//! every bit pattern of every message and slice header gives `Ok` or a `Rejection`, never a
//! panic, and `Ok` means what it promises. The codec must refuse arbitrary bytes the same way.
//!
//! Messages are built from raw bytes (every field is an integer or a float, so any bit pattern
//! is a value) and, to get past the first check, from valid defaults with a few bytes
//! overwritten and with slice lengths that match the header.

use std::mem::size_of;

use hopnav_ipc::codec::{self, CodecError};
use hopnav_ipc::messages::{
    AltimeterSample, BodyStates, CellClass, CellUpdate, CloudHeader, Control, DriveCommand,
    FeaturePoint, FrameTick, Heartbeat, HopLaunch, ImageHeader, ImuSample, JumpRequest, MapHeader,
    MissionState, PathHeader, PathPoint, PhysicsState, PixelFormat, PoseEstimate, Robot,
};
use hopnav_ipc::validate::{Message, Rejection, SequenceGuard, SliceHeader};
use proptest::prelude::*;

#[path = "support/plain_old_data.rs"]
mod plain_old_data;

use plain_old_data::{PlainOldData, take};

#[path = "support/framed.rs"]
mod framed;

use framed::{Framed, Kind};

/// A `T` holding `bytes` (zero-padded or truncated to its size).
fn from_bytes<T: PlainOldData>(bytes: &[u8]) -> T {
    take::<T>(bytes).0
}

/// The bytes of `value`.
fn to_bytes<T: PlainOldData>(value: &T) -> Vec<u8> {
    // SAFETY: `value` is a live reference to `size_of::<T>()` bytes; `PlainOldData` types
    // have no padding (every message file asserts its size equals the sum of its fields), so
    // all of them are initialized.
    unsafe { std::slice::from_raw_parts((value as *const T).cast::<u8>(), size_of::<T>()) }.to_vec()
}

/// Values that hit the edges of numeric checks when written over a field.
fn nasty_bytes() -> impl Strategy<Value = Vec<u8>> {
    prop_oneof![
        Just(f64::NAN.to_le_bytes().to_vec()),
        Just(f64::INFINITY.to_le_bytes().to_vec()),
        Just(f64::NEG_INFINITY.to_le_bytes().to_vec()),
        Just((-0.0_f64).to_le_bytes().to_vec()),
        Just(f64::MAX.to_le_bytes().to_vec()),
        Just(f64::MIN_POSITIVE.to_le_bytes().to_vec()),
        Just(f32::NAN.to_le_bytes().to_vec()),
        Just(f32::INFINITY.to_le_bytes().to_vec()),
        Just(u32::MAX.to_le_bytes().to_vec()),
        Just(u64::MAX.to_le_bytes().to_vec()),
        Just(0_u32.to_le_bytes().to_vec()),
        Just(1_u32.to_le_bytes().to_vec()),
        Just(2_u32.to_le_bytes().to_vec()),
        Just(3_u32.to_le_bytes().to_vec()),
        Just(4_u32.to_le_bytes().to_vec()),
        prop::collection::vec(any::<u8>(), 1..9),
    ]
}

/// Arbitrary bit patterns of `T`, and valid-looking `base` values with a few fields (aligned
/// 4-byte words, as every field starts on one) overwritten by edge values.
fn corrupted<T: PlainOldData + std::fmt::Debug>(base: T) -> impl Strategy<Value = T> {
    let size = size_of::<T>();
    let base_bytes = to_bytes(&base);
    prop_oneof![
        prop::collection::vec(any::<u8>(), size).prop_map(|bytes| from_bytes::<T>(&bytes)),
        Just(base),
        prop::collection::vec((0..size / 4, nasty_bytes()), 1..4).prop_map(move |patches| {
            let mut bytes = base_bytes.clone();
            for (word, patch) in patches {
                let start = word * 4;
                let end = (start + patch.len()).min(size);
                bytes[start..end].copy_from_slice(&patch[..end - start]);
            }
            from_bytes::<T>(&bytes)
        }),
    ]
}

fn elements<T: PlainOldData + std::fmt::Debug>(
    valid: T,
    max_len: usize,
) -> impl Strategy<Value = Vec<T>> {
    prop::collection::vec(
        prop_oneof![3 => Just(valid), 1 => corrupted(valid)],
        0..max_len,
    )
}

fn pose_estimate() -> PoseEstimate {
    PoseEstimate {
        robot: Robot::Rover.code(),
        confidence: 0.9,
        scale: 1.0,
        ..PoseEstimate::default()
    }
}

fn image_header() -> ImageHeader {
    let mut header = ImageHeader {
        width_px: 4,
        height_px: 3,
        stride_bytes: 4,
        format: PixelFormat::Mono8.code(),
        view_count: 2,
        robot: Robot::Rover.code(),
        ..ImageHeader::default()
    };
    header.intrinsics.fx_px = 386.3;
    header.intrinsics.fy_px = 386.3;
    header
}

fn cloud_header() -> CloudHeader {
    CloudHeader {
        point_count: 3,
        robot: Robot::Jumper.code(),
        ..CloudHeader::default()
    }
}

fn map_header() -> MapHeader {
    MapHeader {
        cell_size_m: 0.5,
        width_cells: 8,
        height_cells: 8,
        update_count: 3,
        ..MapHeader::default()
    }
}

fn path_header() -> PathHeader {
    PathHeader {
        point_count: 3,
        state: MissionState::Driving.code(),
        ..PathHeader::default()
    }
}

fn cell() -> CellUpdate {
    CellUpdate {
        x: 2,
        y: 5,
        class: CellClass::Free.code(),
        ..CellUpdate::default()
    }
}

fn path_point() -> PathPoint {
    PathPoint {
        x_m: 1.0,
        y_m: -2.0,
    }
}

/// A slice `header` accepts (after `set_count` announced the slice's true length, if given)
/// is valid itself, announces `count` elements, and every element is `element_ok`.
fn accepted_slice_keeps_its_promises<H: SliceHeader>(
    mut header: H,
    elements: &[H::Element],
    set_count: Option<fn(&mut H, u32)>,
    count: impl Fn(&H) -> u32,
    element_ok: impl Fn(&H, &H::Element) -> bool,
) -> Result<(), TestCaseError> {
    if let Some(set_count) = set_count {
        set_count(&mut header, elements.len() as u32);
    }
    if header.validate_slice(elements).is_ok() {
        prop_assert_eq!(header.validate(), Ok(()));
        prop_assert_eq!(count(&header) as usize, elements.len());
        prop_assert!(elements.iter().all(|element| element_ok(&header, element)));
    }
    Ok(())
}

/// Checks one message type: arbitrary and corrupted values never panic in `validate`.
macro_rules! message_never_panics {
    ($name:ident, $type:ty, $base:expr) => {
        proptest! {
            #[test]
            fn $name(message in corrupted::<$type>($base)) {
                let _ = message.validate();
                let _ = message.stamp();
            }
        }
    };
}

message_never_panics!(frame_tick, FrameTick, FrameTick::default());
message_never_panics!(heartbeat, Heartbeat, Heartbeat::default());
message_never_panics!(body_states, BodyStates, BodyStates::default());
message_never_panics!(altimeter, AltimeterSample, AltimeterSample::default());
message_never_panics!(imu, ImuSample, ImuSample::default());
message_never_panics!(pose_estimate_msg, PoseEstimate, pose_estimate());
message_never_panics!(drive_command, DriveCommand, DriveCommand::default());
message_never_panics!(jump_request, JumpRequest, JumpRequest::default());
message_never_panics!(hop_launch, HopLaunch, HopLaunch::default());
message_never_panics!(control, Control, Control::default());
message_never_panics!(physics_state, PhysicsState, PhysicsState::default());

proptest! {
    #[test]
    fn image_slice(
        mut header in corrupted(image_header()),
        pixels in prop::collection::vec(any::<u8>(), 0..64),
        match_len in any::<bool>(),
    ) {
        let _ = header.validate();
        let _ = header.view_len_bytes();
        let expected = header.expected_len_bytes();
        let pixels = if match_len && expected <= 4096 { vec![7; expected] } else { pixels };
        match header.validate_slice(&pixels) {
            Ok(()) => {
                prop_assert_eq!(header.validate(), Ok(()));
                prop_assert_eq!(pixels.len(), expected);
                prop_assert!(header.width_px > 0 && header.height_px > 0);
                prop_assert!(header.stride_bytes >= header.width_px);
                prop_assert!(header.view_count == 1 || header.view_count == 2);
            }
            Err(Rejection::LengthMismatch { expected: announced, actual }) => {
                prop_assert_eq!(announced, expected);
                prop_assert_eq!(actual, pixels.len());
            }
            Err(_) => {}
        }
        // Dimensions at the top of the range saturate instead of overflowing.
        header.stride_bytes = u32::MAX;
        header.height_px = u32::MAX;
        header.view_count = u32::MAX;
        let _ = header.validate_slice(&pixels);
    }

    #[test]
    fn cloud_slice(
        header in corrupted(cloud_header()),
        points in elements(FeaturePoint::default(), 8),
        match_len in any::<bool>(),
    ) {
        accepted_slice_keeps_its_promises(
            header,
            &points,
            match_len.then_some(|h: &mut CloudHeader, n| h.point_count = n),
            |h| h.point_count,
            |_, point| point.is_valid(),
        )?;
    }

    #[test]
    fn map_slice(
        header in corrupted(map_header()),
        cells in elements(cell(), 8),
        match_len in any::<bool>(),
    ) {
        accepted_slice_keeps_its_promises(
            header,
            &cells,
            match_len.then_some(|h: &mut MapHeader, n| h.update_count = n),
            |h| h.update_count,
            |h, cell| {
                cell.x < h.width_cells
                    && cell.y < h.height_cells
                    && CellClass::from_code(cell.class).is_some()
            },
        )?;
    }

    #[test]
    fn path_slice(
        header in corrupted(path_header()),
        points in elements(path_point(), 8),
        match_len in any::<bool>(),
    ) {
        accepted_slice_keeps_its_promises(
            header,
            &points,
            match_len.then_some(|h: &mut PathHeader, n| h.point_count = n),
            |h| h.point_count,
            |_, p| p.x_m.is_finite() && p.y_m.is_finite(),
        )?;
    }

    /// The guard behaves like a small least-recently-used table of last sequences.
    #[test]
    fn sequence_guard_matches_model(
        capacity in 0_usize..5,
        events in prop::collection::vec((0_u8..6, prop_oneof![0_u64..8, any::<u64>()]), 0..64),
    ) {
        let mut guard = SequenceGuard::new(capacity);
        let mut model: Vec<(u8, u64)> = Vec::new();
        for (origin, sequence) in events {
            let expected = match model.iter().position(|(o, _)| *o == origin) {
                Some(index) => {
                    let (_, last) = model.remove(index);
                    if sequence <= last {
                        model.push((origin, last));
                        Err(Rejection::StaleSequence { last, received: sequence })
                    } else {
                        model.push((origin, sequence));
                        Ok(())
                    }
                }
                None => {
                    if model.len() == capacity.max(1) {
                        model.remove(0);
                    }
                    model.push((origin, sequence));
                    Ok(())
                }
            };
            prop_assert_eq!(guard.check(origin, sequence), expected);
        }
    }
}

proptest! {
    #[test]
    fn codec_decode_arbitrary_bytes(bytes in prop::collection::vec(any::<u8>(), 0..512)) {
        let _ = codec::decode::<Framed>(&bytes);
        let _ = codec::decode::<Vec<String>>(&bytes);
        let _ = codec::decode::<(u8, Kind)>(&bytes);
    }

    /// A length prefix promising more than the limit (or than the input) is an error, not an
    /// allocation of that size.
    #[test]
    fn codec_decode_huge_length_prefix(
        length in prop_oneof![Just(u64::MAX), Just(codec::MAX_DECODE_BYTES as u64 + 1), any::<u64>()],
        tail in prop::collection::vec(any::<u8>(), 0..32),
    ) {
        let mut bytes = length.to_le_bytes().to_vec();
        bytes.extend_from_slice(&tail);
        prop_assert!(codec::decode::<Vec<u8>>(&bytes).is_err() || length as usize == tail.len());
        prop_assert!(codec::decode::<String>(&bytes).is_err() || length as usize == tail.len());
        if length > codec::MAX_DECODE_BYTES as u64 {
            prop_assert!(matches!(
                codec::decode::<Vec<Vec<u64>>>(&bytes),
                Err(CodecError::Decode(_))
            ));
        }
    }
}

/// Regression: `validate_slice` of a path skipped the header's own checks, so a corrupt
/// mission state code reached the supervisor (which then reset its unreachable timer).
#[test]
fn path_slice_rejects_unknown_state() {
    let header = PathHeader {
        point_count: 0,
        state: 99,
        ..PathHeader::default()
    };
    assert_eq!(
        header.validate_slice(&[]),
        Err(Rejection::UnknownCode {
            field: "state",
            code: 99
        })
    );
}

/// Regression: a guard sized from a corrupt or absurd capacity must not try to reserve it.
#[test]
fn sequence_guard_with_huge_capacity_does_not_preallocate() {
    let mut guard = SequenceGuard::new(usize::MAX);
    assert_eq!(guard.check(1_u32, 1), Ok(()));
    assert!(guard.check(1_u32, 1).is_err());
}

#[test]
fn path_header_with_more_route_changes_than_replans_is_rejected() {
    let header = PathHeader {
        replan_count: 3,
        route_change_count: 4,
        ..path_header()
    };
    assert!(matches!(
        header.validate_slice(&[PathPoint::default(); 3]),
        Err(Rejection::Inconsistent(_))
    ));
    let consistent = PathHeader {
        route_change_count: 3,
        ..header
    };
    assert_eq!(
        consistent.validate_slice(&[PathPoint::default(); 3]),
        Ok(())
    );
}
