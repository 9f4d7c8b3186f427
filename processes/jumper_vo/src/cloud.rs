//! World-frame feature cloud of a keyframe pair: triangulation of the RANSAC inliers with the
//! metric relative pose, and the height of each point above a robust local ground plane.

use hopnav_vision::triangulate::{Method, TriangulationConfig, parallax_rad, triangulate_checked};
use nalgebra::{Isometry3, Matrix3, Point3, Vector2, Vector3};

/// A triangulated feature in the world frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WorldPoint {
    /// Position, world frame, metres.
    pub position_m: Point3<f64>,
    /// Height above the local ground plane fitted to the cloud, metres (`None` if no plane).
    pub height_above_ground_m: Option<f64>,
    /// One-sigma range uncertainty from a 1 px ray error at the pair's parallax, metres.
    pub depth_sigma_m: f64,
}

/// One feature seen from two cameras: where it was first observed and in the current keyframe
/// (normalized image coordinates).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TwoViews {
    /// The camera of the first observation.
    pub world_from_first: Isometry3<f64>,
    /// The feature in the first camera.
    pub x_first: Vector2<f64>,
    /// The feature in the current keyframe camera.
    pub x_now: Vector2<f64>,
    /// Keyframe intervals between the two views (1: the last keyframe and this one).
    pub intervals: u32,
}

/// Whether `point` projects within `max_error_px` of `x` (normalized) in the camera
/// `world_from_camera` (in front of it).
pub fn reprojects_within(
    world_from_camera: &Isometry3<f64>,
    point: &WorldPoint,
    x: &Vector2<f64>,
    focal_px: f64,
    max_error_px: f64,
) -> bool {
    let p = world_from_camera.inverse_transform_point(&point.position_m);
    p.z > 0.0 && (Vector2::new(p.x / p.z, p.y / p.z) - x).norm() * focal_px <= max_error_px
}

/// Largest reprojection error a cloud point may have in any view it was seen in, pixels.
pub const MAX_REPROJECTION_ERROR_PX: f64 = 2.0;

/// Variance a view's ray error gains per keyframe interval beyond the first, px²: the
/// attitude between the two views is a chain of keyframe-to-keyframe estimates, and KLT
/// drifts over the frames a track lives. Set so that the bare-ground heights of
/// `hopnav eval jumper-clouds` stay as honest in their sigmas as over one interval.
pub const RAY_VARIANCE_PER_INTERVAL_PX2: f64 = 0.5;

/// Triangulates `views` against the current keyframe camera (`now_from_world`, its inverse
/// pose, taken once per cloud) and returns the
/// accepted point in the world frame. Its depth sigma is the range from the current camera
/// (the viewpoint every point of a cloud shares, published with it) for the ray error at the
/// point's parallax: 1 px over one keyframe interval, growing with
/// [`RAY_VARIANCE_PER_INTERVAL_PX2`] per further interval.
pub fn triangulate_views(
    now_from_world: &Isometry3<f64>,
    views: &TwoViews,
    focal_px: f64,
) -> Option<WorldPoint> {
    let cfg = TriangulationConfig {
        min_parallax_rad: 1f64.to_radians(),
        max_reprojection_error_sq: (MAX_REPROJECTION_ERROR_PX / focal_px.max(1.0)).powi(2),
        min_depth: 0.05,
        max_depth: 500.0,
    };
    let now_from_first = now_from_world * views.world_from_first;
    let p = triangulate_checked(
        &now_from_first,
        &views.x_first,
        &views.x_now,
        &cfg,
        Method::Midpoint,
    )
    .ok()?;
    // Range error ≈ range · ray error / parallax (small-angle triangulation).
    let parallax_rad = parallax_rad(&now_from_first, &p.point_cam1).max(1e-6);
    let range_now_m = (now_from_first * p.point_cam1).coords.norm();
    let extra_intervals = f64::from(views.intervals.saturating_sub(1));
    let ray_sigma_px = (1.0 + RAY_VARIANCE_PER_INTERVAL_PX2 * extra_intervals).sqrt();
    Some(WorldPoint {
        position_m: views.world_from_first * p.point_cam1,
        height_above_ground_m: None,
        depth_sigma_m: range_now_m * ray_sigma_px / focal_px.max(1.0) / parallax_rad,
    })
}

/// Fits `z = a x + b y + c` to the lower part of the cloud (three passes of least squares that
/// drop points more than 2 robust σ above it: rocks) and fills `height_above_ground_m`.
/// Returns the plane coefficients, or `None` (heights left empty) with fewer than 10 points.
pub fn fill_heights_above_ground(points: &mut [WorldPoint]) -> Option<Vector3<f64>> {
    if points.len() < 10 {
        return None;
    }
    let mut use_point = vec![true; points.len()];
    let mut plane = None;
    let mut residuals = vec![0.0; points.len()];
    for _ in 0..3 {
        let mut n = Matrix3::zeros();
        let mut r = Vector3::zeros();
        for (p, _) in points.iter().zip(&use_point).filter(|(_, u)| **u) {
            let a = Vector3::new(p.position_m.x, p.position_m.y, 1.0);
            n += a * a.transpose();
            r += a * p.position_m.z;
        }
        let coeffs = n.try_inverse().map(|inv| inv * r)?;
        for (res, p) in residuals.iter_mut().zip(points.iter()) {
            *res =
                p.position_m.z - (coeffs.x * p.position_m.x + coeffs.y * p.position_m.y + coeffs.z);
        }
        let mut abs: Vec<f64> = residuals.iter().map(|v| v.abs()).collect();
        let half = abs.len() / 2;
        let sigma = 1.4826 * *abs.select_nth_unstable_by(half, f64::total_cmp).1 + 1e-3;
        for (u, res) in use_point.iter_mut().zip(&residuals) {
            *u = *res < 2.0 * sigma;
        }
        plane = Some(coeffs);
    }
    let plane = plane?;
    // Rolling terrain bends away from one plane: measure each point against the low quartile
    // of its neighbours' residuals (same cloud, so the same pose and scale), which follows the
    // local ground and leaves rocks standing. Neighbours come from a grid of radius-sized
    // cells (the 3 × 3 cells around a point hold every neighbour), not from all points.
    let grid = NeighbourGrid::new(points);
    let mut neighbour_residuals = Vec::with_capacity(points.len());
    let local_offsets: Vec<f64> = points
        .iter()
        .map(|p| {
            neighbour_residuals.clear();
            grid.for_each_near(&p.position_m, |j| {
                let q = &points[j].position_m;
                let dx = q.x - p.position_m.x;
                let dy = q.y - p.position_m.y;
                if dx * dx + dy * dy <= LOCAL_GROUND_RADIUS_M * LOCAL_GROUND_RADIUS_M {
                    neighbour_residuals.push(residuals[j]);
                }
            });
            if neighbour_residuals.len() < 8 {
                return 0.0;
            }
            let k = neighbour_residuals.len() / 4;
            *neighbour_residuals
                .select_nth_unstable_by(k, f64::total_cmp)
                .1
        })
        .collect();
    for ((p, res), offset) in points.iter_mut().zip(&residuals).zip(&local_offsets) {
        p.height_above_ground_m = Some(res - offset);
    }
    Some(plane)
}

/// Points bucketed in square cells of [`LOCAL_GROUND_RADIUS_M`] over their x–y bounding box.
struct NeighbourGrid {
    min_x: f64,
    min_y: f64,
    cols: usize,
    rows: usize,
    /// `cell_start[c]..cell_start[c + 1]` indexes `order` for cell `c`.
    cell_start: Vec<usize>,
    /// Point indices sorted by cell.
    order: Vec<usize>,
}

impl NeighbourGrid {
    /// Cells per axis at most (a degenerate, huge cloud just gets coarser cells' worth of
    /// neighbours per lookup; the radius test stays exact).
    const MAX_CELLS_PER_AXIS: usize = 256;

    fn new(points: &[WorldPoint]) -> Self {
        let (mut min_x, mut min_y) = (f64::INFINITY, f64::INFINITY);
        let (mut max_x, mut max_y) = (f64::NEG_INFINITY, f64::NEG_INFINITY);
        for p in points {
            min_x = min_x.min(p.position_m.x);
            min_y = min_y.min(p.position_m.y);
            max_x = max_x.max(p.position_m.x);
            max_y = max_y.max(p.position_m.y);
        }
        let span = |lo: f64, hi: f64| {
            let cells = ((hi - lo) / LOCAL_GROUND_RADIUS_M).floor();
            if cells.is_finite() && cells >= 0.0 {
                (cells as usize + 1).min(Self::MAX_CELLS_PER_AXIS)
            } else {
                1
            }
        };
        let (cols, rows) = (span(min_x, max_x), span(min_y, max_y));
        let mut grid = Self {
            min_x,
            min_y,
            cols,
            rows,
            cell_start: vec![0; cols * rows + 1],
            order: vec![0; points.len()],
        };
        for p in points {
            let c = grid.cell_of(&p.position_m);
            grid.cell_start[c + 1] += 1;
        }
        for c in 0..cols * rows {
            grid.cell_start[c + 1] += grid.cell_start[c];
        }
        let mut fill = grid.cell_start.clone();
        for (i, p) in points.iter().enumerate() {
            let c = grid.cell_of(&p.position_m);
            grid.order[fill[c]] = i;
            fill[c] += 1;
        }
        grid
    }

    fn coord(&self, v: f64, lo: f64, cells: usize) -> usize {
        let c = ((v - lo) / LOCAL_GROUND_RADIUS_M).floor();
        if c.is_finite() && c > 0.0 {
            (c as usize).min(cells - 1)
        } else {
            0
        }
    }

    fn cell_of(&self, p: &Point3<f64>) -> usize {
        self.coord(p.y, self.min_y, self.rows) * self.cols + self.coord(p.x, self.min_x, self.cols)
    }

    /// Calls `f` with every point index in the 3 × 3 cells around `p` (a superset of the
    /// points within [`LOCAL_GROUND_RADIUS_M`]).
    fn for_each_near(&self, p: &Point3<f64>, mut f: impl FnMut(usize)) {
        let (cx, cy) = (
            self.coord(p.x, self.min_x, self.cols),
            self.coord(p.y, self.min_y, self.rows),
        );
        for y in cy.saturating_sub(1)..=(cy + 1).min(self.rows - 1) {
            for x in cx.saturating_sub(1)..=(cx + 1).min(self.cols - 1) {
                let c = y * self.cols + x;
                for &i in &self.order[self.cell_start[c]..self.cell_start[c + 1]] {
                    f(i);
                }
            }
        }
    }
}

/// Neighbourhood of the local ground estimate, metres (about a rock's size, well below the
/// terrain's relief wavelength).
const LOCAL_GROUND_RADIUS_M: f64 = 2.5;

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Translation3, UnitQuaternion};

    /// A camera at `x_m` along a 10 m-high track, looking straight down (camera z = −world z).
    fn camera_at(x_m: f64) -> Isometry3<f64> {
        Isometry3::from_parts(
            Translation3::new(x_m, 0.0, 10.0),
            UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI),
        )
    }

    fn seen_from(camera: &Isometry3<f64>, point: &Point3<f64>) -> Vector2<f64> {
        let p = camera.inverse_transform_point(point);
        Vector2::new(p.x / p.z, p.y / p.z)
    }

    #[test]
    fn a_longer_baseline_gives_the_same_point_with_a_smaller_sigma() {
        let rock_top = Point3::new(3.0, 1.0, 0.5);
        let now = camera_at(4.0);
        let views = |first_x_m: f64, intervals: u32| TwoViews {
            world_from_first: camera_at(first_x_m),
            x_first: seen_from(&camera_at(first_x_m), &rock_top),
            x_now: seen_from(&now, &rock_top),
            intervals,
        };
        let focal_px = 386.0;
        let now_from_world = now.inverse();
        let short = triangulate_views(&now_from_world, &views(3.0, 1), focal_px).unwrap();
        let long = triangulate_views(&now_from_world, &views(0.0, 4), focal_px).unwrap();
        for point in [short, long] {
            assert!((point.position_m - rock_top).norm() < 1e-9, "{point:?}");
        }
        // Four times the baseline, but a ray error grown to sqrt(1 + 3 · 0.5) px.
        let expected = 4.0 / (1.0 + 3.0 * RAY_VARIANCE_PER_INTERVAL_PX2).sqrt();
        let ratio = short.depth_sigma_m / long.depth_sigma_m;
        assert!(ratio > 0.8 * expected && ratio < 1.2 * expected, "{ratio}");
        // A first view off the epipolar line (a track that drifted across it) is refused.
        let mut drifted = views(0.0, 4);
        drifted.x_first.y += 10.0 / focal_px;
        assert!(triangulate_views(&now_from_world, &drifted, focal_px).is_none());
    }

    #[test]
    fn reprojection_is_checked_in_pixels_and_in_front_of_the_camera() {
        let point = WorldPoint {
            position_m: Point3::new(1.0, 0.0, 0.0),
            height_above_ground_m: None,
            depth_sigma_m: 0.1,
        };
        let camera = camera_at(0.0);
        let x = seen_from(&camera, &point.position_m);
        let focal_px = 400.0;
        assert!(reprojects_within(&camera, &point, &x, focal_px, 2.0));
        let off = x + Vector2::new(3.0 / focal_px, 0.0);
        assert!(!reprojects_within(&camera, &point, &off, focal_px, 2.0));
        let above = WorldPoint {
            position_m: Point3::new(1.0, 0.0, 20.0),
            ..point
        };
        assert!(!reprojects_within(&camera, &above, &x, focal_px, 2.0));
    }

    #[test]
    fn ground_plane_ignores_rocks() {
        let mut pts: Vec<WorldPoint> = (0..200)
            .map(|i| {
                let (x, y) = ((i % 20) as f64, (i / 20) as f64);
                let rock = if i % 17 == 0 { 0.8 } else { 0.0 };
                WorldPoint {
                    depth_sigma_m: 0.0,
                    position_m: Point3::new(x, y, 0.1 * x + 2.0 + rock),
                    height_above_ground_m: None,
                }
            })
            .collect();
        let plane = fill_heights_above_ground(&mut pts).unwrap();
        assert!((plane.x - 0.1).abs() < 1e-6 && (plane.z - 2.0).abs() < 1e-6);
        assert!((pts[17].height_above_ground_m.unwrap() - 0.8).abs() < 1e-6);
        assert!(pts[1].height_above_ground_m.unwrap().abs() < 1e-6);
    }

    /// The old all-pairs local-ground offset, as the reference of the grid lookup.
    fn brute_force_heights(points: &[WorldPoint], plane: &Vector3<f64>) -> Vec<f64> {
        let residuals: Vec<f64> = points
            .iter()
            .map(|p| {
                p.position_m.z - (plane.x * p.position_m.x + plane.y * p.position_m.y + plane.z)
            })
            .collect();
        points
            .iter()
            .zip(&residuals)
            .map(|(p, res)| {
                let mut near: Vec<f64> = points
                    .iter()
                    .zip(&residuals)
                    .filter(|(q, _)| {
                        let (dx, dy) = (
                            q.position_m.x - p.position_m.x,
                            q.position_m.y - p.position_m.y,
                        );
                        dx * dx + dy * dy <= LOCAL_GROUND_RADIUS_M * LOCAL_GROUND_RADIUS_M
                    })
                    .map(|(_, r)| *r)
                    .collect();
                if near.len() < 8 {
                    return *res;
                }
                near.sort_by(f64::total_cmp);
                res - near[near.len() / 4]
            })
            .collect()
    }

    #[test]
    fn grid_neighbours_match_all_pairs() {
        // Rolling ground with rocks, scattered over 40 m × 25 m, a few isolated points far out.
        let mut state = 12345u64;
        let mut rand = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut pts: Vec<WorldPoint> = (0..600)
            .map(|i| {
                let (x, y) = (40.0 * rand() - 13.0, 25.0 * rand() + 4.0);
                let rock = if i % 13 == 0 { 0.5 + rand() } else { 0.0 };
                WorldPoint {
                    depth_sigma_m: 0.0,
                    position_m: Point3::new(x, y, (0.3 * x).sin() + 0.05 * y + rock),
                    height_above_ground_m: None,
                }
            })
            .collect();
        for k in 0..3 {
            pts.push(WorldPoint {
                depth_sigma_m: 0.0,
                position_m: Point3::new(300.0 + 50.0 * k as f64, -80.0, 1.0),
                height_above_ground_m: None,
            });
        }
        let plane = fill_heights_above_ground(&mut pts).unwrap();
        let expected = brute_force_heights(&pts, &plane);
        for (p, e) in pts.iter().zip(&expected) {
            assert_eq!(p.height_above_ground_m, Some(*e));
        }
        // Rocks stand out, the rolling ground does not.
        assert!(pts[13].height_above_ground_m.unwrap() > 0.3);
    }
}
