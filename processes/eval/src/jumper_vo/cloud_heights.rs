//! How well the jumper's keyframe clouds measure heights above the ground, against the world
//! they were rendered from: the noise on bare ground, whether the clouds' height sigmas are
//! honest, and how many points on rocks of each height the mapper's rule would call high.
//!
//! Each point is matched to the surface it came from by casting its viewing ray from the
//! **true** camera centre of the cloud's keyframe (the camera all its points share): the ray
//! direction is good to a pixel, while the point's range (and the estimated keyframe pose)
//! carry the errors under test. The surface is the terrain and the rocks' meshes, as the
//! camera renders them.

use hopnav_world::World;
use nalgebra::{Isometry3, Point3};

use super::truth_surface::{SurfaceHit, TruthSurface};
use hopnav_jumper_vo::run::HopRun;
use hopnav_jumper_vo::simulate::SimulatedHop;

/// The mapper's test for a jumper point (defaults: `config/default.toml`'s `[mapper]`). Its
/// height sigma is the depth sigma times the vertical part of the ray from the camera the
/// cloud is published with to the point, as the mapper computes it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HighRule {
    /// Points whose depth sigma exceeds this are dropped, metres.
    pub max_depth_sigma_m: f64,
    /// Points whose height is beyond this (either sign) are dropped, metres.
    pub max_feature_height_m: f64,
    /// A point is high above `traversable_height_m + sigma_factor · height sigma`, metres.
    pub traversable_height_m: f64,
    /// Height sigmas of margin.
    pub sigma_factor: f64,
}

impl Default for HighRule {
    fn default() -> Self {
        Self {
            max_depth_sigma_m: 0.25,
            max_feature_height_m: 5.0,
            traversable_height_m: 0.15,
            sigma_factor: 2.0,
        }
    }
}

/// Upper edges of the true-height classes of rock points, metres (the last class is open).
pub const HEIGHT_CLASS_EDGES_M: [f64; 3] = [0.15, 0.3, 0.5];

/// Points on rock surfaces whose true height above the ground falls in one class.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct HeightClass {
    /// Points in the class.
    pub points: usize,
    /// Of them, called high by the [`HighRule`].
    pub called_high: usize,
    /// Sum of their estimated heights above the ground, metres.
    pub estimated_sum_m: f64,
    /// Sum of their true heights above the ground, metres.
    pub true_sum_m: f64,
}

/// Totals over any number of hops.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize)]
pub struct CloudHeightStats {
    /// Keyframe clouds evaluated.
    pub clouds: usize,
    /// Points with a height and a sigma under the rule's limit.
    pub points: usize,
    /// Points whose ray hit no surface within [`MAX_RAY_M`](super::truth_surface::MAX_RAY_M).
    pub unmatched: usize,
    /// Points on bare ground at least [`GROUND_CLEARANCE_M`] from any rock's bounding circle.
    pub ground_points: usize,
    /// Sum of squared estimated heights of the ground points, m².
    pub ground_height_sq_sum_m2: f64,
    /// Sum of squared (estimated height / height sigma) of the ground points.
    pub ground_z_sq_sum: f64,
    /// Ground points called high (false obstacles before the mapper's cloud vote).
    pub ground_called_high: usize,
    /// Rock points by true height, classes split at [`HEIGHT_CLASS_EDGES_M`].
    pub rock_classes: [HeightClass; 4],
}

/// A ground point lies at least this far from every rock's bounding circle, metres.
pub const GROUND_CLEARANCE_M: f64 = 0.5;

impl CloudHeightStats {
    /// RMS of the ground points' estimated heights (truth: 0), metres.
    pub fn ground_rms_m(&self) -> Option<f64> {
        (self.ground_points > 0)
            .then(|| (self.ground_height_sq_sum_m2 / self.ground_points as f64).sqrt())
    }

    /// RMS of the ground points' heights in units of their own sigma (1 = honest sigmas).
    pub fn ground_z_rms(&self) -> Option<f64> {
        (self.ground_points > 0).then(|| (self.ground_z_sq_sum / self.ground_points as f64).sqrt())
    }

    /// Adds one hop's clouds: `run` is the VO over `hop`, rendered from `world`.
    pub fn add_hop(&mut self, world: &World, hop: &SimulatedHop, run: &HopRun, rule: &HighRule) {
        let surface = TruthSurface::new(world);
        for out in &run.outputs {
            let (Some(cloud), Some(estimated_camera)) = (&out.cloud, out.cloud_world_from_camera)
            else {
                continue;
            };
            let Some(truth) = usize::try_from(out.frame_index)
                .ok()
                .and_then(|frame| hop.truth_world_from_body.get(frame))
            else {
                continue;
            };
            let true_camera = truth * hop.body_from_camera;
            let estimated_camera_from_world = estimated_camera.inverse();
            let published_from_m = estimated_camera.translation.vector;
            self.clouds += 1;
            for point in cloud {
                let to_point = point.position_m.coords - published_from_m;
                let vertical = to_point.z.abs() / to_point.norm().max(1e-9);
                let height_sigma_m = point.depth_sigma_m * vertical;
                self.add_point(
                    &surface,
                    (&true_camera, &estimated_camera_from_world),
                    point,
                    height_sigma_m,
                    rule,
                );
            }
        }
    }

    /// `cameras`: the camera the cloud was triangulated from, true (`world_from_camera`) and
    /// as the VO had it (`camera_from_world`).
    fn add_point(
        &mut self,
        surface: &TruthSurface<'_>,
        (true_camera, estimated_camera_from_world): (&Isometry3<f64>, &Isometry3<f64>),
        point: &hopnav_jumper_vo::cloud::WorldPoint,
        height_sigma_m: f64,
        rule: &HighRule,
    ) {
        let Some(height_m) = point.height_above_ground_m else {
            return;
        };
        // NaN sigmas and heights fail this too.
        let usable = point.depth_sigma_m <= rule.max_depth_sigma_m
            && height_m.abs() <= rule.max_feature_height_m;
        if !usable {
            return;
        }
        self.points += 1;
        // The point as seen from the keyframe camera, put under the true camera.
        let in_camera = estimated_camera_from_world * point.position_m;
        let ray = true_camera.rotation * in_camera.coords;
        let range_m = ray.norm();
        if range_m <= 0.0 {
            self.unmatched += 1;
            return;
        }
        let called_high = height_m > rule.traversable_height_m + rule.sigma_factor * height_sigma_m;
        let origin = true_camera.translation.vector;
        let Some(hit) = surface.cast(&Point3::from(origin), &(ray / range_m)) else {
            self.unmatched += 1;
            return;
        };
        match hit {
            SurfaceHit::Ground { rock_clearance_m } => {
                if rock_clearance_m >= GROUND_CLEARANCE_M {
                    self.ground_points += 1;
                    self.ground_height_sq_sum_m2 += height_m * height_m;
                    let z = height_m / height_sigma_m.max(1e-3);
                    self.ground_z_sq_sum += z * z;
                    self.ground_called_high += usize::from(called_high);
                }
            }
            SurfaceHit::Rock { true_height_m } => {
                let class = HEIGHT_CLASS_EDGES_M
                    .iter()
                    .position(|&edge| true_height_m < edge)
                    .unwrap_or(HEIGHT_CLASS_EDGES_M.len());
                if let Some(entry) = self.rock_classes.get_mut(class) {
                    entry.points += 1;
                    entry.called_high += usize::from(called_high);
                    entry.estimated_sum_m += height_m;
                    entry.true_sum_m += true_height_m;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::jumper_vo::truth_surface::tests::flat_world_with_a_rock;
    use hopnav_jumper_vo::cloud::WorldPoint;
    use hopnav_jumper_vo::output::{VoOutput, VoStatus};
    use nalgebra::Vector3;

    /// The VO's placement error of the cloud camera along x, metres (wider than the rock).
    const CAMERA_ERROR_X_M: f64 = 1.5;

    /// Keyframes 10 m up at x = 0 and x = 2 m, looking down. The VO placed the second keyframe
    /// (the cloud's camera) [`CAMERA_ERROR_X_M`] off, so every point of `true_points` reaches
    /// the cloud shifted by that much; the published body poses are off by 0.7 m more.
    fn stats_of(true_points: Vec<WorldPoint>) -> CloudHeightStats {
        let world = flat_world_with_a_rock();
        let keyframe = |x_m: f64| Isometry3::translation(x_m, 0.0, 10.0);
        let hop = hopnav_jumper_vo::simulate::SimulatedHop {
            width_px: 0,
            height_px: 0,
            camera: hopnav_vision::camera::PinholeCamera::new(320, 320, 300.0, 300.0, 160.0, 160.0)
                .unwrap(),
            hop: hopnav_jumper_vo::trajectory::HopTrajectory::table1(),
            body_from_camera: Isometry3::identity(),
            t_s: vec![0.0, 0.1],
            images: Vec::new(),
            truth_world_from_body: vec![keyframe(0.0), keyframe(2.0)],
            altimeter_m: vec![10.0; 2],
        };
        let cloud: Vec<WorldPoint> = true_points
            .into_iter()
            .map(|point| WorldPoint {
                position_m: point.position_m + Vector3::x() * CAMERA_ERROR_X_M,
                ..point
            })
            .collect();
        let output = |frame_index: u64, cloud: Option<Vec<WorldPoint>>| VoOutput {
            frame_index,
            t_s: 0.1 * frame_index as f64,
            // The body pose is not the camera the cloud was triangulated to.
            world_from_body: keyframe(2.0 * frame_index as f64 + CAMERA_ERROR_X_M + 0.7),
            confidence: 1.0,
            status: VoStatus::Tracking,
            is_keyframe: true,
            tracked_features: 0,
            inliers: 0,
            scale: None,
            model: None,
            position_sigma_m: f64::NAN,
            cloud_world_from_camera: cloud
                .as_ref()
                .map(|_| keyframe(2.0 * frame_index as f64 + CAMERA_ERROR_X_M)),
            cloud,
        };
        let run = HopRun {
            outputs: vec![output(0, None), output(1, Some(cloud))],
            frame_time_us: Vec::new(),
            frame_cpu_us: Vec::new(),
        };
        let mut stats = CloudHeightStats::default();
        stats.add_hop(&world, &hop, &run, &HighRule::default());
        stats
    }

    fn point(x_m: f64, z_m: f64, height_m: f64, depth_sigma_m: f64) -> WorldPoint {
        WorldPoint {
            position_m: Point3::new(x_m, 0.0, z_m),
            height_above_ground_m: Some(height_m),
            depth_sigma_m,
        }
    }

    #[test]
    fn points_are_sorted_by_the_surface_their_ray_meets_from_the_true_camera() {
        let stats = stats_of(vec![
            // On the rock top, read well (0.38 > 0.15 + 2 · 0.05): called high.
            point(0.0, 0.38, 0.38, 0.05),
            // On the rock top, read low: missed.
            point(0.0, 0.2, 0.2, 0.05),
            // Bare ground 4 m away, read 0.1 m high with a 0.05 m sigma: z = 2, not high.
            point(4.0, 0.1, 0.1, 0.05),
            // Too uncertain to count.
            point(4.0, 0.0, 0.0, 0.5),
        ]);
        assert_eq!(stats.clouds, 1);
        assert_eq!(stats.points, 3);
        let class = stats.rock_classes[2];
        assert_eq!((class.points, class.called_high), (2, 1));
        assert_eq!(stats.ground_points, 1);
        assert_eq!(stats.ground_called_high, 0);
        assert!((stats.ground_rms_m().unwrap() - 0.1).abs() < 1e-9);
        // Seen from the cloud's camera 2 m beside it, the point's ray is steep: height sigma
        // ≈ 0.98 · depth sigma, z ≈ 2.04.
        let z = stats.ground_z_rms().unwrap();
        assert!(z > 2.0 && z < 2.1, "{z}");
    }
}
