//! Gaussian image pyramid with gradients, in buffers allocated once.
//!
//! [`Pyramid::new`] allocates every level for a fixed image size; [`Pyramid::build`] refills them
//! from an [`ImageView`] each frame without allocating. Each level is an `f32` plane with a
//! replicated border of [`PyramidConfig::border_px`] pixels on every side, plus its Scharr
//! gradients, so the KLT tracker can sample windows that straddle the image edge without
//! per-pixel bounds logic. Level 0 is a copy of the input (the sample it came from can be released
//! while the pyramid is kept as the "previous frame").
//!
//! ```
//! use hopnav_vision::{image::ImageView, pyramid::{Pyramid, PyramidConfig}};
//! let pixels = vec![100u8; 64 * 64];
//! let mut pyr = Pyramid::new(64, 64, PyramidConfig::default()).unwrap();
//! pyr.build(&ImageView::packed(&pixels, 64, 64).unwrap()).unwrap();
//! assert_eq!(pyr.num_levels(), 4);
//! assert_eq!(pyr.level(1).unwrap().width(), 32);
//! ```

use crate::image::ImageView;

/// Smallest width/height a pyramid level may have.
const MIN_LEVEL_SIZE_PX: usize = 8;

/// Pyramid shape.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PyramidConfig {
    /// Wanted number of levels including the full-resolution one (fewer if the image gets
    /// smaller than 8 px).
    pub levels: usize,
    /// Replicated border around each level, in pixels (≥ KLT window radius + 2).
    pub border_px: usize,
}

impl Default for PyramidConfig {
    fn default() -> Self {
        Self {
            levels: 4,
            border_px: 12,
        }
    }
}

/// Error creating or filling a [`Pyramid`].
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum PyramidError {
    /// The base image is smaller than the minimal level size.
    #[error("image {width}x{height} is too small for a pyramid (min 8x8)")]
    TooSmall {
        /// Requested width.
        width: usize,
        /// Requested height.
        height: usize,
    },
    /// `levels` is zero or `border_px` is below 2.
    #[error("invalid pyramid config: levels={levels} (>= 1), border_px={border_px} (>= 2)")]
    BadConfig {
        /// Configured levels.
        levels: usize,
        /// Configured border.
        border_px: usize,
    },
    /// The image given to `build` does not have the size the pyramid was made for.
    #[error("image is {got_width}x{got_height}, pyramid expects {width}x{height}")]
    SizeMismatch {
        /// Expected width.
        width: usize,
        /// Expected height.
        height: usize,
        /// Width of the given image.
        got_width: usize,
        /// Height of the given image.
        got_height: usize,
    },
}

/// One `f32` image plane with a border of `pad` pixels on every side.
#[derive(Debug, Clone)]
pub struct PaddedPlane {
    width: usize,
    height: usize,
    pad: usize,
    stride: usize,
    data: Vec<f32>,
}

impl PaddedPlane {
    fn new(width: usize, height: usize, pad: usize) -> Self {
        let stride = width + 2 * pad;
        Self {
            width,
            height,
            pad,
            stride,
            data: vec![0.0; stride * (height + 2 * pad)],
        }
    }

    /// Width without the border.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Height without the border.
    pub fn height(&self) -> usize {
        self.height
    }

    /// Border size in pixels.
    pub fn pad(&self) -> usize {
        self.pad
    }

    /// Distance between rows in elements.
    pub fn stride(&self) -> usize {
        self.stride
    }

    /// The whole buffer, border included; pixel `(x, y)` (which may be negative down to `-pad`)
    /// is at [`PaddedPlane::index`].
    pub fn data(&self) -> &[f32] {
        &self.data
    }

    /// Buffer index of pixel `(x, y)`; valid for `-pad <= x < width + pad` and likewise `y`.
    #[inline]
    pub fn index(&self, x: isize, y: isize) -> usize {
        ((y + self.pad as isize) as usize) * self.stride + (x + self.pad as isize) as usize
    }

    /// Value at `(x, y)` inside the padded area, `None` outside it.
    pub fn get(&self, x: isize, y: isize) -> Option<f32> {
        let p = self.pad as isize;
        if x < -p || y < -p || x >= self.width as isize + p || y >= self.height as isize + p {
            return None;
        }
        self.data.get(self.index(x, y)).copied()
    }

    /// Replicates the edge pixels into the border.
    fn fill_border(&mut self) {
        let (w, h, pad, stride) = (self.width, self.height, self.pad, self.stride);
        for y in pad..pad + h {
            let row = &mut self.data[y * stride..(y + 1) * stride];
            let left = row[pad];
            let right = row[pad + w - 1];
            row[..pad].fill(left);
            row[pad + w..].fill(right);
        }
        for y in 0..pad {
            self.data
                .copy_within(pad * stride..(pad + 1) * stride, y * stride);
        }
        let last = (pad + h - 1) * stride;
        for y in pad + h..h + 2 * pad {
            self.data.copy_within(last..last + stride, y * stride);
        }
    }
}

/// One pyramid level: intensity and its Scharr gradients (intensity units per pixel).
#[derive(Debug, Clone)]
pub struct PyramidLevel {
    /// Intensity in `[0, 255]`.
    pub image: PaddedPlane,
    /// Horizontal derivative.
    pub grad_x: PaddedPlane,
    /// Vertical derivative.
    pub grad_y: PaddedPlane,
}

impl PyramidLevel {
    fn new(width: usize, height: usize, pad: usize) -> Self {
        Self {
            image: PaddedPlane::new(width, height, pad),
            grad_x: PaddedPlane::new(width, height, pad),
            grad_y: PaddedPlane::new(width, height, pad),
        }
    }

    /// Width of this level in pixels.
    pub fn width(&self) -> usize {
        self.image.width
    }

    /// Height of this level in pixels.
    pub fn height(&self) -> usize {
        self.image.height
    }

    fn compute_gradients(&mut self) {
        let img = &self.image;
        let (stride, total_rows) = (img.stride, img.height + 2 * img.pad);
        let src = &img.data;
        for y in 1..total_rows - 1 {
            let up = &src[(y - 1) * stride..y * stride];
            let mid = &src[y * stride..(y + 1) * stride];
            let down = &src[(y + 1) * stride..(y + 2) * stride];
            let gx_row = &mut self.grad_x.data[y * stride..(y + 1) * stride];
            let gy_row = &mut self.grad_y.data[y * stride..(y + 1) * stride];
            for x in 1..stride - 1 {
                gx_row[x] = (3.0 * (up[x + 1] - up[x - 1])
                    + 10.0 * (mid[x + 1] - mid[x - 1])
                    + 3.0 * (down[x + 1] - down[x - 1]))
                    * (1.0 / 32.0);
                gy_row[x] = (3.0 * (down[x - 1] - up[x - 1])
                    + 10.0 * (down[x] - up[x])
                    + 3.0 * (down[x + 1] - up[x + 1]))
                    * (1.0 / 32.0);
            }
        }
    }
}

/// Gaussian pyramid (5-tap binomial filter, factor 2) with preallocated levels.
#[derive(Debug, Clone)]
pub struct Pyramid {
    levels: Vec<PyramidLevel>,
    /// Horizontal-pass scratch for downsampling, sized for the largest level.
    scratch: Vec<f32>,
    config: PyramidConfig,
}

impl Pyramid {
    /// Allocates all levels for `width` x `height` images.
    pub fn new(width: usize, height: usize, config: PyramidConfig) -> Result<Self, PyramidError> {
        if config.levels == 0 || config.border_px < 2 {
            return Err(PyramidError::BadConfig {
                levels: config.levels,
                border_px: config.border_px,
            });
        }
        if width < MIN_LEVEL_SIZE_PX || height < MIN_LEVEL_SIZE_PX {
            return Err(PyramidError::TooSmall { width, height });
        }
        let mut levels = Vec::with_capacity(config.levels);
        let (mut w, mut h) = (width, height);
        while levels.len() < config.levels && w >= MIN_LEVEL_SIZE_PX && h >= MIN_LEVEL_SIZE_PX {
            levels.push(PyramidLevel::new(w, h, config.border_px));
            w = w.div_ceil(2);
            h = h.div_ceil(2);
        }
        let scratch = vec![0.0; (height + 2 * config.border_px) * width.div_ceil(2)];
        Ok(Self {
            levels,
            scratch,
            config,
        })
    }

    /// Refills every level from `image` (no allocation).
    pub fn build(&mut self, image: &ImageView<'_>) -> Result<(), PyramidError> {
        let (width, height) = (self.base_width(), self.base_height());
        if image.width() != width || image.height() != height {
            return Err(PyramidError::SizeMismatch {
                width,
                height,
                got_width: image.width(),
                got_height: image.height(),
            });
        }
        if let Some(base) = self.levels.first_mut() {
            let plane = &mut base.image;
            for y in 0..height {
                let Some(src) = image.row(y) else { break };
                let start = plane.index(0, y as isize);
                for (dst, &s) in plane.data[start..start + width].iter_mut().zip(src) {
                    *dst = f32::from(s);
                }
            }
            plane.fill_border();
            base.compute_gradients();
        }
        for l in 1..self.levels.len() {
            let (lower, upper) = self.levels.split_at_mut(l);
            let (Some(src), Some(dst)) = (lower.last(), upper.first_mut()) else {
                break;
            };
            downsample(&src.image, &mut dst.image, &mut self.scratch);
            dst.image.fill_border();
            dst.compute_gradients();
        }
        Ok(())
    }

    /// Number of levels actually allocated.
    pub fn num_levels(&self) -> usize {
        self.levels.len()
    }

    /// Level `i` (0 = full resolution).
    pub fn level(&self, i: usize) -> Option<&PyramidLevel> {
        self.levels.get(i)
    }

    /// Full-resolution width.
    pub fn base_width(&self) -> usize {
        self.levels.first().map_or(0, PyramidLevel::width)
    }

    /// Full-resolution height.
    pub fn base_height(&self) -> usize {
        self.levels.first().map_or(0, PyramidLevel::height)
    }

    /// The configuration the pyramid was built with.
    pub fn config(&self) -> PyramidConfig {
        self.config
    }
}

/// `dst(x, y) = Σ k_i k_j src(2x + i, 2y + j)`, `k = [1 4 6 4 1] / 16`; needs `src.pad >= 2`.
fn downsample(src: &PaddedPlane, dst: &mut PaddedPlane, scratch: &mut [f32]) {
    const K: [f32; 5] = [1.0 / 16.0, 4.0 / 16.0, 6.0 / 16.0, 4.0 / 16.0, 1.0 / 16.0];
    let rows = src.height + 4; // src rows -2 ..= h + 1
    let dw = dst.width;
    // Horizontal pass: scratch[r * dw + x] for src row (r - 2).
    for r in 0..rows {
        let y = r as isize - 2;
        let base = src.index(0, y);
        let out = &mut scratch[r * dw..(r + 1) * dw];
        for (x, o) in out.iter_mut().enumerate() {
            let c = base + 2 * x;
            let s = &src.data[c - 2..c + 3];
            *o = K[0] * s[0] + K[1] * s[1] + K[2] * s[2] + K[3] * s[3] + K[4] * s[4];
        }
    }
    // Vertical pass.
    for y in 0..dst.height {
        let start = dst.index(0, y as isize);
        let r = 2 * y + 2; // scratch row of src row 2y
        for x in 0..dw {
            let v = K[0] * scratch[(r - 2) * dw + x]
                + K[1] * scratch[(r - 1) * dw + x]
                + K[2] * scratch[r * dw + x]
                + K[3] * scratch[(r + 1) * dw + x]
                + K[4] * scratch[(r + 2) * dw + x];
            dst.data[start + x] = v;
        }
    }
}

/// Test helpers of the crate.
#[cfg(test)]
pub(crate) mod test_support {
    use super::{Pyramid, PyramidConfig};
    use crate::image::ImageView;

    /// The default pyramid of a packed `w × h` image.
    pub(crate) fn packed_pyramid(pixels: &[u8], w: usize, h: usize) -> Pyramid {
        let mut pyr = Pyramid::new(w, h, PyramidConfig::default()).expect("pyramid");
        pyr.build(&ImageView::packed(pixels, w, h).expect("image"))
            .expect("build");
        pyr
    }
}

#[cfg(test)]
mod tests {
    use super::test_support::packed_pyramid;
    use super::*;

    #[test]
    fn constant_image_stays_constant_and_flat() {
        let pixels = vec![77u8; 33 * 20];
        let pyr = packed_pyramid(&pixels, 33, 20);
        assert_eq!(pyr.num_levels(), 2); // 33x20 -> 17x10 -> (9x5 too small)
        for l in 0..pyr.num_levels() {
            let lvl = pyr.level(l).unwrap();
            for y in -2..lvl.height() as isize + 2 {
                for x in -2..lvl.width() as isize + 2 {
                    assert!((lvl.image.get(x, y).unwrap() - 77.0).abs() < 1e-4);
                    assert!(lvl.grad_x.get(x, y).unwrap().abs() < 1e-4);
                }
            }
        }
    }

    #[test]
    fn ramp_gradient_and_size_checks() {
        let (w, h) = (40usize, 30usize);
        let pixels: Vec<u8> = (0..w * h).map(|i| (2 * (i % w)) as u8).collect();
        let mut pyr = packed_pyramid(&pixels, w, h);
        let l0 = pyr.level(0).unwrap();
        assert!((l0.grad_x.get(10, 10).unwrap() - 2.0).abs() < 1e-5);
        assert!(l0.grad_y.get(10, 10).unwrap().abs() < 1e-5);
        // Level 1 halves the resolution: a ramp of 2/px becomes 4/px.
        let l1 = pyr.level(1).unwrap();
        assert!((l1.grad_x.get(8, 8).unwrap() - 4.0).abs() < 1e-4);
        let other = vec![0u8; 10 * 10];
        assert!(matches!(
            pyr.build(&ImageView::packed(&other, 10, 10).unwrap()),
            Err(PyramidError::SizeMismatch { .. })
        ));
        assert!(Pyramid::new(4, 40, PyramidConfig::default()).is_err());
        let bad = PyramidConfig {
            levels: 0,
            border_px: 12,
        };
        assert!(Pyramid::new(40, 40, bad).is_err());
    }
}
