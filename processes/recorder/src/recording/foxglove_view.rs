//! hopnav's samples as Foxglove's well-known messages, so a recording opens in Foxglove with
//! images, clouds, both robots' frames (estimated and true), the map and the path.
//!
//! Plain functions from a sample to a message; the recording writes them beside the lossless
//! hopnav channels. Everything is in one fixed frame, [`WORLD_FRAME`] (the mission's world:
//! x east, y north, z up, metres).

use foxglove::messages::{
    FrameTransform, FrameTransforms, Grid, PackedElementField, PointCloud, Pose, PosesInFrame,
    Quaternion, RawImage, Timestamp, Vector2, Vector3, packed_element_field::NumericType,
};
use hopnav_ipc::messages::{
    BodyStates, CellClass, CellUpdate, CloudHeader, FeaturePoint, ImageHeader, MapHeader,
    PathHeader, PathPoint, PixelFormat, Pose3, PoseEstimate, Robot,
};

/// The fixed frame every position is given in.
pub const WORLD_FRAME: &str = "world";

/// A sample's simulated time as a Foxglove timestamp.
fn timestamp(sim_time_ns: u64) -> Timestamp {
    let seconds = u32::try_from(sim_time_ns / 1_000_000_000).unwrap_or(u32::MAX);
    Timestamp::new(seconds, (sim_time_ns % 1_000_000_000) as u32)
}

fn pose(pose: &Pose3) -> Pose {
    let [x, y, z] = pose.position_m;
    let [qx, qy, qz, qw] = pose.orientation_xyzw;
    Pose {
        position: Some(Vector3 { x, y, z }),
        orientation: Some(Quaternion {
            x: qx,
            y: qy,
            z: qz,
            w: qw,
        }),
    }
}

fn transform(sim_time_ns: u64, child: &str, world_from_child: &Pose3) -> FrameTransform {
    let Pose {
        position,
        orientation,
    } = pose(world_from_child);
    FrameTransform {
        timestamp: Some(timestamp(sim_time_ns)),
        parent_frame_id: WORLD_FRAME.to_owned(),
        child_frame_id: child.to_owned(),
        translation: position,
        rotation: orientation,
    }
}

/// The frame name of a robot's estimate (`…_vo`) or its truth (`…_truth`).
fn robot_frame(robot: Robot, truth: bool) -> String {
    let name = match robot {
        Robot::Jumper => "jumper",
        Robot::Rover => "rover",
    };
    format!("{name}_{}", if truth { "truth" } else { "vo" })
}

/// One view (`view` 0 = left or mono, 1 = right) of an image sample, or `None` when the
/// sample has no such view, too few pixels for it, or a pixel format Foxglove is not told of.
pub fn image(header: &ImageHeader, pixels: &[u8], view: u32) -> Option<RawImage> {
    let encoding = match PixelFormat::from_code(header.format)? {
        PixelFormat::Mono8 => "mono8",
    };
    if view >= header.view_count {
        return None;
    }
    let length = header.view_len_bytes();
    let start = length.checked_mul(view as usize)?;
    let data = pixels.get(start..start.checked_add(length)?)?;
    let robot = Robot::from_code(header.robot).unwrap_or(Robot::Rover);
    let camera = match (robot, header.view_count, view) {
        (Robot::Jumper, _, _) => "jumper_camera",
        (Robot::Rover, 1, _) | (Robot::Rover, _, 0) => "rover_left_camera",
        (Robot::Rover, _, _) => "rover_right_camera",
    };
    Some(RawImage {
        timestamp: Some(timestamp(header.stamp.sim_time_ns)),
        frame_id: camera.to_owned(),
        width: header.width_px,
        height: header.height_px,
        encoding: encoding.to_owned(),
        step: header.stride_bytes,
        data: data.to_vec().into(),
    })
}

/// A feature cloud in the world frame: x, y, z, height above the local ground and depth
/// sigma of each point, as 32-bit floats.
pub fn cloud(header: &CloudHeader, points: &[FeaturePoint]) -> PointCloud {
    const FIELDS: [&str; 5] = ["x", "y", "z", "height_above_ground_m", "depth_sigma_m"];
    let mut data = Vec::with_capacity(points.len() * FIELDS.len() * 4);
    for point in points {
        let [x, y, z] = point.position_m;
        for value in [x, y, z, point.height_above_ground_m, point.depth_sigma_m] {
            data.extend_from_slice(&value.to_le_bytes());
        }
    }
    PointCloud {
        timestamp: Some(timestamp(header.stamp.sim_time_ns)),
        frame_id: WORLD_FRAME.to_owned(),
        pose: Some(pose(&Pose3::default())),
        point_stride: (FIELDS.len() * 4) as u32,
        fields: float_fields(&FIELDS),
        data: data.into(),
    }
}

fn float_fields(names: &[&str]) -> Vec<PackedElementField> {
    names
        .iter()
        .enumerate()
        .map(|(index, name)| PackedElementField {
            name: (*name).to_owned(),
            offset: (index * 4) as u32,
            r#type: NumericType::Float32 as i32,
        })
        .collect()
}

/// The estimated pose of a robot as the transform world → `<robot>_vo`.
pub fn estimate(pose: &PoseEstimate) -> Option<FrameTransforms> {
    let robot = Robot::from_code(pose.robot)?;
    Some(FrameTransforms {
        transforms: vec![transform(
            pose.stamp.sim_time_ns,
            &robot_frame(robot, false),
            &pose.world_from_body,
        )],
    })
}

/// Both robots' true poses as the transforms world → `jumper_truth`, `rover_truth`.
pub fn truth(states: &BodyStates) -> FrameTransforms {
    let time_ns = states.stamp.sim_time_ns;
    FrameTransforms {
        transforms: vec![
            transform(
                time_ns,
                &robot_frame(Robot::Jumper, true),
                &states.jumper.world_from_body,
            ),
            transform(
                time_ns,
                &robot_frame(Robot::Rover, true),
                &states.rover.world_from_body,
            ),
        ],
    }
}

/// What a cell shows in the grid: its class code, so a colour map tells them apart.
fn cell_value(cell: &CellUpdate) -> u8 {
    CellClass::from_code(cell.class).map_or(0, |class| class.code() as u8)
}

/// A whole-map snapshot as a grid of one `class` byte per cell (the [`CellClass`] codes:
/// 0 unknown, 1 free, 2 obstacle, 3 inflated, 4 lethal, 5 uncertain), row 0 at the map's
/// origin. `None` when the header's grid is empty or too large to draw.
pub fn map(header: &MapHeader, cells: &[CellUpdate]) -> Option<Grid> {
    let (width, height) = (header.width_cells as usize, header.height_cells as usize);
    let total = width
        .checked_mul(height)
        .filter(|&n| n > 0 && n <= 1 << 24)?;
    let mut data = vec![0u8; total];
    for cell in cells {
        let (x, y) = (cell.x as usize, cell.y as usize);
        if x < width && y < height {
            data[y * width + x] = cell_value(cell);
        }
    }
    let origin = Pose3 {
        position_m: [header.origin_x_m, header.origin_y_m, 0.0],
        ..Pose3::default()
    };
    Some(Grid {
        timestamp: Some(timestamp(header.stamp.sim_time_ns)),
        frame_id: WORLD_FRAME.to_owned(),
        pose: Some(pose(&origin)),
        column_count: header.width_cells,
        cell_size: Some(Vector2 {
            x: header.cell_size_m,
            y: header.cell_size_m,
        }),
        row_stride: header.width_cells,
        cell_stride: 1,
        fields: vec![PackedElementField {
            name: "class".to_owned(),
            offset: 0,
            r#type: NumericType::Uint8 as i32,
        }],
        data: data.into(),
    })
}

/// The planned path as poses on the ground plane (z = 0; the 3D panel draws it as a line).
pub fn path(header: &PathHeader, points: &[PathPoint]) -> PosesInFrame {
    PosesInFrame {
        timestamp: Some(timestamp(header.stamp.sim_time_ns)),
        frame_id: WORLD_FRAME.to_owned(),
        poses: points
            .iter()
            .map(|point| {
                pose(&Pose3 {
                    position_m: [point.x_m, point.y_m, 0.0],
                    ..Pose3::default()
                })
            })
            .collect(),
    }
}

#[cfg(test)]
mod tests {
    use hopnav_ipc::messages::SampleStamp;

    use super::*;

    fn stamp() -> SampleStamp {
        SampleStamp {
            sim_time_ns: 12_500_000_000,
            ..SampleStamp::default()
        }
    }

    #[test]
    fn a_stereo_pair_gives_its_right_view_and_no_third() {
        let header = ImageHeader {
            stamp: stamp(),
            width_px: 2,
            height_px: 2,
            stride_bytes: 2,
            view_count: 2,
            robot: Robot::Rover.code(),
            format: PixelFormat::Mono8.code(),
            ..ImageHeader::default()
        };
        let pixels = [1, 2, 3, 4, 5, 6, 7, 8];
        let right = image(&header, &pixels, 1).expect("right view");
        assert_eq!(&right.data[..], &[5, 6, 7, 8]);
        assert_eq!(right.frame_id, "rover_right_camera");
        assert_eq!(right.timestamp, Some(Timestamp::new(12, 500_000_000)));
        assert!(image(&header, &pixels, 2).is_none());
        assert!(image(&header, &pixels[..6], 1).is_none(), "short slice");
        let unknown_format = ImageHeader {
            format: 99,
            ..header
        };
        assert!(image(&unknown_format, &pixels, 0).is_none());
    }

    #[test]
    fn a_cloud_packs_five_floats_per_point() {
        let header = CloudHeader {
            stamp: stamp(),
            ..CloudHeader::default()
        };
        let point = FeaturePoint {
            position_m: [1.0, 2.0, 3.0],
            height_above_ground_m: 0.25,
            depth_sigma_m: 0.02,
            ..FeaturePoint::default()
        };
        let cloud = cloud(&header, &[point, point]);
        assert_eq!(cloud.point_stride, 20);
        assert_eq!(cloud.data.len(), 40);
        assert_eq!(cloud.fields[3].name, "height_above_ground_m");
        assert_eq!(cloud.fields[3].offset, 12);
        assert_eq!(&cloud.data[4..8], &2.0f32.to_le_bytes());
    }

    #[test]
    fn the_map_grid_holds_each_cells_class_at_its_place() {
        let header = MapHeader {
            stamp: stamp(),
            origin_x_m: -8.0,
            origin_y_m: -4.0,
            cell_size_m: 0.25,
            width_cells: 4,
            height_cells: 3,
            ..MapHeader::default()
        };
        let lethal = CellUpdate {
            x: 3,
            y: 2,
            class: CellClass::Lethal.code(),
            ..CellUpdate::default()
        };
        let off_grid = CellUpdate { x: 9, ..lethal };
        let grid = map(&header, &[lethal, off_grid]).expect("grid");
        assert_eq!(grid.data.len(), 12);
        assert_eq!(grid.data[11], 4);
        assert_eq!(grid.data.iter().filter(|&&v| v != 0).count(), 1);
        let origin = grid.pose.and_then(|p| p.position).expect("origin");
        assert_eq!((origin.x, origin.y), (-8.0, -4.0));
        let empty = MapHeader {
            width_cells: 0,
            ..header
        };
        assert!(map(&empty, &[]).is_none());
    }

    #[test]
    fn poses_become_transforms_from_the_world_frame() {
        let estimate = estimate(&PoseEstimate {
            stamp: stamp(),
            robot: Robot::Jumper.code(),
            world_from_body: Pose3 {
                position_m: [1.0, 2.0, 3.0],
                ..Pose3::default()
            },
            ..PoseEstimate::default()
        })
        .expect("robot known");
        let only = &estimate.transforms[0];
        assert_eq!(
            (only.parent_frame_id.as_str(), only.child_frame_id.as_str()),
            ("world", "jumper_vo")
        );
        assert_eq!(only.translation.as_ref().map(|t| t.z), Some(3.0));
        let unknown = PoseEstimate {
            robot: 99,
            ..PoseEstimate::default()
        };
        assert!(super::estimate(&unknown).is_none());
        let truth = truth(&BodyStates::default());
        assert_eq!(truth.transforms[1].child_frame_id, "rover_truth");
    }
}
