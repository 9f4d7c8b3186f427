//! The heightfield: a regular grid of heights with bilinear height and normal queries.
//!
//! # Convention
//! World frame: **z up**, x and y horizontal, metres. The grid is centred on the origin:
//! node `(i, j)` (column `i` along x, row `j` along y) sits at
//! `x = origin_m[0] + i · spacing_m`, `y = origin_m[1] + j · spacing_m` with
//! `origin_m = [-(nx-1)·spacing/2, -(ny-1)·spacing/2]`.
//! Heights are stored **row-major**: `heights_m()[j * nx + i]`.
//!
//! For a physics heightfield (parry/rapier: local y up, centred, heights in a matrix) use
//! [`Heightfield::heights_column_major_m`]: the `ny × nx` matrix `m[(j, i)]` (rows along world
//! y, columns along world x) in column-major order, plus `extent_m()` as the horizontal scale.
//! Which matrix axis maps to which local axis, and the rotation from parry's y-up frame to this
//! z-up world, belong to the physics crate; check them there with a test that compares a few
//! [`Heightfield::height_at`] values against collider ray casts.
//!
//! ```
//! use hopnav_world::terrain::Heightfield;
//! let hf = Heightfield::flat(5, 5, 0.5, 1.0);
//! assert_eq!(hf.height_at(0.3, -0.2), 1.0);
//! assert_eq!(hf.normal_at(0.0, 0.0), [0.0, 0.0, 1.0]);
//! ```

use crate::config::TerrainConfig;
use crate::noise::{NoiseKind, fbm};
use crate::rng::derive_seed;

/// Stream number of the relief noise (see [`derive_seed`]).
const RELIEF_STREAM: u64 = 0x7265_6c69_6566; // "relief"

/// A regular, centred grid of terrain heights (z up).
#[derive(Debug, Clone, PartialEq)]
pub struct Heightfield {
    nx: usize,
    ny: usize,
    spacing_m: f64,
    origin_m: [f64; 2],
    heights_m: Vec<f64>,
}

impl Heightfield {
    /// A flat grid of `nx × ny` nodes (each at least 2) at height `z_m`, centred on the origin.
    pub fn flat(nx: usize, ny: usize, spacing_m: f64, z_m: f64) -> Self {
        let nx = nx.max(2);
        let ny = ny.max(2);
        let spacing_m = if spacing_m.is_finite() && spacing_m > 0.0 {
            spacing_m
        } else {
            1.0
        };
        Self {
            nx,
            ny,
            spacing_m,
            origin_m: [
                -((nx - 1) as f64) * spacing_m / 2.0,
                -((ny - 1) as f64) * spacing_m / 2.0,
            ],
            heights_m: vec![z_m; nx * ny],
        }
    }

    /// Fractal relief (gradient-noise fBm) as configured; no craters.
    pub fn from_relief(seed: u64, cfg: &TerrainConfig) -> Self {
        let (nx, ny) = cfg.grid_nodes();
        let mut hf = Self::flat(nx, ny, cfg.spacing_m, 0.0);
        if cfg.relief_amplitude_m > 0.0 && cfg.relief_octaves > 0 {
            let s = derive_seed(seed, RELIEF_STREAM);
            let inv_wl = 1.0 / cfg.relief_wavelength_m;
            for j in 0..ny {
                for i in 0..nx {
                    let [x, y] = hf.node_xy_m(i, j);
                    let n = fbm(
                        NoiseKind::Gradient,
                        s,
                        x * inv_wl,
                        y * inv_wl,
                        cfg.relief_octaves,
                        cfg.relief_gain,
                    );
                    hf.heights_m[j * nx + i] = cfg.relief_amplitude_m * n;
                }
            }
        }
        hf
    }

    /// Nodes along x.
    pub fn nx(&self) -> usize {
        self.nx
    }

    /// Nodes along y.
    pub fn ny(&self) -> usize {
        self.ny
    }

    /// Distance between neighbouring nodes, metres.
    pub fn spacing_m(&self) -> f64 {
        self.spacing_m
    }

    /// World (x, y) of node (0, 0), the minimum corner, metres.
    pub fn origin_m(&self) -> [f64; 2] {
        self.origin_m
    }

    /// Extent `[(nx-1)·spacing, (ny-1)·spacing]`, metres.
    pub fn extent_m(&self) -> [f64; 2] {
        [
            (self.nx - 1) as f64 * self.spacing_m,
            (self.ny - 1) as f64 * self.spacing_m,
        ]
    }

    /// All heights, row-major (`j * nx + i`), metres.
    pub fn heights_m(&self) -> &[f64] {
        &self.heights_m
    }

    /// Heights as the `ny × nx` matrix `m[(j, i)]` (rows along y, columns along x) in
    /// column-major order: element `(j, i)` at index `i * ny + j`.
    pub fn heights_column_major_m(&self) -> Vec<f64> {
        let mut out = Vec::with_capacity(self.heights_m.len());
        for i in 0..self.nx {
            for j in 0..self.ny {
                out.push(self.heights_m[j * self.nx + i]);
            }
        }
        out
    }

    /// Mutable heights (row-major), for generators in this crate.
    pub(crate) fn heights_mut(&mut self) -> &mut [f64] {
        &mut self.heights_m
    }

    /// World (x, y) of node (i, j), metres (indices are not clamped).
    pub fn node_xy_m(&self, i: usize, j: usize) -> [f64; 2] {
        [
            self.origin_m[0] + i as f64 * self.spacing_m,
            self.origin_m[1] + j as f64 * self.spacing_m,
        ]
    }

    /// Height of node (i, j), metres; indices are clamped to the grid.
    pub fn node_height_m(&self, i: usize, j: usize) -> f64 {
        let i = i.min(self.nx - 1);
        let j = j.min(self.ny - 1);
        self.heights_m[j * self.nx + i]
    }

    /// Whether (x, y) lies on the grid (borders included).
    pub fn contains(&self, x_m: f64, y_m: f64) -> bool {
        let [ex, ey] = self.extent_m();
        let u = x_m - self.origin_m[0];
        let v = y_m - self.origin_m[1];
        (0.0..=ex).contains(&u) && (0.0..=ey).contains(&v)
    }

    /// Cell indices and fractions of (x, y), clamped to the grid.
    fn locate(&self, x_m: f64, y_m: f64) -> (usize, usize, f64, f64) {
        let gx = ((x_m - self.origin_m[0]) / self.spacing_m).clamp(0.0, (self.nx - 1) as f64);
        let gy = ((y_m - self.origin_m[1]) / self.spacing_m).clamp(0.0, (self.ny - 1) as f64);
        // NaN input clamps to NaN; map it to the origin cell instead.
        let gx = if gx.is_nan() { 0.0 } else { gx };
        let gy = if gy.is_nan() { 0.0 } else { gy };
        let i = (gx.floor() as usize).min(self.nx - 2);
        let j = (gy.floor() as usize).min(self.ny - 2);
        (i, j, gx - i as f64, gy - j as f64)
    }

    /// Heights of the four nodes of the cell holding (x, y), `[h00, h10, h01, h11]`, and the
    /// position's fractions along x and y within that cell.
    fn cell_at(&self, x_m: f64, y_m: f64) -> ([f64; 4], f64, f64) {
        let (i, j, fx, fy) = self.locate(x_m, y_m);
        let k = j * self.nx + i;
        let h = &self.heights_m;
        ([h[k], h[k + 1], h[k + self.nx], h[k + self.nx + 1]], fx, fy)
    }

    /// Bilinearly interpolated height at (x, y), metres; outside the grid the border value.
    pub fn height_at(&self, x_m: f64, y_m: f64) -> f64 {
        let ([h00, h10, h01, h11], fx, fy) = self.cell_at(x_m, y_m);
        let a = h00 + (h10 - h00) * fx;
        let b = h01 + (h11 - h01) * fx;
        a + (b - a) * fy
    }

    /// Gradient `[∂z/∂x, ∂z/∂y]` of the bilinear surface at (x, y).
    pub fn gradient_at(&self, x_m: f64, y_m: f64) -> [f64; 2] {
        let ([h00, h10, h01, h11], fx, fy) = self.cell_at(x_m, y_m);
        let dzdx = ((h10 - h00) * (1.0 - fy) + (h11 - h01) * fy) / self.spacing_m;
        let dzdy = ((h01 - h00) * (1.0 - fx) + (h11 - h10) * fx) / self.spacing_m;
        [dzdx, dzdy]
    }

    /// Unit upward surface normal of the bilinear surface at (x, y).
    pub fn normal_at(&self, x_m: f64, y_m: f64) -> [f64; 3] {
        let [gx, gy] = self.gradient_at(x_m, y_m);
        let n = (gx * gx + gy * gy + 1.0).sqrt();
        [-gx / n, -gy / n, 1.0 / n]
    }

    /// Unit normal at node (i, j) from central differences (one-sided at the border).
    pub fn node_normal(&self, i: usize, j: usize) -> [f64; 3] {
        let i0 = i.saturating_sub(1);
        let i1 = (i + 1).min(self.nx - 1);
        let j0 = j.saturating_sub(1);
        let j1 = (j + 1).min(self.ny - 1);
        let gx = (self.node_height_m(i1, j) - self.node_height_m(i0, j))
            / ((i1 - i0).max(1) as f64 * self.spacing_m);
        let gy = (self.node_height_m(i, j1) - self.node_height_m(i, j0))
            / ((j1 - j0).max(1) as f64 * self.spacing_m);
        let n = (gx * gx + gy * gy + 1.0).sqrt();
        [-gx / n, -gy / n, 1.0 / n]
    }

    /// Lowest and highest node heights, metres.
    pub fn height_range_m(&self) -> (f64, f64) {
        self.heights_m
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &h| {
                (lo.min(h), hi.max(h))
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bilinear_matches_nodes_and_midpoints() {
        let mut hf = Heightfield::flat(3, 3, 1.0, 0.0);
        hf.heights_mut()[4] = 2.0; // centre node (1, 1) at (0, 0)
        assert_eq!(hf.height_at(0.0, 0.0), 2.0);
        assert!((hf.height_at(0.5, 0.0) - 1.0).abs() < 1e-12);
        assert!((hf.height_at(-0.5, -0.5) - 0.5).abs() < 1e-12);
        assert_eq!(hf.height_at(100.0, f64::NAN), hf.height_at(1.0, -1.0));
        let [gx, _] = hf.gradient_at(0.5, 0.0);
        assert!((gx + 2.0).abs() < 1e-12);
    }

    #[test]
    fn grid_is_centred() {
        let hf = Heightfield::flat(257, 129, 0.25, 0.0);
        assert_eq!(hf.origin_m(), [-32.0, -16.0]);
        assert_eq!(hf.extent_m(), [64.0, 32.0]);
        assert!(hf.contains(32.0, 16.0) && !hf.contains(32.01, 0.0));
    }

    #[test]
    fn column_major_layout() {
        let mut hf = Heightfield::flat(3, 2, 1.0, 0.0);
        hf.heights_mut()
            .copy_from_slice(&[0.0, 1.0, 2.0, 10.0, 11.0, 12.0]);
        assert_eq!(
            hf.heights_column_major_m(),
            vec![0.0, 10.0, 1.0, 11.0, 2.0, 12.0]
        );
        assert_eq!(hf.node_height_m(2, 1), 12.0);
    }
}
