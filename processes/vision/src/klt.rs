//! Pyramidal Lucas–Kanade (KLT) feature tracking with a forward–backward check.
//!
//! Bouguet's formulation: coarse to fine over the pyramid; at each level the template window
//! (intensity and gradient of the previous frame) is sampled once at the sub-pixel feature
//! position, then the displacement is refined by Gauss–Newton steps `δ = G⁻¹ Σ ∇I (I − J)` with
//! bilinear sampling of the next frame, until `|δ| < epsilon_px` or `max_iterations`.
//!
//! Every successful track is then tracked back from the next frame to the previous one
//! (initialised with the mirrored guess, never with the answer); a track whose round trip misses
//! its start by more than `forward_backward_max_px` is rejected. DESIGN.md §5: without that check
//! bad tracks pass as good under fast rotation.
//!
//! Buffers are allocated in [`KltTracker::new`] for a maximum number of points; `track` does not
//! allocate for up to that many points.
//!
//! ```
//! use hopnav_vision::{image::ImageView, klt::{KltConfig, KltTracker, TrackStatus},
//!     pyramid::{Pyramid, PyramidConfig}, synthetic::{AffineWarp, BlobTexture}};
//! use nalgebra::Point2;
//! let (w, h) = (96, 96);
//! let tex = BlobTexture::random(w, h, 150, 2);
//! let (mut a, mut b) = (vec![0u8; w * h], vec![0u8; w * h]);
//! tex.render(w, h, &AffineWarp::identity(), &mut a);
//! tex.render(w, h, &AffineWarp::translation(1.5, -0.5), &mut b);
//! let mut prev = Pyramid::new(w, h, PyramidConfig::default()).unwrap();
//! let mut next = Pyramid::new(w, h, PyramidConfig::default()).unwrap();
//! prev.build(&ImageView::packed(&a, w, h).unwrap()).unwrap();
//! next.build(&ImageView::packed(&b, w, h).unwrap()).unwrap();
//! let mut klt = KltTracker::new(KltConfig::default(), 16).unwrap();
//! let pts = [Point2::new(40.0f32, 50.0)];
//! let mut out = [Point2::origin()];
//! let mut status = [TrackStatus::Tracked];
//! klt.track(&prev, &next, &pts, &mut out, &mut status, false).unwrap();
//! if status[0] == TrackStatus::Tracked {
//!     assert!((out[0].x - 41.5).abs() < 0.2 && (out[0].y - 49.5).abs() < 0.2);
//! }
//! ```

mod window;

use crate::pyramid::Pyramid;
use crate::simd::LANES;
use nalgebra::{Point2, Vector2};
use window::{
    sample_window_lanes, sample_window_strided, sampled_mismatch, template_from_padded, window_fits,
};

/// Tracker settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KltConfig {
    /// Half window size; the window is `2r+1` pixels wide. Must be ≤ pyramid border − 3.
    pub window_radius_px: usize,
    /// Gauss–Newton iterations per level at most.
    pub max_iterations: usize,
    /// Stop when the update is shorter than this, in pixels, at full resolution.
    pub epsilon_px: f32,
    /// Same at the coarser levels, whose result is only a starting point (pixels of that level).
    pub coarse_epsilon_px: f32,
    /// Reject windows whose structure tensor's smaller eigenvalue, divided by the window's pixel
    /// count, is below this ((intensity/px)²).
    pub min_eigenvalue: f32,
    /// Forward–backward round-trip error limit in pixels; `None` disables the check.
    pub forward_backward_max_px: Option<f32>,
    /// Mean absolute intensity difference limit over the final window; `None` disables it.
    pub max_mean_abs_residual: Option<f32>,
}

impl Default for KltConfig {
    fn default() -> Self {
        Self {
            window_radius_px: 5,
            max_iterations: 20,
            epsilon_px: 0.01,
            coarse_epsilon_px: 0.05,
            min_eigenvalue: 1.0,
            forward_backward_max_px: Some(0.5),
            max_mean_abs_residual: Some(30.0),
        }
    }
}

/// Outcome for one feature.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TrackStatus {
    /// Tracked; the output position is valid.
    Tracked,
    /// The window left the image (or the padded border at a coarse level).
    OutOfBounds,
    /// The template window has too little texture (ill-conditioned `G`).
    LowTexture,
    /// The backward track did not return to the start.
    ForwardBackwardFailed,
    /// The final window differs too much from the template (occlusion, appearance change).
    LargeResidual,
    /// The input position was not finite.
    InvalidInput,
}

/// Counts of a [`KltTracker::track`] call.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct TrackStats {
    /// Tracks that survived every check.
    pub tracked: usize,
    /// Lost at the image border.
    pub out_of_bounds: usize,
    /// Rejected for low texture.
    pub low_texture: usize,
    /// Rejected by the forward–backward check.
    pub forward_backward: usize,
    /// Rejected for a large residual.
    pub large_residual: usize,
    /// Non-finite inputs.
    pub invalid_input: usize,
}

impl TrackStats {
    /// Counts one outcome.
    fn count(&mut self, status: TrackStatus) {
        match status {
            TrackStatus::Tracked => self.tracked += 1,
            TrackStatus::OutOfBounds => self.out_of_bounds += 1,
            TrackStatus::LowTexture => self.low_texture += 1,
            TrackStatus::ForwardBackwardFailed => self.forward_backward += 1,
            TrackStatus::LargeResidual => self.large_residual += 1,
            TrackStatus::InvalidInput => self.invalid_input += 1,
        }
    }
}

/// Error configuring the tracker or calling it.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum KltError {
    /// A configuration value is out of range.
    #[error("invalid KLT config: {field} = {value} ({allowed})")]
    BadConfig {
        /// Offending field.
        field: &'static str,
        /// Its value, formatted.
        value: String,
        /// The allowed range.
        allowed: &'static str,
    },
    /// The point, output and status slices differ in length.
    #[error("slice lengths differ: prev {prev}, next {next}, status {status}")]
    LengthMismatch {
        /// `prev_px.len()`.
        prev: usize,
        /// `next_px.len()`.
        next: usize,
        /// `status.len()`.
        status: usize,
    },
    /// More points than the tracker was sized for.
    #[error("{count} points exceed the tracker capacity {capacity}")]
    TooManyPoints {
        /// Points passed.
        count: usize,
        /// Capacity given to `new`.
        capacity: usize,
    },
    /// The pyramids differ in size or level count.
    #[error("pyramids differ in size or levels")]
    PyramidMismatch,
    /// The pyramid border cannot hold the window.
    #[error(
        "pyramid border {border_px} px too small for window radius {window_radius_px} px (needs radius + 2)"
    )]
    BorderTooSmall {
        /// Pyramid border.
        border_px: usize,
        /// Configured window radius.
        window_radius_px: usize,
    },
}

/// Pyramidal LK tracker with preallocated scratch buffers.
#[derive(Debug, Clone)]
pub struct KltTracker {
    config: KltConfig,
    capacity: usize,
    /// Row stride of the template, gradient and window buffers: the window width `2r+1`
    /// rounded up to [`LANES`], the extra columns zero (they add nothing to the sums), so the
    /// inner loops run on whole SIMD lanes.
    row_stride: usize,
    template: Vec<f32>,
    template_gx: Vec<f32>,
    template_gy: Vec<f32>,
    window: Vec<f32>,
    /// The `(n+2)²` intensity window the template and its gradients come from, in rows of
    /// `row_stride + LANES` (room for the lanes of the last column block's right neighbour).
    padded_template: Vec<f32>,
    /// 1 for the `2r+1` window columns of a `row_stride` row, 0 for the padding.
    lane_mask: Vec<f32>,
    /// Processing order (raster order of the start points).
    order: Vec<u32>,
    /// Forward initial guesses (needed to mirror the backward guess).
    guesses: Vec<Point2<f32>>,
    fb_errors_px: Vec<f32>,
}

impl KltTracker {
    /// Creates a tracker for up to `max_points` features per call.
    pub fn new(config: KltConfig, max_points: usize) -> Result<Self, KltError> {
        let bad = |field: &'static str, value: String, allowed: &'static str| {
            Err(KltError::BadConfig {
                field,
                value,
                allowed,
            })
        };
        if config.window_radius_px == 0 || config.window_radius_px > 32 {
            return bad(
                "window_radius_px",
                config.window_radius_px.to_string(),
                "1..=32",
            );
        }
        if config.max_iterations == 0 {
            return bad("max_iterations", "0".into(), ">= 1");
        }
        if !(config.epsilon_px.is_finite() && config.epsilon_px > 0.0) {
            return bad("epsilon_px", config.epsilon_px.to_string(), "> 0");
        }
        if !(config.coarse_epsilon_px.is_finite() && config.coarse_epsilon_px > 0.0) {
            return bad(
                "coarse_epsilon_px",
                config.coarse_epsilon_px.to_string(),
                "> 0",
            );
        }
        if !(config.min_eigenvalue.is_finite() && config.min_eigenvalue >= 0.0) {
            return bad("min_eigenvalue", config.min_eigenvalue.to_string(), ">= 0");
        }
        if let Some(fb) = config.forward_backward_max_px
            && !(fb.is_finite() && fb > 0.0)
        {
            return bad("forward_backward_max_px", fb.to_string(), "> 0");
        }
        if let Some(r) = config.max_mean_abs_residual
            && !(r.is_finite() && r > 0.0)
        {
            return bad("max_mean_abs_residual", r.to_string(), "> 0");
        }
        let n = 2 * config.window_radius_px + 1;
        let m = n.next_multiple_of(LANES);
        Ok(Self {
            config,
            capacity: max_points,
            row_stride: m,
            template: vec![0.0; n * m],
            template_gx: vec![0.0; n * m],
            template_gy: vec![0.0; n * m],
            window: vec![0.0; n * m],
            padded_template: vec![0.0; (n + 2) * (m + LANES)],
            lane_mask: (0..m).map(|c| if c < n { 1.0 } else { 0.0 }).collect(),
            order: Vec::with_capacity(max_points),
            guesses: Vec::with_capacity(max_points),
            fb_errors_px: Vec::with_capacity(max_points),
        })
    }

    /// The configuration.
    pub fn config(&self) -> &KltConfig {
        &self.config
    }

    /// Forward–backward errors of the last call (pixels; `NaN` where not measured).
    pub fn last_forward_backward_errors_px(&self) -> &[f32] {
        &self.fb_errors_px
    }

    /// Tracks `prev_px` from `prev` into `next`.
    ///
    /// With `use_initial_guess`, `next_px` holds predicted positions on entry (e.g. from a
    /// gyro-predicted rotation); otherwise tracking starts from `prev_px`. On return `next_px`
    /// holds the tracked positions and `status` why a track was dropped.
    pub fn track(
        &mut self,
        prev: &Pyramid,
        next: &Pyramid,
        prev_px: &[Point2<f32>],
        next_px: &mut [Point2<f32>],
        status: &mut [TrackStatus],
        use_initial_guess: bool,
    ) -> Result<TrackStats, KltError> {
        self.track_with_levels(prev, next, prev_px, next_px, status, use_initial_guess, &[])
    }

    /// Like [`Self::track`], with a per-point number of pyramid levels: point `i` is refined on
    /// levels `top_levels[i] − 1 … 0` only (clamped to `1..=` the usable levels). Points past
    /// the end of `top_levels` use every level.
    ///
    /// A good initial guess (e.g. a track's constant-velocity prediction) needs no coarse
    /// search: 2 levels instead of 4 halve the cost. Points with a poor guess (new corners)
    /// should keep every level.
    #[allow(clippy::too_many_arguments)]
    pub fn track_with_levels(
        &mut self,
        prev: &Pyramid,
        next: &Pyramid,
        prev_px: &[Point2<f32>],
        next_px: &mut [Point2<f32>],
        status: &mut [TrackStatus],
        use_initial_guess: bool,
        top_levels: &[u8],
    ) -> Result<TrackStats, KltError> {
        self.check_inputs(prev, next, prev_px, next_px, status)?;
        self.start_guesses(prev_px, next_px, use_initial_guess);
        self.sort_in_raster_order(prev_px);
        let mut stats = TrackStats::default();
        for k in 0..self.order.len() {
            let i = self.order[k] as usize;
            let max_levels = top_levels
                .get(i)
                .map_or(usize::MAX, |&l| usize::from(l).max(1));
            let (q, st) = self.track_forward_backward(prev, next, i, prev_px[i], max_levels);
            next_px[i] = q;
            status[i] = st;
            stats.count(st);
        }
        Ok(stats)
    }

    /// Rejects slices of different lengths, more points than the capacity, pyramids that
    /// differ, and a pyramid border too small for the window.
    fn check_inputs(
        &self,
        prev: &Pyramid,
        next: &Pyramid,
        prev_px: &[Point2<f32>],
        next_px: &[Point2<f32>],
        status: &[TrackStatus],
    ) -> Result<(), KltError> {
        if prev_px.len() != next_px.len() || prev_px.len() != status.len() {
            return Err(KltError::LengthMismatch {
                prev: prev_px.len(),
                next: next_px.len(),
                status: status.len(),
            });
        }
        if prev_px.len() > self.capacity {
            return Err(KltError::TooManyPoints {
                count: prev_px.len(),
                capacity: self.capacity,
            });
        }
        if prev.base_width() != next.base_width()
            || prev.base_height() != next.base_height()
            || prev.num_levels() != next.num_levels()
        {
            return Err(KltError::PyramidMismatch);
        }
        let border_px = prev.config().border_px.min(next.config().border_px);
        if border_px < self.config.window_radius_px + 3 {
            return Err(KltError::BorderTooSmall {
                border_px,
                window_radius_px: self.config.window_radius_px,
            });
        }
        Ok(())
    }

    /// Stores each point's forward guess (its given next position, or its start) and clears
    /// its forward–backward error.
    fn start_guesses(
        &mut self,
        prev_px: &[Point2<f32>],
        next_px: &[Point2<f32>],
        use_initial_guess: bool,
    ) {
        self.guesses.clear();
        self.fb_errors_px.clear();
        for (i, &p) in prev_px.iter().enumerate() {
            let guess = if use_initial_guess { next_px[i] } else { p };
            self.guesses.push(guess);
            self.fb_errors_px.push(f32::NAN);
        }
    }

    /// Orders the points in raster order (16-px bands), which keeps consecutive windows in
    /// cache; results are independent of the order.
    fn sort_in_raster_order(&mut self, prev_px: &[Point2<f32>]) {
        self.order.clear();
        self.order.extend(0..prev_px.len() as u32);
        self.order.sort_unstable_by_key(|&i| {
            let p = prev_px[i as usize];
            let band = if p.y.is_finite() {
                (p.y.max(0.0) as u32) >> 4
            } else {
                u32::MAX
            };
            let x = if p.x.is_finite() {
                p.x.max(0.0) as u32
            } else {
                0
            };
            (band, x)
        });
    }

    /// Tracks point `i` (at `p`) forward from its stored guess, then back to check the round
    /// trip; a lost track reports its start where its end is not finite.
    fn track_forward_backward(
        &mut self,
        prev: &Pyramid,
        next: &Pyramid,
        i: usize,
        p: Point2<f32>,
        max_levels: usize,
    ) -> (Point2<f32>, TrackStatus) {
        let guess = self.guesses[i];
        let (mut q, mut st) = self.track_point(prev, next, p, guess, true, max_levels);
        if st == TrackStatus::Tracked
            && let Some(limit) = self.config.forward_backward_max_px
        {
            // Mirror the forward guess so the backward pass gets no hint of the answer.
            // (Seeding it at the start point over two levels, as VINS-Fusion does, is
            // cheaper but measured weak here: occluded tracks 40 px off were kept.)
            let back_guess = q - (guess - p);
            let (back, back_status) =
                self.track_point(next, prev, q, back_guess, false, max_levels);
            if back_status == TrackStatus::Tracked {
                let err = (back - p).norm();
                self.fb_errors_px[i] = err;
                if err > limit {
                    st = TrackStatus::ForwardBackwardFailed;
                }
            } else {
                st = TrackStatus::ForwardBackwardFailed;
            }
        }
        if st != TrackStatus::Tracked && !(q.x.is_finite() && q.y.is_finite()) {
            q = p;
        }
        (q, st)
    }

    /// Tracks one point from `from` to `to`; `check_residual` applies the residual test.
    fn track_point(
        &mut self,
        from: &Pyramid,
        to: &Pyramid,
        p0: Point2<f32>,
        guess: Point2<f32>,
        check_residual: bool,
        max_levels: usize,
    ) -> (Point2<f32>, TrackStatus) {
        if !(p0.x.is_finite() && p0.y.is_finite() && guess.x.is_finite() && guess.y.is_finite()) {
            return (p0, TrackStatus::InvalidInput);
        }
        let r = self.config.window_radius_px;
        let n_px = ((2 * r + 1) * (2 * r + 1)) as f32;
        // Levels smaller than two windows are mostly border: they mislead more than they help.
        let min_level_size = 2 * (2 * r + 1);
        let levels = (0..from.num_levels())
            .take_while(|&l| {
                from.level(l)
                    .is_some_and(|lv| lv.width().min(lv.height()) >= min_level_size)
            })
            .count()
            .min(max_levels)
            .max(1);
        let top_scale = 1.0 / (1u32 << (levels - 1)) as f32;
        let mut d = (guess - p0) * top_scale;
        let mut result = p0;
        for l in (0..levels).rev() {
            let entry_d = d;
            let outcome = self.refine_level(from, to, l, p0, &mut d);
            match outcome {
                TrackStatus::Tracked => {}
                // A coarse level that fails (border, flat) keeps the propagated guess; only
                // the full-resolution level decides the status.
                _ if l > 0 => d = entry_d,
                status => return (p0, status),
            }
            if l > 0 {
                d *= 2.0;
            } else {
                result = p0 + d;
            }
        }
        let Some(base) = to.level(0) else {
            return (p0, TrackStatus::OutOfBounds);
        };
        let (w, h) = (base.width() as f32, base.height() as f32);
        if !(result.x >= 0.0 && result.y >= 0.0 && result.x <= w - 1.0 && result.y <= h - 1.0) {
            return (result, TrackStatus::OutOfBounds);
        }
        if check_residual && let Some(limit) = self.config.max_mean_abs_residual {
            // The padding columns are zero in both buffers.
            sample_window_strided(&base.image, result, r, self.row_stride, &mut self.window);
            let sad: f32 = self
                .template
                .iter()
                .zip(&self.window)
                .map(|(a, b)| (a - b).abs())
                .sum();
            if sad / n_px > limit {
                return (result, TrackStatus::LargeResidual);
            }
        }
        (result, TrackStatus::Tracked)
    }
}

impl KltTracker {
    /// Gauss–Newton refinement of the displacement `d` (in level-`l` pixels) of `p0` (level-0
    /// pixels) at pyramid level `l`.
    fn refine_level(
        &mut self,
        from: &Pyramid,
        to: &Pyramid,
        l: usize,
        p0: Point2<f32>,
        d: &mut Vector2<f32>,
    ) -> TrackStatus {
        let r = self.config.window_radius_px;
        let n_px = ((2 * r + 1) * (2 * r + 1)) as f32;
        let (Some(lf), Some(lt)) = (from.level(l), to.level(l)) else {
            return TrackStatus::OutOfBounds;
        };
        let p = p0 * (1.0 / (1u32 << l) as f32);
        if !window_fits(&lf.image, p, r) {
            return TrackStatus::OutOfBounds;
        }
        // One (n+2)² intensity window; the template and its central-difference gradients come
        // from it (cheaper than sampling three planes; the LK fixed point does not depend on the
        // gradient approximation, only the convergence rate does).
        let padded_stride = self.row_stride + LANES;
        sample_window_lanes(
            &lf.image,
            p,
            r + 1,
            padded_stride,
            &mut self.padded_template,
        );
        let (gxx, gxy, gyy) = template_from_padded(
            &self.padded_template,
            padded_stride,
            &self.lane_mask,
            &mut self.template,
            &mut self.template_gx,
            &mut self.template_gy,
        );
        let det = gxx * gyy - gxy * gxy;
        let min_eig =
            0.5 * (gxx + gyy - ((gxx - gyy) * (gxx - gyy) + 4.0 * gxy * gxy).sqrt()) / n_px;
        if min_eig.is_nan() || min_eig < self.config.min_eigenvalue || det.abs() < f32::EPSILON {
            return TrackStatus::LowTexture;
        }
        let inv_det = 1.0 / det;
        let eps = if l == 0 {
            self.config.epsilon_px
        } else {
            self.config.coarse_epsilon_px
        };
        let eps_sq = eps * eps;
        for _ in 0..self.config.max_iterations {
            let q = p + *d;
            if !window_fits(&lt.image, q, r) {
                return TrackStatus::OutOfBounds;
            }
            let (bx, by) = sampled_mismatch(
                &lt.image,
                q,
                r,
                self.row_stride,
                &self.template,
                &self.template_gx,
                &self.template_gy,
            );
            let step = Vector2::new(
                inv_det * (gyy * bx - gxy * by),
                inv_det * (gxx * by - gxy * bx),
            );
            if !(step.x.is_finite() && step.y.is_finite()) {
                return TrackStatus::LowTexture;
            }
            *d += step;
            if step.norm_squared() < eps_sq {
                break;
            }
        }
        TrackStatus::Tracked
    }
}

#[cfg(test)]
mod tests;
