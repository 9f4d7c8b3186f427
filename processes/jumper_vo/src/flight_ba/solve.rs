//! Levenberg–Marquardt over the flight parameters, with the ground points eliminated by the
//! Schur complement (each point is a 3×3 block coupled only to the nine shared parameters).

use super::{
    AltitudeSample, BaError, BaOutcome, BaSettings, FlightModel, FlightParams, FlightPrior,
    ParamVector, Sighting,
};
use nalgebra::{Isometry3, Matrix3, Point3, SMatrix, Vector2, Vector3};

type ParamJacobian = SMatrix<f64, 2, 9>;
type ParamHessian = SMatrix<f64, 9, 9>;
type CrossHessian = SMatrix<f64, 9, 3>;
/// A keyframe's body position and `R_cw`, and the body motion's derivative by the parameters.
type KeyframeMotion = ((Vector3<f64>, Matrix3<f64>), SMatrix<f64, 6, 9>);

/// A point closer to the camera than this (along its axis) is behind it, metres.
const MIN_DEPTH_M: f64 = 0.05;
/// Squared residual (σ²) a sighting behind its camera counts as.
const BEHIND_SQUARED_SIGMAS: f64 = 1e4;
/// Step of the forward differences over the flight parameters.
const PARAM_STEP: f64 = 1e-6;
/// Points adjusted at most, those with the most sightings first (bounds the cost per call).
const MAX_POINTS: usize = 400;
/// Cauchy scale of the altimeter residuals, σs: a wild sample (a glitch, a rock under the
/// beam) counts little.
const ALTIMETER_ROBUST_SIGMAS: f64 = 3.0;
/// Iterations stop once one lowers the cost by less than this fraction.
const MIN_RELATIVE_GAIN: f64 = 1e-4;

/// One ground point: its sightings (a range of `Problem::order`) and its position.
#[derive(Debug, Clone, Copy)]
struct GroundPoint {
    first: usize,
    end: usize,
    position_m: Vector3<f64>,
}

struct Problem<'a> {
    model: &'a FlightModel,
    prior: &'a FlightPrior,
    settings: &'a BaSettings,
    sightings: &'a [Sighting],
    altitudes: &'a [AltitudeSample],
    /// Sighting indices grouped by point.
    order: Vec<usize>,
    /// Keyframe instants, and the keyframe of each sighting.
    keyframe_tau_s: Vec<f64>,
    sighting_keyframe: Vec<usize>,
}

/// Refines `start` against the window's sightings and altimeter samples. The result never
/// has a higher cost than `start`: with nothing to gain the start comes back unchanged.
pub fn adjust(
    model: &FlightModel,
    prior: &FlightPrior,
    settings: &BaSettings,
    start: &FlightParams,
    sightings: &[Sighting],
    altitudes: &[AltitudeSample],
) -> Result<BaOutcome, BaError> {
    check_input(settings, start)?;
    let problem = Problem::new(model, prior, settings, sightings, altitudes);
    let mut points = problem.initial_points(start);
    if points.len() < settings.min_points {
        return Err(BaError::TooFewPoints {
            found: points.len(),
            needed: settings.min_points,
        });
    }
    let mut theta = start.to_vector();
    let mut cost = problem.cost(&theta, &points);
    let cost_before = cost;
    let median_before = problem.median_error_sigmas(&theta, &points);
    let mut lambda = 1e-4;
    let mut iterations = 0;
    // The last normal equations built: at convergence their Schur complement gives the
    // parameters' covariance without another pass over the sightings.
    let mut last_normal = None;
    while iterations < settings.max_iterations {
        iterations += 1;
        let normal = last_normal.insert(problem.normal_equations(&theta, &points));
        let mut accepted = false;
        for _ in 0..8 {
            let Some((step, point_steps)) = normal.solve(lambda) else {
                lambda *= 10.0;
                continue;
            };
            let candidate_theta = theta + step;
            let candidate_points: Vec<GroundPoint> = points
                .iter()
                .zip(&point_steps)
                .map(|(p, dx)| GroundPoint {
                    position_m: p.position_m + dx,
                    ..*p
                })
                .collect();
            let candidate_cost = problem.cost(&candidate_theta, &candidate_points);
            if candidate_cost.is_finite() && candidate_cost < cost {
                let gain = (cost - candidate_cost) / cost.max(1e-12);
                theta = candidate_theta;
                points = candidate_points;
                cost = candidate_cost;
                lambda = (lambda / 3.0).max(1e-9);
                accepted = gain > MIN_RELATIVE_GAIN;
                break;
            }
            lambda *= 4.0;
        }
        if !accepted {
            break;
        }
    }
    let params = FlightParams::from_vector(&theta);
    if !params.is_finite() {
        return Err(BaError::Singular);
    }
    let sightings: usize = points.iter().map(|p| p.end - p.first).sum();
    // The a-posteriori variance factor, never below 1: residuals wider than the pixel σ widen
    // the covariance, narrower ones do not shrink it.
    let dof = (2 * sightings).saturating_sub(9 + 3 * points.len()).max(1);
    let variance_factor = (cost / dof as f64).max(1.0);
    let velocity_covariance = last_normal
        .unwrap_or_else(|| problem.normal_equations(&theta, &points))
        .parameter_covariance()
        .map(|c| c.fixed_view::<3, 3>(0, 0) * variance_factor)
        .filter(|c| c.iter().all(|v| v.is_finite()));
    Ok(BaOutcome {
        params,
        points: points.len(),
        sightings,
        iterations,
        cost_before,
        cost_after: cost,
        median_error_sigmas_before: median_before,
        median_error_sigmas_after: problem.median_error_sigmas(&theta, &points),
        velocity_covariance,
    })
}

fn check_input(settings: &BaSettings, start: &FlightParams) -> Result<(), BaError> {
    if !start.is_finite() {
        return Err(BaError::BadInput("start parameters"));
    }
    let positive = |v: f64| v.is_finite() && v > 0.0;
    if !positive(settings.sighting_sigma) {
        return Err(BaError::BadInput("sighting sigma"));
    }
    if !positive(settings.robust_scale_sigmas) {
        return Err(BaError::BadInput("robust scale"));
    }
    if !positive(settings.altimeter_sigma_m) {
        return Err(BaError::BadInput("altimeter sigma"));
    }
    Ok(())
}

/// Cauchy loss of a squared residual `s` (in σ²) with scale `c`: about `s` for small `s`.
fn cauchy(s: f64, c: f64) -> f64 {
    c * c * (s / (c * c)).ln_1p()
}

/// Its iteratively-reweighted least-squares weight.
fn cauchy_weight(s: f64, c: f64) -> f64 {
    1.0 / (1.0 + s / (c * c))
}

/// Normalized projection residual of `point` seen at `observed` from `camera_from_world`,
/// in σs, and the camera-frame point; `None` behind the camera.
fn residual(
    camera_from_world: &Isometry3<f64>,
    point: &Vector3<f64>,
    observed: &Vector2<f64>,
    sigma: f64,
) -> Option<(Vector2<f64>, Vector3<f64>)> {
    let pc = (camera_from_world * Point3::from(*point)).coords;
    if pc.z < MIN_DEPTH_M {
        return None;
    }
    let projected = Vector2::new(pc.x / pc.z, pc.y / pc.z);
    Some(((projected - observed) / sigma, pc))
}

/// Sum of the per-component prior costs and their Jacobian diagonal (1/σ, or 0 without).
fn prior_terms(prior: &FlightPrior) -> (ParamVector, ParamVector) {
    let inverse = |sigma: f64| {
        if sigma.is_finite() && sigma > 0.0 {
            1.0 / sigma
        } else {
            0.0
        }
    };
    let mut weights = ParamVector::zeros();
    for i in 0..3 {
        weights[i] = inverse(prior.velocity_sigma_mps);
        weights[i + 3] = inverse(prior.rate_sigma_radps);
        weights[i + 6] = inverse(prior.attitude_sigma_rad);
    }
    (prior.mean.to_vector(), weights)
}

impl<'a> Problem<'a> {
    fn new(
        model: &'a FlightModel,
        prior: &'a FlightPrior,
        settings: &'a BaSettings,
        sightings: &'a [Sighting],
        altitudes: &'a [AltitudeSample],
    ) -> Self {
        let mut keyframe_tau_s: Vec<f64> = sightings.iter().map(|s| s.tau_s).collect();
        keyframe_tau_s.sort_by(f64::total_cmp);
        keyframe_tau_s.dedup();
        let sighting_keyframe = sightings
            .iter()
            .map(|s| {
                keyframe_tau_s
                    .binary_search_by(|t| t.total_cmp(&s.tau_s))
                    .unwrap_or(0)
            })
            .collect();
        let mut order: Vec<usize> = (0..sightings.len()).collect();
        order.sort_by(|&a, &b| {
            (sightings[a].track_id, sightings[a].tau_s.to_bits())
                .cmp(&(sightings[b].track_id, sightings[b].tau_s.to_bits()))
        });
        Self {
            model,
            prior,
            settings,
            sightings,
            altitudes,
            order,
            keyframe_tau_s,
            sighting_keyframe,
        }
    }

    fn camera_poses(&self, theta: &ParamVector) -> Vec<Isometry3<f64>> {
        let params = FlightParams::from_vector(theta);
        self.keyframe_tau_s
            .iter()
            .map(|&tau| self.model.camera_from_world(&params, tau))
            .collect()
    }

    /// Tracks seen from two keyframes or more, the most-seen first (the longest baselines),
    /// triangulated from their rays under `start` where they meet at a usable angle in front
    /// of every camera; at most [`MAX_POINTS`].
    fn initial_points(&self, start: &FlightParams) -> Vec<GroundPoint> {
        let mut candidates = Vec::new();
        let mut first = 0;
        while first < self.order.len() {
            let id = self.sightings[self.order[first]].track_id;
            let mut end = first + 1;
            while end < self.order.len() && self.sightings[self.order[end]].track_id == id {
                end += 1;
            }
            if end - first >= 2 {
                candidates.push((first, end));
            }
            first = end;
        }
        // Stable: equally long tracks keep the tracker's order.
        candidates.sort_by_key(|&(first, end)| std::cmp::Reverse(end - first));
        let poses = self.camera_poses(&start.to_vector());
        let world_from_cameras: Vec<Isometry3<f64>> = poses.iter().map(|p| p.inverse()).collect();
        candidates
            .into_iter()
            .filter_map(|(first, end)| {
                let position_m = self.triangulate(&poses, &world_from_cameras, first, end)?;
                Some(GroundPoint {
                    first,
                    end,
                    position_m,
                })
            })
            .take(MAX_POINTS)
            .collect()
    }

    /// Least-squares meeting point of the rays of sightings `order[first..end]`, if the first
    /// and last rays meet at the minimum angle and the point is in front of every camera.
    fn triangulate(
        &self,
        poses: &[Isometry3<f64>],
        world_from_cameras: &[Isometry3<f64>],
        first: usize,
        end: usize,
    ) -> Option<Vector3<f64>> {
        let ray = |i: usize| {
            let x = self.sightings[i].normalized;
            let world_from_camera = &world_from_cameras[self.sighting_keyframe[i]];
            (
                (world_from_camera.rotation * Vector3::new(x.x, x.y, 1.0)).normalize(),
                world_from_camera.translation.vector,
            )
        };
        let sightings = &self.order[first..end];
        let (oldest, _) = ray(sightings[0]);
        let (newest, _) = ray(sightings[sightings.len() - 1]);
        if oldest.angle(&newest) < self.settings.min_ray_angle_rad {
            return None;
        }
        let mut normal = Matrix3::zeros();
        let mut rhs = Vector3::zeros();
        for &i in sightings {
            let (direction, centre) = ray(i);
            let projector = Matrix3::identity() - direction * direction.transpose();
            normal += projector;
            rhs += projector * centre;
        }
        let point = normal.try_inverse()? * rhs;
        let in_front = sightings.iter().all(|&i| {
            let pc = poses[self.sighting_keyframe[i]] * Point3::from(point);
            pc.z >= MIN_DEPTH_M
        });
        (in_front && point.iter().all(|v| v.is_finite())).then_some(point)
    }

    /// Total cost: robust reprojection, altimeter and priors, in σ².
    fn cost(&self, theta: &ParamVector, points: &[GroundPoint]) -> f64 {
        let poses = self.camera_poses(theta);
        let c = self.settings.robust_scale_sigmas;
        let mut total = 0.0;
        for point in points {
            for &i in &self.order[point.first..point.end] {
                let s = residual(
                    &poses[self.sighting_keyframe[i]],
                    &point.position_m,
                    &self.sightings[i].normalized,
                    self.settings.sighting_sigma,
                )
                .map_or(BEHIND_SQUARED_SIGMAS, |(r, _)| r.norm_squared());
                total += cauchy(s, c);
            }
        }
        total + self.flight_cost(theta)
    }

    /// Altimeter and prior cost, in σ².
    fn flight_cost(&self, theta: &ParamVector) -> f64 {
        let params = FlightParams::from_vector(theta);
        let altimeter: f64 = self
            .altitudes
            .iter()
            .map(|a| {
                let r = (self.model.position_m(&params, a.tau_s).z - a.altitude_m)
                    / self.settings.altimeter_sigma_m;
                cauchy(r * r, ALTIMETER_ROBUST_SIGMAS)
            })
            .sum();
        let (mean, weights) = prior_terms(self.prior);
        altimeter + (theta - mean).component_mul(&weights).norm_squared()
    }

    /// Median reprojection error of the points' sightings, σs (NaN without sightings).
    fn median_error_sigmas(&self, theta: &ParamVector, points: &[GroundPoint]) -> f64 {
        let poses = self.camera_poses(theta);
        let mut errors: Vec<f64> = points
            .iter()
            .flat_map(|p| self.order[p.first..p.end].iter().map(move |&i| (p, i)))
            .map(|(p, i)| {
                residual(
                    &poses[self.sighting_keyframe[i]],
                    &p.position_m,
                    &self.sightings[i].normalized,
                    self.settings.sighting_sigma,
                )
                .map_or(f64::INFINITY, |(r, _)| r.norm())
            })
            .collect();
        if errors.is_empty() {
            return f64::NAN;
        }
        let mid = errors.len() / 2;
        *errors.select_nth_unstable_by(mid, f64::total_cmp).1
    }

    /// Gauss–Newton normal equations at `theta` with Cauchy weights.
    fn normal_equations(&self, theta: &ParamVector, points: &[GroundPoint]) -> NormalEquations {
        let poses = self.camera_poses(theta);
        let motion = self.keyframe_motion_jacobians(theta);
        let mut normal = NormalEquations::new(points.len());
        let c = self.settings.robust_scale_sigmas;
        let sigma = self.settings.sighting_sigma;
        for (j, point) in points.iter().enumerate() {
            for &i in &self.order[point.first..point.end] {
                let k = self.sighting_keyframe[i];
                let observed = &self.sightings[i].normalized;
                let Some((r, pc)) = residual(&poses[k], &point.position_m, observed, sigma) else {
                    continue;
                };
                let inv_z = 1.0 / pc.z;
                let projection = SMatrix::<f64, 2, 3>::new(
                    inv_z,
                    0.0,
                    -pc.x * inv_z * inv_z,
                    0.0,
                    inv_z,
                    -pc.y * inv_z * inv_z,
                ) / sigma;
                let (body_position_m, camera_from_world) = &motion[k].0;
                let jac_point = projection * camera_from_world;
                // The camera-frame point is R_cw (X − p) minus a constant lever: a body shift
                // dp moves it by −R_cw dp, a world-frame rotation φ of the body by
                // R_cw [X − p]× φ.
                let from_body = (point.position_m - body_position_m).cross_matrix();
                let mut body_twist = SMatrix::<f64, 3, 6>::zeros();
                body_twist
                    .fixed_view_mut::<3, 3>(0, 0)
                    .copy_from(&(-camera_from_world));
                body_twist
                    .fixed_view_mut::<3, 3>(0, 3)
                    .copy_from(&(camera_from_world * from_body));
                let jac_theta: ParamJacobian = projection * body_twist * motion[k].1;
                let w = cauchy_weight(r.norm_squared(), c);
                normal.add_sighting(j, &jac_theta, &jac_point, &r, w);
            }
        }
        self.add_flight_rows(theta, &mut normal);
        normal
    }

    /// Per keyframe: the body position, `R_cw`, and the 6×9 derivative of the body's motion
    /// (position, then world-frame rotation) by the parameters, by forward differences (nine
    /// pose evaluations per keyframe, not per sighting).
    fn keyframe_motion_jacobians(&self, theta: &ParamVector) -> Vec<KeyframeMotion> {
        let params = FlightParams::from_vector(theta);
        let rotation_bc = self.model.body_from_camera.rotation;
        self.keyframe_tau_s
            .iter()
            .map(|&tau| {
                let body = self.model.world_from_body(&params, tau);
                let camera_from_world = (body.rotation * rotation_bc)
                    .inverse()
                    .to_rotation_matrix()
                    .into_inner();
                let mut jacobian = SMatrix::<f64, 6, 9>::zeros();
                for p in 0..9 {
                    let mut t = *theta;
                    t[p] += PARAM_STEP;
                    let moved = self
                        .model
                        .world_from_body(&FlightParams::from_vector(&t), tau);
                    let shift = (moved.translation.vector - body.translation.vector) / PARAM_STEP;
                    let turn =
                        (moved.rotation * body.rotation.inverse()).scaled_axis() / PARAM_STEP;
                    jacobian.fixed_view_mut::<3, 1>(0, p).copy_from(&shift);
                    jacobian.fixed_view_mut::<3, 1>(3, p).copy_from(&turn);
                }
                ((body.translation.vector, camera_from_world), jacobian)
            })
            .collect()
    }

    /// The altimeter rows (linear in `v0_z`) and the priors.
    fn add_flight_rows(&self, theta: &ParamVector, normal: &mut NormalEquations) {
        let params = FlightParams::from_vector(theta);
        let s = self.settings.altimeter_sigma_m;
        for a in self.altitudes {
            let r = (self.model.position_m(&params, a.tau_s).z - a.altitude_m) / s;
            let j = a.tau_s / s;
            let w = cauchy_weight(r * r, ALTIMETER_ROBUST_SIGMAS);
            normal.theta[(2, 2)] += w * j * j;
            normal.theta_gradient[2] += w * j * r;
        }
        let (mean, weights) = prior_terms(self.prior);
        for i in 0..9 {
            normal.theta[(i, i)] += weights[i] * weights[i];
            normal.theta_gradient[i] += weights[i] * weights[i] * (theta[i] - mean[i]);
        }
    }
}

/// The normal equations in blocks: shared, per point, and their coupling.
struct NormalEquations {
    theta: ParamHessian,
    theta_gradient: ParamVector,
    point: Vec<Matrix3<f64>>,
    point_gradient: Vec<Vector3<f64>>,
    cross: Vec<CrossHessian>,
}

impl NormalEquations {
    fn new(points: usize) -> Self {
        Self {
            theta: ParamHessian::zeros(),
            theta_gradient: ParamVector::zeros(),
            point: vec![Matrix3::zeros(); points],
            point_gradient: vec![Vector3::zeros(); points],
            cross: vec![CrossHessian::zeros(); points],
        }
    }

    fn add_sighting(
        &mut self,
        point: usize,
        jac_theta: &ParamJacobian,
        jac_point: &SMatrix<f64, 2, 3>,
        r: &Vector2<f64>,
        w: f64,
    ) {
        self.theta += jac_theta.transpose() * jac_theta * w;
        self.theta_gradient += jac_theta.transpose() * r * w;
        self.point[point] += jac_point.transpose() * jac_point * w;
        self.point_gradient[point] += jac_point.transpose() * r * w;
        self.cross[point] += jac_theta.transpose() * jac_point * w;
    }

    /// The covariance of the nine parameters at the solution (the points marginalized out):
    /// the inverse of the undamped Schur complement.
    fn parameter_covariance(&self) -> Option<ParamHessian> {
        let ((reduced, _), _) = self.reduced(0.0);
        reduced.cholesky().map(|c| c.inverse())
    }

    /// The Schur complement of the points, damped by `1 + lambda`, with its gradient and the
    /// points' inverted blocks.
    fn reduced(&self, lambda: f64) -> ((ParamHessian, ParamVector), Vec<Matrix3<f64>>) {
        let damp3 = |m: &Matrix3<f64>| {
            let mut d = *m;
            for i in 0..3 {
                d[(i, i)] = d[(i, i)] * (1.0 + lambda) + 1e-12;
            }
            d
        };
        let mut reduced = self.theta;
        for i in 0..9 {
            reduced[(i, i)] = reduced[(i, i)] * (1.0 + lambda) + 1e-12;
        }
        let mut reduced_gradient = self.theta_gradient;
        let mut inverses = Vec::with_capacity(self.point.len());
        for j in 0..self.point.len() {
            let inverse = damp3(&self.point[j])
                .try_inverse()
                .unwrap_or_else(Matrix3::zeros);
            let coupling = self.cross[j] * inverse;
            reduced -= coupling * self.cross[j].transpose();
            reduced_gradient -= coupling * self.point_gradient[j];
            inverses.push(inverse);
        }
        ((reduced, reduced_gradient), inverses)
    }

    /// The damped step (Marquardt scaling by `1 + lambda`) for the parameters and each point.
    fn solve(&self, lambda: f64) -> Option<(ParamVector, Vec<Vector3<f64>>)> {
        let ((reduced, reduced_gradient), inverses) = self.reduced(lambda);
        let step = -reduced.cholesky()?.solve(&reduced_gradient);
        let point_steps = (0..self.point.len())
            .map(|j| -(inverses[j] * (self.point_gradient[j] + self.cross[j].transpose() * step)))
            .collect();
        step.iter()
            .all(|v| v.is_finite())
            .then_some((step, point_steps))
    }
}
