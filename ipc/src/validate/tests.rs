//! Tests of the `validate` module.

use super::*;
use crate::messages::{CameraIntrinsics, Pose3};

#[path = "../../tests/support/image_header.rs"]
mod image_header_fixture;

use image_header_fixture::image_header;

#[test]
fn image_dims_must_match_slice_length() {
    let header = image_header(4, 3, 2);
    assert_eq!(header.validate_slice(&[0; 24]), Ok(()));
    assert_eq!(
        header.validate_slice(&[0; 23]),
        Err(Rejection::LengthMismatch {
            expected: 24,
            actual: 23
        })
    );
}

#[test]
fn image_rejects_bad_codes_dims_and_nan() {
    let mut header = image_header(4, 3, 1);
    header.format = 99;
    assert!(matches!(
        header.validate_slice(&[0; 12]),
        Err(Rejection::UnknownCode {
            field: "format",
            ..
        })
    ));
    let mut header = image_header(4, 3, 1);
    header.stride_bytes = 2;
    assert!(matches!(
        header.validate(),
        Err(Rejection::BadDimensions(_))
    ));
    let mut header = image_header(0, 3, 1);
    assert!(header.validate().is_err());
    header = image_header(4, 3, 3);
    assert!(header.validate().is_err());
    header = image_header(4, 3, 1);
    header.intrinsics.fx_px = f64::NAN;
    assert_eq!(header.validate(), Err(Rejection::NonFinite("intrinsics")));
}

#[test]
fn cloud_rejects_non_finite_points_and_count_mismatch() {
    let header = CloudHeader {
        point_count: 2,
        robot: Robot::Rover.code(),
        world_from_camera: Pose3::default(),
        ..CloudHeader::default()
    };
    let mut points = [FeaturePoint::default(); 2];
    assert_eq!(header.validate_slice(&points), Ok(()));
    assert!(header.validate_slice(&points[..1]).is_err());
    points[1].position_m[2] = f32::INFINITY;
    assert_eq!(
        header.validate_slice(&points),
        Err(Rejection::BadElement {
            index: 1,
            reason: "non-finite position or sigma"
        })
    );
}

#[test]
fn map_rejects_cells_outside_grid() {
    let header = MapHeader {
        cell_size_m: 0.5,
        width_cells: 4,
        height_cells: 4,
        update_count: 1,
        ..MapHeader::default()
    };
    let inside = CellUpdate {
        x: 3,
        y: 3,
        class: CellClass::Obstacle.code(),
        ..CellUpdate::default()
    };
    assert_eq!(header.validate_slice(&[inside]), Ok(()));
    let outside = CellUpdate { x: 4, ..inside };
    assert!(header.validate_slice(&[outside]).is_err());
}

#[test]
fn pose_rejects_non_unit_quaternion() {
    let mut pose = PoseEstimate {
        robot: Robot::Jumper.code(),
        ..PoseEstimate::default()
    };
    assert_eq!(pose.validate(), Ok(()));
    pose.world_from_body.orientation_xyzw = [0.0, 0.0, 0.0, 2.0];
    assert!(pose.validate().is_err());
}

#[test]
fn physics_state_rejects_bad_phase_flags_and_nan() {
    let state = PhysicsState::default();
    assert_eq!(state.validate(), Ok(()));
    let mut bad = state;
    bad.jumper.phase = 7;
    assert!(matches!(
        bad.validate(),
        Err(Rejection::UnknownCode {
            field: "jumper.phase",
            ..
        })
    ));
    bad = state;
    bad.rover.arrived = 2;
    assert!(matches!(
        bad.validate(),
        Err(Rejection::UnknownCode { field: "flag", .. })
    ));
    bad = state;
    bad.rover.steer_angles_rad[3] = f64::NAN;
    assert_eq!(
        bad.validate(),
        Err(Rejection::NonFinite("rover.steer_angles_rad"))
    );
    bad = state;
    bad.jumper.landing_position_m[0] = f64::INFINITY;
    assert!(bad.validate().is_err());
}

#[test]
fn sequence_guard_refuses_repeats_but_accepts_new_origins() {
    let mut guard = SequenceGuard::new(2);
    assert!(guard.check(1_u32, 0).is_ok());
    assert!(guard.check(1, 1).is_ok());
    assert!(guard.check(1, 1).is_err());
    assert!(guard.check(1, 0).is_err());
    assert!(
        guard.check(2, 0).is_ok(),
        "a restarted publisher starts over"
    );
    assert!(guard.check(1, 2).is_ok());
    assert!(guard.check(3, 5).is_ok(), "evicts the least recent origin");
    assert!(guard.check(2, 0).is_ok(), "origin 2 was forgotten");
}

#[test]
fn arbitrary_headers_never_panic() {
    let mut state = 0x1234_5678_9abc_def1_u64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    for _ in 0..10_000 {
        let header = ImageHeader {
            width_px: next() as u32,
            height_px: next() as u32,
            stride_bytes: next() as u32,
            view_count: next() as u32 % 4,
            format: next() as u32 % 3,
            intrinsics: CameraIntrinsics {
                fx_px: f64::from_bits(next()),
                ..CameraIntrinsics::default()
            },
            ..ImageHeader::default()
        };
        let _ = header.validate_slice(&[0u8; 64]);
        let map = MapHeader {
            width_cells: next() as u32,
            height_cells: next() as u32,
            update_count: next() as u32 % 3,
            cell_size_m: f64::from_bits(next()),
            ..MapHeader::default()
        };
        let _ = map.validate_slice(&[CellUpdate {
            x: next() as u32,
            class: next() as u32,
            ..CellUpdate::default()
        }]);
    }
}
