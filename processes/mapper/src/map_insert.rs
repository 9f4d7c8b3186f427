//! Feeding the feature map: each point of a cloud checked, binned into its cell's statistics,
//! and handed to the traversability layer (belief, fitted rock, ground, free-space ray).

use hopnav_ipc::messages::{FeaturePoint, Robot};

use super::{FeatureMap, PointHeights};
use crate::dome::RockPoint;
use crate::traversability::PointSource;

impl FeatureMap {
    /// Adds the features of one cloud observed by `robot` from an unknown viewpoint (each
    /// point's whole depth sigma counts as height uncertainty); returns how many were
    /// accepted. Bad points (non-finite, implausible height) and points outside the grid are
    /// counted and dropped.
    pub fn insert_cloud(&mut self, robot: Robot, points: &[FeaturePoint]) -> usize {
        self.insert_cloud_seen_from(robot, None, points)
    }

    /// [`Self::insert_cloud`] for a cloud seen from `camera_m` (world metres): a point's
    /// height uncertainty is its depth sigma times the vertical part of its viewing ray, so
    /// a rover's far, grazing points keep their (small) height error and a jumper's steep
    /// ones their large one. A measured feature is high only when it stands more than the
    /// robot's `*_height_sigma_factor` of these sigmas above the traversable height.
    pub fn insert_cloud_seen_from(
        &mut self,
        robot: Robot,
        camera_m: Option<[f64; 3]>,
        points: &[FeaturePoint],
    ) -> usize {
        let before = self.counters.accepted;
        self.cloud_sequence = self.cloud_sequence.wrapping_add(1);
        for point in points {
            self.insert_point(robot, camera_m, point);
        }
        (self.counters.accepted - before) as usize
    }

    fn insert_point(&mut self, robot: Robot, camera_m: Option<[f64; 3]>, point: &FeaturePoint) {
        if !point.is_valid() {
            self.counters.non_finite += 1;
            return;
        }
        let sigma_required = self.beliefs.is_some();
        if point.depth_sigma_m < 0.0 || sigma_required && point.depth_sigma_m <= 0.0 {
            self.counters.bad_sigma += 1;
            return;
        }
        if point.depth_sigma_m > self.thresholds.max_depth_sigma_m {
            self.counters.uncertain += 1;
            return;
        }
        let height = point.height_above_ground_m;
        let height = height.is_finite().then_some(height);
        if let Some(height) = height
            && height.abs() > self.thresholds.max_feature_height_m
        {
            self.counters.implausible_height += 1;
            return;
        }
        let [x, y, _] = point.position_m;
        let Some((cx, cy)) = self.geometry.cell_of(f64::from(x), f64::from(y)) else {
            self.counters.outside_grid += 1;
            return;
        };
        let index = self.geometry.index(cx, cy);
        let t = self.thresholds;
        let sigma_factor = match robot {
            Robot::Jumper => t.jumper_height_sigma_factor,
            Robot::Rover => t.rover_height_sigma_factor,
        };
        let vertical_sigma_m = vertical_sigma_m(camera_m, point) as f32;
        let high_above_m = t.traversable_height_m + sigma_factor * vertical_sigma_m;
        let mut belief_height_m = height;
        if height.is_none()
            && let Some(plane) = &self.ground_cache[index]
        {
            let above_m =
                f64::from(point.position_m[2]) - plane.height_at(f64::from(x), f64::from(y));
            if above_m <= f64::from(t.max_feature_height_m) {
                self.stats[index].add_provisional(above_m > f64::from(high_above_m));
                belief_height_m = Some(above_m as f32);
            }
        }
        if let Some(judged_m) = belief_height_m {
            self.feed_traversability(
                robot,
                camera_m,
                point,
                index,
                PointHeights {
                    measured_m: height,
                    judged_m,
                    vertical_sigma_m,
                },
            );
        }
        if robot == Robot::Jumper
            && let Some(height) = height
        {
            self.stats[index].vote(self.cloud_sequence, height > high_above_m);
        }
        self.stats[index].add(point.position_m, height, robot.code(), high_above_m);
        self.touched.insert(index);
        self.counters.accepted += 1;
    }

    /// The `traversability` model's share of an accepted point (nothing under `features`):
    /// the cell's belief; for the rover's points also the rock points to fit, the ground's
    /// elevation and the free space its stereo ray crossed.
    fn feed_traversability(
        &mut self,
        robot: Robot,
        camera_m: Option<[f64; 3]>,
        point: &FeaturePoint,
        index: usize,
        heights: PointHeights,
    ) {
        let PointHeights {
            judged_m,
            vertical_sigma_m,
            ..
        } = heights;
        let [x, y, _] = point.position_m;
        let Some(layer) = self.beliefs.as_mut() else {
            return;
        };
        // The rover's viewpoint tells which side of a rock it has not seen.
        let camera_xy_m = camera_m
            .filter(|_| robot == Robot::Rover)
            .map(|[cx, cy, _]| [cx, cy]);
        layer.add_point(
            index,
            PointSource {
                robot,
                cloud: self.cloud_sequence,
                camera_xy_m,
            },
            [x, y],
            judged_m,
            vertical_sigma_m,
        );
        if let Some(domes) = self.domes.as_mut().filter(|_| robot == Robot::Rover) {
            domes.add_point(
                index,
                RockPoint {
                    xy_m: [x, y],
                    height_m: judged_m,
                    sigma_m: layer.floored_sigma_m(vertical_sigma_m),
                    ground_z_m: point.position_m[2] - judged_m,
                },
            );
        }
        // The rover's ground points give the ground's elevation (its slope); a jumper
        // cloud's pose drift would tilt it.
        if robot == Robot::Rover
            && let Some(measured_m) = heights.measured_m
            && measured_m < 0.5 * layer.climb_limit_m()
        {
            layer.add_ground(index, point.position_m[2] - measured_m, vertical_sigma_m);
        }
        // Only the rover's stereo rays clear cells: the jumper's clouds carry metres of
        // pose drift, and a ray drawn off its place would clear a real rock.
        if robot == Robot::Rover
            && let Some(camera_m) = camera_m
        {
            let point_m = point.position_m.map(f64::from);
            let ground_z_m = point_m[2] - f64::from(judged_m);
            layer.add_ray(
                &self.geometry,
                camera_m,
                point_m,
                ground_z_m,
                self.cloud_sequence,
                &mut self.touched,
            );
        }
    }
}

/// One-sigma height uncertainty of `point`: its depth sigma along the viewing ray from
/// `camera_m`, projected on the vertical (all of it when the viewpoint is unknown).
fn vertical_sigma_m(camera_m: Option<[f64; 3]>, point: &FeaturePoint) -> f64 {
    let depth_sigma_m = f64::from(point.depth_sigma_m);
    let Some(camera_m) = camera_m else {
        return depth_sigma_m;
    };
    let ray_m = [
        f64::from(point.position_m[0]) - camera_m[0],
        f64::from(point.position_m[1]) - camera_m[1],
        f64::from(point.position_m[2]) - camera_m[2],
    ];
    let range_m = ray_m.iter().map(|v| v * v).sum::<f64>().sqrt();
    if range_m.is_nan() || range_m <= 1e-6 || !range_m.is_finite() {
        return depth_sigma_m;
    }
    depth_sigma_m * ray_m[2].abs() / range_m
}
