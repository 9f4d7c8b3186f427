//! Shi–Tomasi corner detection with grid bucketing, a global cap and a minimum distance to
//! existing tracks.
//!
//! The response is the smaller eigenvalue of the gradient structure tensor summed over a
//! `(2r+1)²` block. Local maxima above `max(quality_level · max_response, min_response)` are taken
//! strongest first, subject to: at most `ceil(max_features / cells)` features per grid cell
//! (existing tracks count), at least `min_distance_px` from every existing track and accepted
//! corner, and at most `max_features` in total (existing tracks count). Optionally
//! ([`CornerConfig::fill_leftover_budget`]) a second pass gives the budget left by texture-poor
//! cells to the strongest corners that full cells turned away. Positions are refined to
//! sub-pixel by a parabola fit of the response.
//!
//! ```
//! use hopnav_vision::{corners::{CornerConfig, CornerDetector}, image::ImageView,
//!     pyramid::{Pyramid, PyramidConfig}, synthetic::{AffineWarp, BlobTexture}};
//! let mut pixels = vec![0u8; 96 * 96];
//! BlobTexture::random(96, 96, 150, 3).render(96, 96, &AffineWarp::identity(), &mut pixels);
//! let mut pyr = Pyramid::new(96, 96, PyramidConfig::default()).unwrap();
//! pyr.build(&ImageView::packed(&pixels, 96, 96).unwrap()).unwrap();
//! let config = CornerConfig { max_features: 50, ..CornerConfig::default() };
//! let mut detector = CornerDetector::new(96, 96, config).unwrap();
//! let mut corners = Vec::new();
//! detector.detect(pyr.level(0).unwrap(), &[], &mut corners).unwrap();
//! assert!(!corners.is_empty() && corners.len() <= 50);
//! ```

use crate::pyramid::PyramidLevel;
use nalgebra::Point2;

const NONE: u32 = u32::MAX;

/// Detector settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CornerConfig {
    /// Cap on existing tracks plus new corners.
    pub max_features: usize,
    /// Bucketing grid columns.
    pub grid_cols: usize,
    /// Bucketing grid rows.
    pub grid_rows: usize,
    /// Minimum distance between features, in pixels.
    pub min_distance_px: f32,
    /// Relative threshold on the response (fraction of the frame's strongest response).
    pub quality_level: f32,
    /// Absolute response floor (sum over the block of squared gradients, (intensity/px)²);
    /// keeps flat frames (sky) from producing noise corners.
    pub min_response: f32,
    /// Structure-tensor block radius in pixels (block is `2r+1` wide); must be < pyramid border.
    pub block_radius_px: usize,
    /// No corner closer than this to the image edge, in pixels.
    pub border_px: usize,
    /// After the bucketed pass, give the budget left by texture-poor cells to the strongest
    /// remaining corners (cells may then exceed their cap; min distance still holds).
    pub fill_leftover_budget: bool,
}

impl Default for CornerConfig {
    fn default() -> Self {
        Self {
            max_features: 1000,
            grid_cols: 8,
            grid_rows: 8,
            min_distance_px: 6.0,
            quality_level: 0.01,
            min_response: 200.0,
            block_radius_px: 2,
            border_px: 8,
            fill_leftover_budget: false,
        }
    }
}

/// Error creating a detector or detecting.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CornerError {
    /// A configuration value is out of range.
    #[error("invalid corner config: {field} = {value} ({allowed})")]
    BadConfig {
        /// Offending field.
        field: &'static str,
        /// Its value, formatted.
        value: String,
        /// The allowed range.
        allowed: &'static str,
    },
    /// The level's size differs from the detector's.
    #[error("level is {got_width}x{got_height}, detector made for {width}x{height}")]
    SizeMismatch {
        /// Detector width.
        width: usize,
        /// Detector height.
        height: usize,
        /// Level width.
        got_width: usize,
        /// Level height.
        got_height: usize,
    },
    /// The level's border is too thin for the structure-tensor block.
    #[error("pyramid border {pad_px} px must exceed block radius {block_radius_px} px")]
    BorderTooThin {
        /// Pyramid border.
        pad_px: usize,
        /// Configured block radius.
        block_radius_px: usize,
    },
}

/// A detected corner.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Corner {
    /// Sub-pixel position.
    pub position_px: Point2<f32>,
    /// Minimum-eigenvalue response.
    pub response: f32,
}

#[derive(Debug, Clone, Copy)]
struct Candidate {
    x: u16,
    y: u16,
    response: f32,
}

/// Shi–Tomasi detector with preallocated buffers for one image size.
#[derive(Debug, Clone)]
pub struct CornerDetector {
    config: CornerConfig,
    width: usize,
    height: usize,
    /// Horizontal box sums of gxx, gxy, gyy for rows `-r..h+r`.
    row_sums: [Vec<f32>; 3],
    /// Gradient products of one row, `w + 2r` wide.
    product_rows: [Vec<f32>; 3],
    /// Vertical running sums of `row_sums`, one row wide.
    col_sums: [Vec<f32>; 3],
    response: Vec<f32>,
    /// Horizontal 3-maxima of `response`.
    row_max: Vec<f32>,
    /// Per-row local-maximum flags.
    max_flags: Vec<u8>,
    candidates: Vec<Candidate>,
    /// Candidates turned away by a full cell (indices into `candidates`), for the second pass.
    deferred: Vec<u32>,
    /// Features per bucketing cell.
    bucket_counts: Vec<usize>,
    /// Min-distance grid: list heads per cell, next links, positions.
    dist_heads: Vec<u32>,
    dist_next: Vec<u32>,
    dist_points: Vec<Point2<f32>>,
    dist_cols: usize,
    dist_rows: usize,
}

impl CornerDetector {
    /// Allocates the buffers for `width` x `height` frames.
    pub fn new(width: usize, height: usize, config: CornerConfig) -> Result<Self, CornerError> {
        let bad = |field: &'static str, value: String, allowed: &'static str| {
            Err(CornerError::BadConfig {
                field,
                value,
                allowed,
            })
        };
        if config.grid_cols == 0 || config.grid_cols > width {
            return bad("grid_cols", config.grid_cols.to_string(), "1..=width");
        }
        if config.grid_rows == 0 || config.grid_rows > height {
            return bad("grid_rows", config.grid_rows.to_string(), "1..=height");
        }
        if !(config.min_distance_px.is_finite() && config.min_distance_px >= 1.0) {
            return bad(
                "min_distance_px",
                config.min_distance_px.to_string(),
                ">= 1 and finite",
            );
        }
        if !(config.quality_level.is_finite() && (0.0..1.0).contains(&config.quality_level)) {
            return bad("quality_level", config.quality_level.to_string(), "[0, 1)");
        }
        if !(config.min_response.is_finite() && config.min_response > 0.0) {
            return bad("min_response", config.min_response.to_string(), "> 0");
        }
        if config.block_radius_px == 0 || config.block_radius_px > 8 {
            return bad(
                "block_radius_px",
                config.block_radius_px.to_string(),
                "1..=8",
            );
        }
        if width > usize::from(u16::MAX) || height > usize::from(u16::MAX) {
            return bad("width/height", format!("{width}x{height}"), "<= 65535");
        }
        let r = config.block_radius_px;
        let sums_len = (height + 2 * r) * width;
        let dist_cols = (width as f32 / config.min_distance_px).ceil() as usize;
        let dist_rows = (height as f32 / config.min_distance_px).ceil() as usize;
        let max_points = 2 * config.max_features;
        Ok(Self {
            config,
            width,
            height,
            row_sums: [
                vec![0.0; sums_len],
                vec![0.0; sums_len],
                vec![0.0; sums_len],
            ],
            product_rows: [
                vec![0.0; width + 2 * r],
                vec![0.0; width + 2 * r],
                vec![0.0; width + 2 * r],
            ],
            col_sums: [vec![0.0; width], vec![0.0; width], vec![0.0; width]],
            response: vec![0.0; width * height],
            row_max: vec![0.0; width * height],
            max_flags: vec![0; width],
            candidates: Vec::with_capacity(width * height / 8),
            deferred: Vec::with_capacity(width * height / 8),
            bucket_counts: vec![0; config.grid_cols * config.grid_rows],
            dist_heads: vec![NONE; dist_cols * dist_rows],
            dist_next: Vec::with_capacity(max_points),
            dist_points: Vec::with_capacity(max_points),
            dist_cols,
            dist_rows,
        })
    }

    /// The configuration.
    pub fn config(&self) -> &CornerConfig {
        &self.config
    }

    /// Features allowed per bucketing cell.
    pub fn per_cell_cap(&self) -> usize {
        self.config
            .max_features
            .div_ceil(self.config.grid_cols * self.config.grid_rows)
    }

    /// Bucketing cell of a pixel position (clamped into the grid).
    pub fn cell_of(&self, p: Point2<f32>) -> usize {
        let cx = ((p.x.max(0.0) as usize) * self.config.grid_cols / self.width)
            .min(self.config.grid_cols - 1);
        let cy = ((p.y.max(0.0) as usize) * self.config.grid_rows / self.height)
            .min(self.config.grid_rows - 1);
        cy * self.config.grid_cols + cx
    }

    /// Detects new corners on `level` (normally pyramid level 0), away from `existing_px`.
    ///
    /// Clears `out` and fills it with the new corners only, strongest first. Returns their count.
    pub fn detect(
        &mut self,
        level: &PyramidLevel,
        existing_px: &[Point2<f32>],
        out: &mut Vec<Corner>,
    ) -> Result<usize, CornerError> {
        out.clear();
        self.check_level(level)?;
        self.reset_grids();
        for &p in existing_px {
            if p.x.is_finite() && p.y.is_finite() {
                let cell = self.cell_of(p);
                self.bucket_counts[cell] += 1;
                self.insert_point(p);
            }
        }
        let budget = self.config.max_features.saturating_sub(existing_px.len());
        if budget == 0 {
            return Ok(0);
        }
        let max_response = self.compute_response(level);
        let threshold = (self.config.quality_level * max_response).max(self.config.min_response);
        self.collect_candidates(threshold);
        let min_dist_sq = self.config.min_distance_px * self.config.min_distance_px;
        self.take_per_cell(budget, min_dist_sq, out);
        self.take_deferred(budget, min_dist_sq, out);
        Ok(out.len())
    }

    /// `level` must have this detector's size and a border wider than the corner block.
    fn check_level(&self, level: &PyramidLevel) -> Result<(), CornerError> {
        if level.width() != self.width || level.height() != self.height {
            return Err(CornerError::SizeMismatch {
                width: self.width,
                height: self.height,
                got_width: level.width(),
                got_height: level.height(),
            });
        }
        if level.grad_x.pad() <= self.config.block_radius_px {
            return Err(CornerError::BorderTooThin {
                pad_px: level.grad_x.pad(),
                block_radius_px: self.config.block_radius_px,
            });
        }
        Ok(())
    }

    /// First pass: the strongest candidates, at most the per-cell cap in each grid cell;
    /// those turned away by a full cell are deferred when leftover budget may be filled.
    fn take_per_cell(&mut self, budget: usize, min_dist_sq: f32, out: &mut Vec<Corner>) {
        let cap = self.per_cell_cap();
        for i in 0..self.candidates.len() {
            if out.len() >= budget {
                break;
            }
            let c = self.candidates[i];
            let p = self.refine(c);
            let cell = self.cell_of(p);
            if self.bucket_counts[cell] >= cap {
                if self.config.fill_leftover_budget {
                    self.deferred.push(i as u32);
                }
                continue;
            }
            if self.too_close(p, min_dist_sq) {
                continue;
            }
            self.accept(cell, p, c.response, out);
        }
    }

    /// Second pass: budget left by texture-poor cells goes to the strongest corners that
    /// were turned away by a full cell.
    fn take_deferred(&mut self, budget: usize, min_dist_sq: f32, out: &mut Vec<Corner>) {
        for k in 0..self.deferred.len() {
            if out.len() >= budget {
                break;
            }
            let c = self.candidates[self.deferred[k] as usize];
            let p = self.refine(c);
            if self.too_close(p, min_dist_sq) {
                continue;
            }
            let cell = self.cell_of(p);
            self.accept(cell, p, c.response, out);
        }
    }

    /// Adds the corner at `p` (in grid cell `cell`) to `out` and to the spacing grids.
    fn accept(&mut self, cell: usize, p: Point2<f32>, response: f32, out: &mut Vec<Corner>) {
        self.bucket_counts[cell] += 1;
        self.insert_point(p);
        out.push(Corner {
            position_px: p,
            response,
        });
    }

    fn reset_grids(&mut self) {
        self.deferred.clear();
        self.bucket_counts.fill(0);
        self.dist_heads.fill(NONE);
        self.dist_next.clear();
        self.dist_points.clear();
    }

    fn dist_cell(&self, p: Point2<f32>) -> (usize, usize) {
        let md = self.config.min_distance_px;
        let gx = ((p.x.max(0.0) / md) as usize).min(self.dist_cols - 1);
        let gy = ((p.y.max(0.0) / md) as usize).min(self.dist_rows - 1);
        (gx, gy)
    }

    fn insert_point(&mut self, p: Point2<f32>) {
        let (gx, gy) = self.dist_cell(p);
        let cell = gy * self.dist_cols + gx;
        let id = self.dist_points.len() as u32;
        self.dist_points.push(p);
        self.dist_next.push(self.dist_heads[cell]);
        self.dist_heads[cell] = id;
    }

    fn too_close(&self, p: Point2<f32>, min_dist_sq: f32) -> bool {
        let (gx, gy) = self.dist_cell(p);
        for cy in gy.saturating_sub(1)..=(gy + 1).min(self.dist_rows - 1) {
            for cx in gx.saturating_sub(1)..=(gx + 1).min(self.dist_cols - 1) {
                let mut id = self.dist_heads[cy * self.dist_cols + cx];
                while id != NONE {
                    let q = self.dist_points[id as usize];
                    if (q - p).norm_squared() < min_dist_sq {
                        return true;
                    }
                    id = self.dist_next[id as usize];
                }
            }
        }
        false
    }

    /// Fills `self.response`; returns its maximum.
    fn compute_response(&mut self, level: &PyramidLevel) -> f32 {
        let r = self.config.block_radius_px;
        let (w, h) = (self.width, self.height);
        let gx = &level.grad_x;
        let gy = &level.grad_y;
        let [sxx, sxy, syy] = &mut self.row_sums;
        // Horizontal box sums of the gradient products for rows -r..h+r: products into
        // scratch rows, then 2r+1 shifted adds (all vectorisable, no loop-carried sum).
        let [pxx, pxy, pyy] = &mut self.product_rows;
        for row in 0..h + 2 * r {
            let y = row as isize - r as isize;
            let start = gx.index(-(r as isize), y);
            let gxr = &gx.data()[start..start + w + 2 * r];
            let gyr = &gy.data()[start..start + w + 2 * r];
            for ((((a, b), xx), xy), yy) in gxr
                .iter()
                .zip(gyr)
                .zip(pxx.iter_mut())
                .zip(pxy.iter_mut())
                .zip(pyy.iter_mut())
            {
                *xx = a * a;
                *xy = a * b;
                *yy = b * b;
            }
            let out = row * w..(row + 1) * w;
            for (dst, src) in [
                (&mut sxx[out.clone()], &pxx[..]),
                (&mut sxy[out.clone()], &pxy[..]),
                (&mut syy[out], &pyy[..]),
            ] {
                dst.copy_from_slice(&src[..w]);
                for k in 1..=2 * r {
                    for (d, v) in dst.iter_mut().zip(&src[k..k + w]) {
                        *d += v;
                    }
                }
            }
        }
        // Vertical running sums over 2r+1 rows, then the minimum eigenvalue.
        let [cxx, cxy, cyy] = &mut self.col_sums;
        cxx.fill(0.0);
        cxy.fill(0.0);
        cyy.fill(0.0);
        let add_row = |col: &mut [f32], src: &[f32], row: usize, sign: f32| {
            for (c, v) in col.iter_mut().zip(&src[row * w..(row + 1) * w]) {
                *c += sign * v;
            }
        };
        for row in 0..2 * r {
            add_row(cxx, sxx, row, 1.0);
            add_row(cxy, sxy, row, 1.0);
            add_row(cyy, syy, row, 1.0);
        }
        let mut max_response = 0.0f32;
        for y in 0..h {
            add_row(cxx, sxx, y + 2 * r, 1.0);
            add_row(cxy, sxy, y + 2 * r, 1.0);
            add_row(cyy, syy, y + 2 * r, 1.0);
            let resp = &mut self.response[y * w..(y + 1) * w];
            for (((out, &a), &b), &c) in resp
                .iter_mut()
                .zip(cxx.iter())
                .zip(cxy.iter())
                .zip(cyy.iter())
            {
                let half_trace = 0.5 * (a + c);
                let half_diff = 0.5 * (a - c);
                let min_eig = half_trace - (half_diff * half_diff + b * b).sqrt();
                *out = min_eig;
                max_response = max_response.max(min_eig);
            }
            add_row(cxx, sxx, y, -1.0);
            add_row(cxy, sxy, y, -1.0);
            add_row(cyy, syy, y, -1.0);
        }
        max_response
    }

    fn collect_candidates(&mut self, threshold: f32) {
        self.candidates.clear();
        let (w, h) = (self.width, self.height);
        let b = self.config.border_px.max(1);
        if w <= 2 * b || h <= 2 * b {
            return;
        }
        // 3×3 maximum filter (vectorisable): horizontal maxima per row, then vertical.
        let resp = &self.response;
        let hmax = &mut self.row_max;
        for y in 0..h {
            let row = &resp[y * w..(y + 1) * w];
            let out = &mut hmax[y * w..(y + 1) * w];
            out[0] = row[0].max(row[1]);
            out[w - 1] = row[w - 2].max(row[w - 1]);
            for (o, t) in out[1..w - 1].iter_mut().zip(row.windows(3)) {
                *o = t[0].max(t[1]).max(t[2]);
            }
        }
        let flags = &mut self.max_flags;
        for y in b..h - b {
            let up = &hmax[(y - 1) * w + b..(y - 1) * w + w - b];
            let mid = &hmax[y * w + b..y * w + w - b];
            let down = &hmax[(y + 1) * w + b..(y + 1) * w + w - b];
            let row = &resp[y * w + b..y * w + w - b];
            let f = &mut flags[..w - 2 * b];
            for ((((f, &v), &u), &m), &d) in f.iter_mut().zip(row).zip(up).zip(mid).zip(down) {
                *f = u8::from(v >= threshold && v >= u.max(m).max(d));
            }
            for (i, &is_max) in f.iter().enumerate() {
                if is_max != 0 {
                    let x = b + i;
                    self.candidates.push(Candidate {
                        x: x as u16,
                        y: y as u16,
                        response: resp[y * w + x],
                    });
                }
            }
        }
        self.candidates
            .sort_unstable_by(|a, b| b.response.total_cmp(&a.response));
    }

    /// Parabola fit of the response around an integer maximum.
    fn refine(&self, c: Candidate) -> Point2<f32> {
        let (x, y, w) = (usize::from(c.x), usize::from(c.y), self.width);
        let r = &self.response;
        let v = c.response;
        let offset = |lo: f32, hi: f32| {
            let denom = lo - 2.0 * v + hi;
            if denom < -1e-12 {
                (0.5 * (lo - hi) / denom).clamp(-0.5, 0.5)
            } else {
                0.0
            }
        };
        let dx = offset(r[y * w + x - 1], r[y * w + x + 1]);
        let dy = offset(r[(y - 1) * w + x], r[(y + 1) * w + x]);
        Point2::new(x as f32 + dx, y as f32 + dy)
    }
}

#[cfg(test)]
mod tests;
