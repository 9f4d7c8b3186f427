//! The final map's blocked ground judged over four sets of cells: those the rover's camera
//! had in sight (the headline), those in its field of view hidden or not, the same in sight
//! with the map carried onto the truth by the rover VO's fit, and every mapped cell near the
//! track. Each answers a different "was it the mapper's fault" question; see
//! [`crate::traversability`] for what is counted.

use hopnav_ipc::messages::CellClass;
use hopnav_metrics::trajectory::align::{Similarity, umeyama};
use hopnav_robot::SlopeClass;
use hopnav_supervisor::mission_record::{MissionRecord, RecordedMap};
use nalgebra::{Isometry3, Point3};

use crate::line_of_sight::SeenCells;
use crate::mission::{MissionTruth, RoverCamera};
use crate::traversability::{
    BlockedArea, CameraView, MapCell, NEAR_TRACK_M, Reach, RockOutline, blocked_area,
};

/// The four judgements of one mission's final map (`None` where the truth or the record
/// lacks what one needs).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BlockedAreaJudgements {
    /// Over the cells the camera had in sight within 5 m.
    pub in_sight: Option<BlockedArea>,
    /// Over the cells in its horizontal field of view within 5 m, hidden or not.
    pub in_view: Option<BlockedArea>,
    /// `in_sight` with the map carried onto the truth by the rover VO's ground-plane fit.
    pub in_sight_map_frame: Option<BlockedArea>,
    /// Over every mapped cell within 5 m of the true track.
    pub near_track: Option<BlockedArea>,
}

/// Judges `record`'s final map against `truth` four ways.
pub fn judge_blocked_area(truth: &MissionTruth, record: &MissionRecord) -> BlockedAreaJudgements {
    let (Some(map), Some(rocks)) = (record.map.as_ref(), truth.rock_outlines.as_deref()) else {
        return BlockedAreaJudgements::default();
    };
    let world_cells = map_cells(map, |xy| xy);
    let judge = |cells: &[MapCell], reach: &Reach<'_>| {
        judge_cells(truth, cells, map.cell_size_m, reach, rocks)
    };
    let seen = seen_cells(truth, record);
    let in_sight = seen
        .as_ref()
        .map(|seen| judge(&world_cells, &Reach::InSight(seen)));
    let in_sight_map_frame = seen.as_ref().and_then(|seen| {
        let onto_truth = rover_vo_alignment(record)?;
        let carried = map_cells(map, |[x, y]| {
            let p = onto_truth.apply(&Point3::new(x, y, 0.0));
            [p.x, p.y]
        });
        Some(judge(&carried, &Reach::InSight(seen)))
    });
    let in_view = truth.rover_camera.map(|camera| {
        let views = rover_camera_views(record, &camera);
        let reach = Reach::InView {
            views: &views,
            half_fov_rad: camera.half_fov_rad,
        };
        judge(&world_cells, &reach)
    });
    let track_m: Vec<[f64; 2]> = record.rover_track_m.iter().map(|&(x, y)| [x, y]).collect();
    BlockedAreaJudgements {
        in_sight,
        in_view,
        in_sight_map_frame,
        near_track: Some(judge(&world_cells, &Reach::NearTrack(&track_m))),
    }
}

/// The cells the rover's camera had in sight from its true poses (`None`, with a warning,
/// when the truth has no line of sight or rendering failed).
fn seen_cells(truth: &MissionTruth, record: &MissionRecord) -> Option<SeenCells> {
    let line_of_sight = truth.line_of_sight.as_ref()?;
    let geometry = truth.map_geometry()?;
    let poses = rover_true_poses(record);
    match line_of_sight.seen_cells(poses, &geometry, NEAR_TRACK_M) {
        Ok(seen) => Some(seen),
        Err(error) => {
            eprintln!("warning: {error}; the map is not judged over the cells in sight");
            None
        }
    }
}

/// The rover's true poses the VO was paired with (one a frame while the VO ran).
fn rover_true_poses(record: &MissionRecord) -> impl Iterator<Item = &Isometry3<f64>> {
    record
        .vo
        .iter()
        .filter(|vo| vo.robot == "rover")
        .flat_map(|vo| vo.track.pairs().iter().map(|(_, _, truth)| truth))
}

/// The rigid motion in the ground plane (a turn about z and a shift) that best carries the
/// rover's VO estimates onto its true positions (`None` with fewer than three pairs or a
/// rover that did not move).
fn rover_vo_alignment(record: &MissionRecord) -> Option<Similarity> {
    ground_plane_alignment(
        record
            .vo
            .iter()
            .find(|vo| vo.robot == "rover")?
            .track
            .pairs(),
    )
}

/// The rigid motion in the ground plane that best carries the estimates of `(time,
/// estimate, truth)` pairs onto their truths (heights left out).
fn ground_plane_alignment(pairs: &[(u64, Isometry3<f64>, Isometry3<f64>)]) -> Option<Similarity> {
    let flat =
        |p: &Isometry3<f64>| Point3::new(p.translation.vector.x, p.translation.vector.y, 0.0);
    let estimate: Vec<_> = pairs.iter().map(|(_, e, _)| flat(e)).collect();
    let truth: Vec<_> = pairs.iter().map(|(_, _, g)| flat(g)).collect();
    umeyama(&estimate, &truth, false)
}

/// The final map's known cells as the judge needs them, each centre carried into the world's
/// frame by `to_world`.
fn map_cells(map: &RecordedMap, to_world: impl Fn([f64; 2]) -> [f64; 2]) -> Vec<MapCell> {
    let size_m = map.cell_size_m;
    map.cells
        .iter()
        .filter(|cell| cell.class != CellClass::Unknown)
        .map(|cell| MapCell {
            centre_m: to_world([
                map.origin_m.0 + (f64::from(cell.x) + 0.5) * size_m,
                map.origin_m.1 + (f64::from(cell.y) + 0.5) * size_m,
            ]),
            lethal: matches!(cell.class, CellClass::Obstacle | CellClass::Lethal),
            uncertain: cell.class == CellClass::Uncertain,
            costly: cell.extra_cost > 0,
            unobserved: cell.observed_by == 0,
        })
        .collect()
}

/// The lethal ground of `cells` (a grid of `cell_size_m`) that `reach` covers, against the
/// rocks' and the truly too-steep ground.
fn judge_cells(
    truth: &MissionTruth,
    cells: &[MapCell],
    cell_size_m: f64,
    reach: &Reach<'_>,
    rocks: &[RockOutline],
) -> BlockedArea {
    blocked_area(
        cells,
        rocks,
        reach,
        cell_size_m,
        truth.climbable_height_m,
        truth.inscribed_m,
        |centre_m| {
            truth
                .slopes
                .as_ref()
                .is_some_and(|slopes| slopes.class_at_m(centre_m) == SlopeClass::TooSteep)
        },
    )
}

/// The rover's camera at each of its true poses the VO was paired with (one a frame while
/// the VO ran), thinned to one per 5 cm or 2° of change.
fn rover_camera_views(record: &MissionRecord, camera: &RoverCamera) -> Vec<CameraView> {
    let mut views: Vec<CameraView> = Vec::new();
    for world_from_body in rover_true_poses(record) {
        let (_, _, yaw_rad) = world_from_body.rotation.euler_angles();
        let mount = world_from_body.transform_point(&nalgebra::Point3::new(
            camera.body_xy_m[0],
            camera.body_xy_m[1],
            0.0,
        ));
        let view = CameraView {
            position_m: [mount.x, mount.y],
            yaw_rad: yaw_rad + camera.yaw_rad,
        };
        let same = views.last().is_some_and(|last| {
            (last.position_m[0] - view.position_m[0]).hypot(last.position_m[1] - view.position_m[1])
                < 0.05
                && (last.yaw_rad - view.yaw_rad).sin().abs() < 2_f64.to_radians()
        });
        if !same {
            views.push(view);
        }
    }
    views
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ground_plane_alignment_undoes_a_turn_and_a_shift_of_the_whole_track() {
        // The estimate is the truth turned by 0.5° about the origin and shifted by (4, −3) cm,
        // at a height 0.3 m off (left out).
        let turn = nalgebra::Rotation3::from_axis_angle(
            &nalgebra::Vector3::z_axis(),
            0.5_f64.to_radians(),
        );
        let pairs: Vec<_> = (0..40u64)
            .map(|i| {
                let truth = Point3::new(i as f64, 0.1 * (i as f64).powi(2) / 40.0, 0.0);
                let estimate = turn * truth + nalgebra::Vector3::new(0.04, -0.03, 0.3);
                (
                    i,
                    Isometry3::translation(estimate.x, estimate.y, estimate.z),
                    Isometry3::translation(truth.x, truth.y, truth.z),
                )
            })
            .collect();
        let onto_truth = ground_plane_alignment(&pairs).expect("a track that moved aligns");
        for (_, estimate, truth) in &pairs {
            let [x, y] = [estimate.translation.vector.x, estimate.translation.vector.y];
            let carried = onto_truth.apply(&Point3::new(x, y, 0.0));
            let error_m = (carried.x - truth.translation.vector.x)
                .hypot(carried.y - truth.translation.vector.y);
            assert!(error_m < 1e-9, "{error_m}");
        }
        assert!(ground_plane_alignment(&pairs[..2]).is_none());
    }
}
