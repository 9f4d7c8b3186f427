//! Fits one rock to the points stereo saw on it: a dome (half a spheroid) standing on the
//! local ground, of height `H` and base radius `c·H`.
//!
//! Why: a camera sees a rock's near face only, and features sit on its corners and flanks,
//! so the tallest point under-reads the rock and the points' box leaves its back out. Rocks
//! are domes about twice as wide as tall (Golombek's rock model, and the world's
//! ellipsoids): each point at height `z` and horizontal distance `d` from the centre then
//! satisfies `(d / c)² + z² = H²`, and a few points on the near face fix the centre behind
//! them and the height above them, as a few points on an arc fix a circle.
//!
//! Gauss–Newton over (centre x, centre y, `H`, `c`) with Cauchy weights (a stereo mismatch
//! weighs almost nothing), weak priors on the centre and the height, and a prior on the
//! shape `c` around the expected one (points across a flat rock's top say it is flat).

use nalgebra::{Matrix4, Vector4};

/// One point on a rock, world metres (as the map keeps it, too).
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RockPoint {
    /// Horizontal position.
    pub xy_m: [f32; 2],
    /// Height above the local ground.
    pub height_m: f32,
    /// One-sigma uncertainty of the height (and, roughly, of the position), > 0.
    pub sigma_m: f32,
    /// World height of the local ground under the point (its z minus its height), metres.
    pub ground_z_m: f32,
}

/// A fitted dome.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DomeFit {
    /// Centre of the dome's base, world metres.
    pub centre_m: [f64; 2],
    /// Height above the local ground, metres.
    pub height_m: f64,
    /// One-sigma uncertainty of the height, metres.
    pub height_sigma_m: f64,
    /// Radius of the base, metres.
    pub base_radius_m: f64,
    /// Root mean square of the points' residuals in their sigmas.
    pub rms_sigmas: f64,
}

/// Fewer points than this fix no dome.
pub const MIN_POINTS: usize = 4;
/// A fit whose residuals exceed this many sigmas (RMS) is not one dome (a cluster, a wall
/// of misplaced points): no fit.
const MAX_RMS_SIGMAS: f64 = 3.0;
/// A point this many sigmas off the dome is an outlier …
const OUTLIER_SIGMAS: f64 = 3.0;
/// … and a dome that leaves more than this fraction of the points off is no dome.
const MAX_OUTLIER_FRACTION: f64 = 0.25;
/// The Cauchy loss's scale, sigmas (a redescending loss: a point many sigmas off, a stereo
/// mismatch, weighs almost nothing, where Huber's would still pull the dome).
const CAUCHY_SIGMAS: f64 = 2.5;
/// The prior on the centre, metres (weak: the points decide).
const CENTRE_PRIOR_SIGMA_M: f64 = 0.5;
/// The prior on the shape (base radius per height), as a fraction of the expected shape:
/// rocks differ, and points across a flat rock's top say it is flat.
const SHAPE_PRIOR_FRACTION: f64 = 0.3;
/// The prior on the height, metres (weak: a few points on the near face outweigh it, but no
/// metre-tall dome explains a 0.3 m rock's face).
const HEIGHT_PRIOR_SIGMA_M: f64 = 0.1;
const ITERATIONS: usize = 12;

/// Fits a dome of expected shape `base_per_height` to `points`, starting behind them along
/// `view_direction` (the horizontal unit vector from the camera towards the points; `None`
/// for a view from above). `None` when the points are too few, not finite or fit no dome.
///
/// ```
/// use hopnav_mapper::dome::{RockPoint, fit_dome};
/// // Points on the near face (x < 0) of a 0.3 m dome centred at (2, 1).
/// let points: Vec<RockPoint> = [(-0.25, 0.0), (-0.2, 0.12), (-0.2, -0.12), (-0.1, 0.05), (-0.15, -0.2)]
///     .iter()
///     .map(|&(dx, dy): &(f32, f32)| RockPoint {
///         xy_m: [2.0 + dx, 1.0 + dy],
///         height_m: (0.09 - dx * dx - dy * dy).max(0.0).sqrt(),
///         sigma_m: 0.01,
///         ground_z_m: 0.0,
///     })
///     .collect();
/// let fit = fit_dome(&points, 1.0, Some([1.0, 0.0])).unwrap();
/// assert!((fit.height_m - 0.3).abs() < 0.02);
/// assert!((fit.centre_m[0] - 2.0).abs() < 0.05 && (fit.centre_m[1] - 1.0).abs() < 0.05);
/// ```
pub fn fit_dome(
    points: &[RockPoint],
    base_per_height: f64,
    view_direction: Option<[f64; 2]>,
) -> Option<DomeFit> {
    let points = usable_points(points);
    if points.len() < MIN_POINTS || !(base_per_height.is_finite() && base_per_height > 0.0) {
        return None;
    }
    let direction = unit_direction(view_direction);
    let (prior, starts) = prior_and_starts(&points, base_per_height, direction);
    let state = starts
        .iter()
        .filter_map(|&(centre_m, height_m)| {
            let state = refine(&points, &prior, centre_m, height_m)?;
            let (_, _, _, cost) = normal_equations(&points, &state, &prior);
            Some((cost, state))
        })
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, state)| state)?;
    let (normal, _, squared, _) = normal_equations(&points, &state, &prior);
    let rms = (squared / points.len() as f64).sqrt();
    let covariance = normal.try_inverse()?;
    let height_sigma_m = covariance[(2, 2)].max(0.0).sqrt() * rms.max(1.0);
    let fit = DomeFit {
        centre_m: [state[0], state[1]],
        height_m: state[2],
        height_sigma_m,
        base_radius_m: state[3] * state[2],
        rms_sigmas: rms,
    };
    fit_is_credible(&fit, &points, &state).then_some(fit)
}

/// The points with a finite position and a positive finite height and σ.
fn usable_points(points: &[RockPoint]) -> Vec<&RockPoint> {
    let valid = |p: &&RockPoint| {
        p.xy_m.iter().all(|v| v.is_finite())
            && p.height_m.is_finite()
            && p.height_m > 0.0
            && p.sigma_m.is_finite()
            && p.sigma_m > 0.0
    };
    points.iter().filter(valid).collect()
}

/// The horizontal view direction as a unit vector (zero if unknown or degenerate).
fn unit_direction(view_direction: Option<[f64; 2]>) -> [f64; 2] {
    view_direction
        .filter(|d| d.iter().all(|v| v.is_finite()) && d[0].hypot(d[1]) > 1e-6)
        .map_or([0.0, 0.0], |d| {
            let n = d[0].hypot(d[1]);
            [d[0] / n, d[1] / n]
        })
}

/// The priors, and the two starts of the fit (kept by the lower robust cost): from the
/// priors, and from the tallest point. The priors: the top a little above the second-tallest
/// point (the tallest may be an outlier; a camera higher than the rock sees near its top), the
/// centre half a base radius behind that point, away from the camera.
fn prior_and_starts(
    points: &[&RockPoint],
    base_per_height: f64,
    direction: [f64; 2],
) -> (Prior, [([f64; 2], f64); 2]) {
    let mut by_height = points.to_vec();
    by_height.sort_by(|a, b| b.height_m.total_cmp(&a.height_m));
    let anchor = by_height[1];
    let height0 = f64::from(anchor.height_m) + f64::from(anchor.sigma_m);
    let behind_m = 0.5 * base_per_height * height0;
    let prior = Prior {
        centre_m: [
            f64::from(anchor.xy_m[0]) + direction[0] * behind_m,
            f64::from(anchor.xy_m[1]) + direction[1] * behind_m,
        ],
        height_m: height0,
        shape: base_per_height,
    };
    let tallest = by_height[0];
    let starts = [
        (prior.centre_m, prior.height_m),
        (
            [
                f64::from(tallest.xy_m[0]) + direction[0] * behind_m,
                f64::from(tallest.xy_m[1]) + direction[1] * behind_m,
            ],
            f64::from(tallest.height_m) + f64::from(tallest.sigma_m),
        ),
    ];
    (prior, starts)
}

/// Whether `fit` is finite and fits its points. The RMS counts outliers at full weight: judge
/// the fit by its inliers, and by how many points are inliers (a wall or a cluster leaves many
/// points off any one dome).
fn fit_is_credible(fit: &DomeFit, points: &[&RockPoint], state: &Vector4<f64>) -> bool {
    let finite = [
        fit.centre_m[0],
        fit.centre_m[1],
        fit.height_m,
        fit.height_sigma_m,
    ]
    .iter()
    .all(|v| v.is_finite());
    let outliers = points
        .iter()
        .filter(|p| residual_and_jacobian(p, state).0.abs() > OUTLIER_SIGMAS)
        .count();
    let inliers_ok = (outliers as f64) <= MAX_OUTLIER_FRACTION * points.len() as f64;
    finite && inliers_ok && robust_rms(points, state) <= MAX_RMS_SIGMAS
}

/// Where the dome is expected before its points are weighed.
struct Prior {
    centre_m: [f64; 2],
    height_m: f64,
    /// Base radius per height.
    shape: f64,
}

/// Gauss–Newton from (`centre_m`, `height_m`) and the prior's shape; the state is
/// (centre x, centre y, height, base radius per height).
fn refine(
    points: &[&RockPoint],
    prior: &Prior,
    centre_m: [f64; 2],
    height_m: f64,
) -> Option<Vector4<f64>> {
    let mut state = Vector4::new(centre_m[0], centre_m[1], height_m, prior.shape);
    for _ in 0..ITERATIONS {
        let (normal, gradient, _, _) = normal_equations(points, &state, prior);
        let step = normal.lu().solve(&(-gradient))?;
        state += step;
        state[2] = state[2].max(1e-3);
        state[3] = state[3].clamp(0.5 * prior.shape, 2.0 * prior.shape);
        if step.norm() < 1e-5 {
            break;
        }
    }
    Some(state)
}

/// RMS of the residuals (sigmas), each weighted as the Cauchy loss weighs it (an outlier
/// does not fail a good fit).
fn robust_rms(points: &[&RockPoint], state: &Vector4<f64>) -> f64 {
    let (mut weighted, mut weights) = (0.0, 0.0);
    for p in points {
        let residual = residual_and_jacobian(p, state).0;
        let weight = 1.0 / (1.0 + (residual / CAUCHY_SIGMAS).powi(2));
        weighted += weight * residual * residual;
        weights += weight;
    }
    (weighted / weights.max(1e-12)).sqrt()
}

/// The point's residual in sigmas, `sqrt(d²/c² + z²) − H`, and its gradient.
fn residual_and_jacobian(p: &RockPoint, state: &Vector4<f64>) -> (f64, Vector4<f64>) {
    let (ex, ey) = (
        f64::from(p.xy_m[0]) - state[0],
        f64::from(p.xy_m[1]) - state[1],
    );
    let z = f64::from(p.height_m);
    let c = state[3];
    let (c2, d2) = (c * c, ex * ex + ey * ey);
    let s = (d2 / c2 + z * z).sqrt().max(1e-6);
    let sigma = f64::from(p.sigma_m);
    let residual = (s - state[2]) / sigma;
    let jacobian = Vector4::new(-ex / (c2 * s), -ey / (c2 * s), -1.0, -d2 / (c2 * c * s)) / sigma;
    (residual, jacobian)
}

/// JᵀWJ and JᵀWr of the residuals at `state` (Cauchy-weighted, with the priors), Σ r²
/// (unweighted, in sigmas) and the robust cost.
fn normal_equations(
    points: &[&RockPoint],
    state: &Vector4<f64>,
    prior: &Prior,
) -> (Matrix4<f64>, Vector4<f64>, f64, f64) {
    let mut normal = Matrix4::zeros();
    let mut gradient = Vector4::zeros();
    let (mut squared, mut cost) = (0.0, 0.0);
    for p in points {
        let (residual, jacobian) = residual_and_jacobian(p, state);
        let ratio2 = (residual / CAUCHY_SIGMAS).powi(2);
        cost += 0.5 * CAUCHY_SIGMAS * CAUCHY_SIGMAS * ratio2.ln_1p();
        let weight = 1.0 / (1.0 + ratio2);
        normal += weight * jacobian * jacobian.transpose();
        gradient += weight * jacobian * residual;
        squared += residual * residual;
    }
    let offsets = [
        state[0] - prior.centre_m[0],
        state[1] - prior.centre_m[1],
        state[2] - prior.height_m,
        state[3] - prior.shape,
    ];
    let sigmas = [
        CENTRE_PRIOR_SIGMA_M,
        CENTRE_PRIOR_SIGMA_M,
        HEIGHT_PRIOR_SIGMA_M,
        SHAPE_PRIOR_FRACTION * prior.shape,
    ];
    for axis in 0..4 {
        let information = 1.0 / (sigmas[axis] * sigmas[axis]);
        normal[(axis, axis)] += information;
        gradient[axis] += information * offsets[axis];
        cost += 0.5 * information * offsets[axis] * offsets[axis];
    }
    (normal, gradient, squared, cost)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Points on the dome's surface at the given (dx, dy) offsets from its centre, plus a
    /// deterministic height error of ± `noise_m`.
    fn dome_points(
        centre: [f32; 2],
        height: f32,
        offsets: &[(f32, f32)],
        noise_m: f32,
    ) -> Vec<RockPoint> {
        offsets
            .iter()
            .enumerate()
            .map(|(i, &(dx, dy))| RockPoint {
                xy_m: [centre[0] + dx, centre[1] + dy],
                height_m: (height * height - dx * dx - dy * dy).max(0.0).sqrt()
                    + if i % 2 == 0 { noise_m } else { -noise_m },
                sigma_m: 0.03,
                ground_z_m: 0.0,
            })
            .collect()
    }

    const NEAR_FACE: [(f32, f32); 8] = [
        (-0.2, 0.0),
        (-0.18, 0.1),
        (-0.18, -0.1),
        (-0.12, 0.05),
        (-0.1, -0.15),
        (-0.22, 0.05),
        (-0.05, 0.0),
        (-0.15, 0.18),
    ];

    #[test]
    fn points_on_the_near_face_recover_the_rock_behind_them() {
        let points = dome_points([5.0, -3.0], 0.25, &NEAR_FACE, 0.02);
        let fit = fit_dome(&points, 1.0, Some([1.0, 0.0])).unwrap();
        assert!((fit.height_m - 0.25).abs() < 0.03, "{fit:?}");
        assert!((fit.centre_m[0] - 5.0).abs() < 0.08, "{fit:?}");
        assert!((fit.centre_m[1] + 3.0).abs() < 0.08, "{fit:?}");
        assert!(
            fit.height_sigma_m > 0.0 && fit.height_sigma_m < 0.05,
            "{fit:?}"
        );
    }

    #[test]
    fn a_wider_rock_shape_moves_the_centre_farther_back() {
        // A dome whose base is twice its height.
        let offsets: Vec<(f32, f32)> = NEAR_FACE.iter().map(|&(x, y)| (2.0 * x, 2.0 * y)).collect();
        let points: Vec<RockPoint> = offsets
            .iter()
            .map(|&(dx, dy)| RockPoint {
                xy_m: [dx, dy],
                height_m: (0.0625 - (dx * dx + dy * dy) / 4.0).max(0.0).sqrt(),
                sigma_m: 0.02,
                ground_z_m: 0.0,
            })
            .collect();
        let fit = fit_dome(&points, 2.0, Some([1.0, 0.0])).unwrap();
        assert!((fit.height_m - 0.25).abs() < 0.03, "{fit:?}");
        assert!(fit.centre_m[0].abs() < 0.1, "{fit:?}");
        assert!((fit.base_radius_m - 0.5).abs() < 0.06, "{fit:?}");
    }

    #[test]
    fn too_few_or_bad_points_fit_nothing() {
        let points = dome_points([0.0, 0.0], 0.3, &NEAR_FACE[..3], 0.0);
        assert!(fit_dome(&points, 1.0, None).is_none());
        let mut points = dome_points([0.0, 0.0], 0.3, &NEAR_FACE, 0.0);
        for p in &mut points[..5] {
            p.height_m = f32::NAN;
        }
        assert!(
            fit_dome(&points, 1.0, None).is_none(),
            "three good points left"
        );
        let mut points = dome_points([0.0, 0.0], 0.3, &NEAR_FACE, 0.0);
        points[0].sigma_m = 0.0;
        points[1].xy_m[0] = f32::INFINITY;
        assert!(
            fit_dome(&points, 1.0, None).is_some(),
            "bad points are skipped"
        );
        assert!(fit_dome(&points, f64::NAN, None).is_none());
    }

    #[test]
    fn a_line_of_tall_points_is_no_dome() {
        // A misplaced cloud's wall: 0.4 m tall points along 3 m.
        let points: Vec<RockPoint> = (0..12)
            .map(|i| RockPoint {
                xy_m: [0.25 * i as f32, 0.0],
                height_m: 0.4,
                sigma_m: 0.02,
                ground_z_m: 0.0,
            })
            .collect();
        assert!(fit_dome(&points, 1.0, Some([0.0, 1.0])).is_none());
    }

    #[test]
    fn one_outlier_does_not_move_the_height_much() {
        let mut points = dome_points([0.0, 0.0], 0.3, &NEAR_FACE, 0.01);
        points.push(RockPoint {
            xy_m: [-0.1, 0.0],
            height_m: 0.6,
            sigma_m: 0.03,
            ground_z_m: 0.0,
        });
        let fit = fit_dome(&points, 1.0, Some([1.0, 0.0])).unwrap();
        assert!((fit.height_m - 0.3).abs() < 0.06, "{fit:?}");
    }
}
