//! Sparse stereo matching on a rectified pair: for a left feature, search the same row of the
//! right view with zero-mean normalized cross-correlation (ZNCC) on a square patch, refine the
//! disparity with a parabola through the three best scores, confirm it with a right-to-left
//! search (left–right consistency), and triangulate `Z = f·b / d` with `σ_Z = Z²·σ_d / (f·b)`.
//!
//! Rows are interpolated at the feature's sub-pixel `y` once per feature into preallocated
//! bands; nothing is allocated per call.
//!
//! ```
//! use hopnav_rover_vo::stereo::{StereoMatcher, StereoParams};
//! use hopnav_vision::image::ImageView;
//! let (w, h) = (64, 32);
//! let tex = |x: i32, y: i32| ((x * 37 + y * 91) % 97 * 2 + (x * x + 3 * y * y) % 13) as u8;
//! let left: Vec<u8> = (0..w * h).map(|i| tex((i % w) as i32, (i / w) as i32)).collect();
//! let right: Vec<u8> = (0..w * h).map(|i| tex((i % w) as i32 + 5, (i / w) as i32)).collect();
//! let params = StereoParams { fx_px: 100.0, cx_px: 32.0, cy_px: 16.0, baseline_m: 0.2, ..StereoParams::default() };
//! let mut m = StereoMatcher::new(w, h, params).unwrap();
//! let l = ImageView::packed(&left, w as usize, h as usize).unwrap();
//! let r = ImageView::packed(&right, w as usize, h as usize).unwrap();
//! let p = m.match_point(&l, &r, 40.0, 16.0).unwrap();
//! assert!((p.disparity_px - 5.0).abs() < 0.2);
//! ```

use hopnav_vision::image::ImageView;
use nalgebra::Point3;

use crate::stereo_edge::Bands;
use crate::stereo_patch::{fill_band, parabola, patch_stats, zncc};

/// Geometry and matching settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StereoParams {
    /// Focal length, pixels (both views, rectified).
    pub fx_px: f64,
    /// Focal length along y, pixels.
    pub fy_px: f64,
    /// Principal point x, pixels.
    pub cx_px: f64,
    /// Principal point y, pixels.
    pub cy_px: f64,
    /// Baseline, metres (right camera along left camera +x).
    pub baseline_m: f64,
    /// Smallest disparity accepted, pixels.
    pub min_disparity_px: f64,
    /// Largest disparity searched, pixels.
    pub max_disparity_px: f64,
    /// Patch half size, pixels.
    pub patch_radius_px: usize,
    /// Minimum ZNCC of the best match.
    pub min_zncc: f64,
    /// Left–right consistency limit, pixels.
    pub left_right_max_px: f64,
    /// Disparity noise σ, pixels.
    pub disparity_sigma_px: f64,
    /// Largest depth returned, metres.
    pub max_depth_m: f64,
    /// Minimum standard deviation of the patch intensity (texture), grey levels.
    pub min_patch_std: f64,
    /// Largest disparity gap between the halves of the patch (left and right, top and
    /// bottom), each matched on its own, pixels; a wider gap is a depth edge inside the patch
    /// and the match is refused (`stereo_edge.rs`). 0 turns the check off.
    pub max_half_disagreement_px: f64,
}

impl Default for StereoParams {
    fn default() -> Self {
        Self {
            fx_px: 277.0,
            fy_px: 277.0,
            cx_px: 160.0,
            cy_px: 120.0,
            baseline_m: 0.2,
            min_disparity_px: 1.5,
            max_disparity_px: 64.0,
            patch_radius_px: 3,
            min_zncc: 0.8,
            left_right_max_px: 1.0,
            disparity_sigma_px: 0.2,
            max_depth_m: 30.0,
            min_patch_std: 2.0,
            max_half_disagreement_px: 0.0,
        }
    }
}

/// Error creating a [`StereoMatcher`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StereoError {
    /// A parameter is out of range.
    #[error("stereo parameter {name} = {value} is out of range")]
    BadParameter {
        /// Which.
        name: &'static str,
        /// Its value.
        value: f64,
    },
}

/// Why a feature has no stereo match.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NoMatch {
    /// Too close to the border, non-finite position, or images of the wrong size.
    OutOfBounds,
    /// The patch is flat.
    LowTexture,
    /// The best ZNCC is below the limit.
    LowScore,
    /// The right-to-left search lands elsewhere.
    LeftRightMismatch,
    /// The disparity is outside the accepted range (too far or too close).
    BadDisparity,
    /// The halves of the patch match at different disparities: it straddles a depth edge.
    DepthEdge,
}

/// A triangulated stereo match.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StereoPoint {
    /// Point in the left camera frame, metres.
    pub point_camera_m: Point3<f64>,
    /// σ of the depth, metres.
    pub depth_sigma_m: f64,
    /// Sub-pixel disparity, pixels.
    pub disparity_px: f64,
    /// ZNCC of the match.
    pub zncc: f64,
}

/// Row-search ZNCC matcher with preallocated bands.
#[derive(Debug, Clone)]
pub struct StereoMatcher {
    params: StereoParams,
    width: usize,
    height: usize,
    band_left: Vec<f32>,
    band_right: Vec<f32>,
    scores: Vec<f32>,
    template: Vec<f32>,
    col_sum: Vec<f32>,
    col_sq: Vec<f32>,
}

impl StereoMatcher {
    /// A matcher for `width × height` views.
    pub fn new(width: u32, height: u32, params: StereoParams) -> Result<Self, StereoError> {
        let bad = |name, value| Err(StereoError::BadParameter { name, value });
        let positive = |v: f64| v.is_finite() && v > 0.0;
        if !positive(params.fx_px) {
            return bad("fx_px", params.fx_px);
        }
        if !positive(params.fy_px) {
            return bad("fy_px", params.fy_px);
        }
        if !positive(params.baseline_m) {
            return bad("baseline_m", params.baseline_m);
        }
        if !(params.cx_px.is_finite() && params.cy_px.is_finite()) {
            return bad("cx_px", params.cx_px);
        }
        if !(positive(params.min_disparity_px)
            && params.max_disparity_px > params.min_disparity_px + 1.0)
            || params.max_disparity_px > 1024.0
        {
            return bad("max_disparity_px", params.max_disparity_px);
        }
        if params.patch_radius_px == 0 || params.patch_radius_px > 7 {
            return bad("patch_radius_px", params.patch_radius_px as f64);
        }
        if !positive(params.disparity_sigma_px) {
            return bad("disparity_sigma_px", params.disparity_sigma_px);
        }
        if !positive(params.max_depth_m) {
            return bad("max_depth_m", params.max_depth_m);
        }
        if !(params.max_half_disagreement_px.is_finite() && params.max_half_disagreement_px >= 0.0)
        {
            return bad("max_half_disagreement_px", params.max_half_disagreement_px);
        }
        let (width, height) = (width as usize, height as usize);
        let rows = 2 * params.patch_radius_px + 1;
        Ok(Self {
            params,
            width,
            height,
            band_left: vec![0.0; rows * width],
            band_right: vec![0.0; rows * width],
            scores: vec![0.0; params.max_disparity_px.ceil() as usize + 2],
            template: vec![0.0; rows * rows],
            col_sum: vec![0.0; width],
            col_sq: vec![0.0; width],
        })
    }

    /// The parameters.
    pub fn params(&self) -> &StereoParams {
        &self.params
    }

    /// Matches the left feature at `(u_px, v_px)` over the whole disparity range and
    /// triangulates it in the left camera frame.
    pub fn match_point(
        &mut self,
        left: &ImageView<'_>,
        right: &ImageView<'_>,
        u_px: f32,
        v_px: f32,
    ) -> Result<StereoPoint, NoMatch> {
        self.match_point_in_range(left, right, u_px, v_px, None)
    }

    /// As [`Self::match_point`], searching only disparities in `range_px` (clipped to the
    /// configured range), e.g. around a prediction.
    pub fn match_point_in_range(
        &mut self,
        left: &ImageView<'_>,
        right: &ImageView<'_>,
        u_px: f32,
        v_px: f32,
        range_px: Option<(f64, f64)>,
    ) -> Result<StereoPoint, NoMatch> {
        let xl = self.feature_column(left, right, u_px, v_px)?;
        let (d_min, d_max) = self.disparity_search(range_px, xl)?;
        self.load_bands(left, right, v_px, xl, d_max);
        let (mean_l, std_l) = self.left_patch_texture(xl)?;
        self.prepare_forward_search(xl, d_min, d_max, mean_l);
        let (score, d_best) = self.forward_search(xl, d_min, d_max, std_l);
        let disparity = self.refine_disparity(score, d_best, d_min, d_max)?;
        self.left_right_check(xl, disparity, d_min)?;
        self.depth_edge_check(xl, disparity, d_min, d_max)?;
        self.triangulate(u_px, v_px, disparity, score)
    }

    /// Patch side (and band rows), pixels.
    fn patch_side(&self) -> usize {
        2 * self.params.patch_radius_px + 1
    }

    /// The left feature's integer column, if both views have the configured size and the
    /// feature's patch lies inside them.
    fn feature_column(
        &self,
        left: &ImageView<'_>,
        right: &ImageView<'_>,
        u_px: f32,
        v_px: f32,
    ) -> Result<isize, NoMatch> {
        let r = self.params.patch_radius_px as isize;
        let (w, h) = (self.width as isize, self.height as isize);
        if left.width() != self.width
            || right.width() != self.width
            || left.height() != self.height
            || right.height() != self.height
            || !u_px.is_finite()
            || !v_px.is_finite()
        {
            return Err(NoMatch::OutOfBounds);
        }
        let xl = u_px.round() as isize;
        let y_top = v_px - r as f32;
        if xl - r < 0 || xl + r >= w || y_top < 0.0 || (v_px + r as f32) as isize + 1 >= h {
            return Err(NoMatch::OutOfBounds);
        }
        Ok(xl)
    }

    /// Integer disparities `(d_min, d_max)` searched: `range_px` clipped to the configured
    /// range and to the image, with one spare below for the parabola.
    fn disparity_search(
        &self,
        range_px: Option<(f64, f64)>,
        xl: isize,
    ) -> Result<(isize, isize), NoMatch> {
        let p = &self.params;
        let r = p.patch_radius_px as isize;
        let (lo_px, hi_px) = match range_px {
            Some((lo, hi)) if lo.is_finite() && hi.is_finite() => {
                (lo.max(p.min_disparity_px), hi.min(p.max_disparity_px))
            }
            _ => (p.min_disparity_px, p.max_disparity_px),
        };
        let d_max = (hi_px.ceil() as isize).min(xl - r);
        let d_min = (lo_px.floor() as isize).max(1) - 1;
        if d_max < d_min + 2 {
            return Err(NoMatch::BadDisparity);
        }
        Ok((d_min, d_max))
    }

    /// Interpolates both bands at the feature's sub-pixel row, over the columns needed: the
    /// left patch and every right patch of the search.
    fn load_bands(
        &mut self,
        left: &ImageView<'_>,
        right: &ImageView<'_>,
        v_px: f32,
        xl: isize,
        d_max: isize,
    ) {
        let r = self.params.patch_radius_px as isize;
        let y_top = v_px - r as f32;
        let rows = self.patch_side();
        let x_lo = (xl - d_max - r).max(0) as usize;
        let x_hi = (xl + r) as usize;
        fill_band(
            left,
            &mut self.band_left,
            self.width,
            y_top,
            rows,
            x_lo,
            x_hi,
        );
        fill_band(
            right,
            &mut self.band_right,
            self.width,
            y_top,
            rows,
            x_lo,
            x_hi,
        );
    }

    /// Mean and standard deviation of the left patch, if it has enough texture to match.
    fn left_patch_texture(&self, xl: isize) -> Result<(f32, f32), NoMatch> {
        let r = self.params.patch_radius_px;
        let Some((mean_l, std_l)) = patch_stats(
            &self.band_left,
            self.width,
            self.patch_side(),
            xl as usize,
            r,
        ) else {
            return Err(NoMatch::LowTexture);
        };
        if f64::from(std_l) < self.params.min_patch_std {
            return Err(NoMatch::LowTexture);
        }
        Ok((mean_l, std_l))
    }

    /// Fills the zero-mean left template and the per-column sums of the right band, so that
    /// each candidate of the forward search is one multiply-add per pixel.
    fn prepare_forward_search(&mut self, xl: isize, d_min: isize, d_max: isize, mean_l: f32) {
        let r = self.params.patch_radius_px as isize;
        let side = self.patch_side();
        let rows = side;
        for k in 0..rows {
            for c in 0..side {
                self.template[k * side + c] =
                    self.band_left[k * self.width + xl as usize - r as usize + c] - mean_l;
            }
        }
        let c_lo = (xl - d_max - r) as usize;
        let c_hi = (xl - d_min + r) as usize;
        for x in c_lo..=c_hi {
            let (mut s1, mut s2) = (0.0f32, 0.0f32);
            for k in 0..rows {
                let v = self.band_right[k * self.width + x];
                s1 += v;
                s2 += v * v;
            }
            self.col_sum[x] = s1;
            self.col_sq[x] = s2;
        }
    }

    /// Forward search: the right patch at `xl − d` for every `d` in `d_min..=d_max`, scores
    /// kept for the parabola; returns the best `(score, d)`.
    fn forward_search(
        &mut self,
        xl: isize,
        d_min: isize,
        d_max: isize,
        std_l: f32,
    ) -> (f32, isize) {
        let r = self.params.patch_radius_px as isize;
        let side = self.patch_side();
        let rows = side;
        let n = (rows * side) as f32;
        let mut best = (f32::NEG_INFINITY, d_min);
        for d in d_min..=d_max {
            let x0 = (xl - d - r) as usize;
            let (mut sb, mut sb2, mut sab) = (0.0f32, 0.0f32, 0.0f32);
            for c in 0..side {
                sb += self.col_sum[x0 + c];
                sb2 += self.col_sq[x0 + c];
            }
            for k in 0..rows {
                let row = &self.band_right[k * self.width + x0..k * self.width + x0 + side];
                let t = &self.template[k * side..(k + 1) * side];
                for (a, b) in t.iter().zip(row) {
                    sab += a * b;
                }
            }
            let mean_b = sb / n;
            let var_b = (sb2 / n - mean_b * mean_b).max(0.0);
            let s = if var_b < 1e-6 {
                -1.0
            } else {
                (sab / n) / (std_l * var_b.sqrt())
            };
            self.scores[d as usize] = s;
            if s > best.0 {
                best = (s, d);
            }
        }
        best
    }

    /// The sub-pixel disparity of the best forward score, if it is good enough and not at an
    /// end of the search (where the parabola has no neighbour).
    fn refine_disparity(
        &self,
        score: f32,
        d_best: isize,
        d_min: isize,
        d_max: isize,
    ) -> Result<f64, NoMatch> {
        if f64::from(score) < self.params.min_zncc {
            return Err(NoMatch::LowScore);
        }
        if d_best <= d_min || d_best >= d_max {
            return Err(NoMatch::BadDisparity);
        }
        let offset = parabola(
            self.scores[(d_best - 1) as usize],
            score,
            self.scores[(d_best + 1) as usize],
        );
        Ok(d_best as f64 + offset)
    }

    /// Left–right check: the right patch at its integer column searched along the left row
    /// must land back on the left feature.
    fn left_right_check(&self, xl: isize, disparity: f64, d_min: isize) -> Result<(), NoMatch> {
        let r = self.params.patch_radius_px as isize;
        let w = self.width as isize;
        let rows = self.patch_side();
        let xr = (xl as f64 - disparity).round() as isize;
        if xr - r < 0 {
            return Err(NoMatch::OutOfBounds);
        }
        let Some((mean_r, std_r)) =
            patch_stats(&self.band_right, self.width, rows, xr as usize, r as usize)
        else {
            return Err(NoMatch::LowTexture);
        };
        let back_score = |d: isize| {
            zncc(
                &self.band_right,
                xr as usize,
                mean_r,
                std_r,
                &self.band_left,
                (xr + d) as usize,
                self.width,
                rows,
                r as usize,
            )
        };
        let mut back = (f32::NEG_INFINITY, 0isize);
        let lo = (xl - xr - 2).max(d_min);
        let hi = (xl - xr + 2).min(w - 1 - r - xr);
        for d in lo..=hi {
            let s = back_score(d);
            if s > back.0 {
                back = (s, d);
            }
        }
        if back.0 == f32::NEG_INFINITY {
            return Err(NoMatch::LeftRightMismatch);
        }
        let mut back_scores = [f32::NEG_INFINITY; 3];
        for (k, slot) in back_scores.iter_mut().enumerate() {
            let d = back.1 + k as isize - 1;
            if xr + d + r < w && d >= 0 {
                *slot = back_score(d);
            }
        }
        let back_disp = back.1 as f64 + parabola(back_scores[0], back_scores[1], back_scores[2]);
        let back_xl = xr as f64 + back_disp;
        if (back_xl - xl as f64 - 0.0).abs()
            > self.params.left_right_max_px + (xr as f64 - (xl as f64 - disparity)).abs()
        {
            return Err(NoMatch::LeftRightMismatch);
        }
        Ok(())
    }

    /// Refuses a patch whose halves match at disparities further apart than
    /// `max_half_disagreement_px`: it straddles a depth edge.
    fn depth_edge_check(
        &self,
        xl: isize,
        disparity: f64,
        d_min: isize,
        d_max: isize,
    ) -> Result<(), NoMatch> {
        let limit_px = self.params.max_half_disagreement_px;
        if limit_px <= 0.0 {
            return Ok(());
        }
        let bands = Bands {
            left: &self.band_left,
            right: &self.band_right,
            width: self.width,
        };
        let gap_px =
            bands.half_disagreement_px(self.params.patch_radius_px, xl, disparity, (d_min, d_max));
        if gap_px > limit_px {
            return Err(NoMatch::DepthEdge);
        }
        Ok(())
    }

    /// The point in the left camera frame for `disparity`, with its depth σ, if the depth is
    /// in range.
    fn triangulate(
        &self,
        u_px: f32,
        v_px: f32,
        disparity: f64,
        score: f32,
    ) -> Result<StereoPoint, NoMatch> {
        let p = &self.params;
        if disparity < p.min_disparity_px {
            return Err(NoMatch::BadDisparity);
        }
        let fb = p.fx_px * p.baseline_m;
        let z = fb / disparity;
        if !(z.is_finite() && z > 0.0 && z <= p.max_depth_m) {
            return Err(NoMatch::BadDisparity);
        }
        let x = (f64::from(u_px) - p.cx_px) / p.fx_px * z;
        let y = (f64::from(v_px) - p.cy_px) / p.fy_px * z;
        Ok(StereoPoint {
            point_camera_m: Point3::new(x, y, z),
            depth_sigma_m: z * z * p.disparity_sigma_px / fb,
            disparity_px: disparity,
            zncc: f64::from(score),
        })
    }
}

#[cfg(test)]
#[path = "stereo_tests.rs"]
mod tests;
