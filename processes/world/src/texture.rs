//! 8-bit mip-mapped textures and their samplers; what the procedural textures contain is in
//! [`bake`](crate::bake):
//!
//! - **Terrain atlas** (clamped, one texel per `texture.texel_m`, default 2 cm, over the whole
//!   map): multi-scale albedo noise (8 m down to a few cm), baked pebbles (1–8 cm) and Lambertian
//!   shading from the terrain normals perturbed by centimetre-scale bumps, with cast shadows of
//!   the terrain and the rocks, so the ground has contrast at metre scale far away and at
//!   centimetre scale nearby. Unique everywhere.
//! - **Detail tile** (wrapping 512², `texture.detail_texel_m`, default 4 mm): sand, grit and
//!   sun-shaded gravel, mean 128 (= ×1.0), multiplied onto the atlas for close views.
//! - **Rock tile** (wrapping 256², 5 mm): speckled, veined rock surface, mean 128.
//!
//! Baking is seeded and order-independent: the same config gives the same bytes.

/// Side of the detail tile, texels (power of two).
pub const DETAIL_TILE_TEXELS: usize = 512;
/// Side of the rock tile, texels (power of two).
pub const ROCK_TILE_TEXELS: usize = 256;
/// Texel size of the rock tile, metres.
pub const ROCK_TEXEL_M: f64 = 0.005;

/// One mip level: `width × height` bytes, row-major.
#[derive(Debug, Clone, PartialEq)]
pub struct TextureLevel {
    /// Width, texels (≥ 2).
    pub width: usize,
    /// Height, texels (≥ 2).
    pub height: usize,
    /// Texels, row-major.
    pub data: Vec<u8>,
    /// Level width over level-0 width (maps level-0 texel coordinates to this level).
    pub scale_u: f32,
    /// Level height over level-0 height.
    pub scale_v: f32,
    max_x: f32,
    max_y: f32,
    /// Largest coordinate (texel units, centres at integers) whose bilinear footprint stays
    /// inside the level: `width − 2 + 0.99`.
    pub(crate) lim_u: f32,
    /// Same along v.
    pub(crate) lim_v: f32,
}

impl TextureLevel {
    fn new(width: usize, height: usize, data: Vec<u8>, base: (usize, usize)) -> Self {
        Self {
            width,
            height,
            data,
            scale_u: width as f32 / base.0 as f32,
            scale_v: height as f32 / base.1 as f32,
            max_x: (width - 1) as f32,
            max_y: (height - 1) as f32,
            lim_u: (width - 2) as f32 + 0.99,
            lim_v: (height - 2) as f32 + 0.99,
        }
    }

    /// Bilinear sample with clamped borders; `(u, v)` in this level's texel units
    /// (texel centres at `i + 0.5`).
    #[inline(always)]
    pub fn sample_clamp(&self, u: f32, v: f32) -> f32 {
        let x = (u - 0.5).max(0.0).min(self.max_x);
        let y = (v - 0.5).max(0.0).min(self.max_y);
        let ix = (x as usize).min(self.width - 2);
        let iy = (y as usize).min(self.height - 2);
        let fx = x - ix as f32;
        let fy = y - iy as f32;
        let i = iy * self.width + ix;
        self.bilerp(i, i + 1, i + self.width, i + self.width + 1, fx, fy)
    }

    /// Bilinear sample with wrap-around; sizes must be powers of two.
    #[inline(always)]
    pub fn sample_wrap(&self, u: f32, v: f32) -> f32 {
        let x = u - 0.5;
        let y = v - 0.5;
        let xi = fast_floor(x);
        let yi = fast_floor(y);
        let fx = x - xi as f32;
        let fy = y - yi as f32;
        let mx = self.width - 1;
        let my = self.height - 1;
        let x0 = (xi as usize) & mx;
        let x1 = (x0 + 1) & mx;
        let r0 = ((yi as usize) & my) * self.width;
        let r1 = (((yi as usize) + 1) & my) * self.width;
        self.bilerp(r0 + x0, r0 + x1, r1 + x0, r1 + x1, fx, fy)
    }

    #[inline(always)]
    fn bilerp(&self, i00: usize, i10: usize, i01: usize, i11: usize, fx: f32, fy: f32) -> f32 {
        let d = &self.data;
        let (t00, t10) = (f32::from(d[i00]), f32::from(d[i10]));
        let (t01, t11) = (f32::from(d[i01]), f32::from(d[i11]));
        let a = t00 + (t10 - t00) * fx;
        let b = t01 + (t11 - t01) * fx;
        a + (b - a) * fy
    }
}

/// Floor of an `f32` as `i32` without a libm call (saturates on huge values, NaN → 0).
#[inline(always)]
pub fn fast_floor(x: f32) -> i32 {
    let t = x as i32;
    t - i32::from(x < t as f32)
}

/// A texture with its box-filtered mip chain (level 0 first).
#[derive(Debug, Clone, PartialEq)]
pub struct MipTexture {
    levels: Vec<TextureLevel>,
}

impl MipTexture {
    /// Builds the mip chain of a `width × height` image (each side ≥ 2; smaller sides are
    /// padded by repetition). `wrap` averages across the border (tiles) instead of clamping.
    pub fn from_base(width: usize, height: usize, data: Vec<u8>, wrap: bool) -> Self {
        let (width, height, data) = pad_to_min(width, height, data);
        let base = (width, height);
        let mut levels = vec![TextureLevel::new(width, height, data, base)];
        while let Some(prev) = levels.last() {
            if prev.width < 4 || prev.height < 4 {
                break;
            }
            let (w, h) = (prev.width.div_ceil(2), prev.height.div_ceil(2));
            let mut out = vec![0u8; w * h];
            for y in 0..h {
                for x in 0..w {
                    let (x0, y0) = (2 * x, 2 * y);
                    let (x1, y1) = if wrap {
                        ((x0 + 1) % prev.width, (y0 + 1) % prev.height)
                    } else {
                        ((x0 + 1).min(prev.width - 1), (y0 + 1).min(prev.height - 1))
                    };
                    let p = |xx: usize, yy: usize| u32::from(prev.data[yy * prev.width + xx]);
                    let sum = p(x0, y0) + p(x1, y0) + p(x0, y1) + p(x1, y1);
                    out[y * w + x] = ((sum + 2) / 4) as u8;
                }
            }
            levels.push(TextureLevel::new(w, h, out, base));
        }
        Self { levels }
    }

    /// Number of mip levels.
    pub fn level_count(&self) -> usize {
        self.levels.len()
    }

    /// Level `i`, clamped to the coarsest.
    #[inline(always)]
    pub fn level(&self, i: usize) -> &TextureLevel {
        &self.levels[i.min(self.levels.len() - 1)]
    }
}

fn pad_to_min(width: usize, height: usize, data: Vec<u8>) -> (usize, usize, Vec<u8>) {
    let (w, h) = (width.max(2), height.max(2));
    if w == width && h == height && data.len() == w * h {
        return (w, h, data);
    }
    let mut out = vec![128u8; w * h];
    for y in 0..h {
        for x in 0..w {
            let (sx, sy) = (
                x.min(width.saturating_sub(1)),
                y.min(height.saturating_sub(1)),
            );
            if let Some(&v) = data.get(sy * width + sx) {
                out[y * w + x] = v;
            }
        }
    }
    (w, h, out)
}

/// The baked terrain atlas and how world (x, y) maps onto it.
#[derive(Debug, Clone, PartialEq)]
pub struct TerrainTexture {
    /// Mip-mapped atlas (clamped).
    pub atlas: MipTexture,
    /// World (x, y) of the atlas corner, metres.
    pub origin_m: [f64; 2],
    /// Texel size along x and y, metres (the atlas spans the terrain exactly).
    pub texel_m: [f64; 2],
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floor_matches_std() {
        for x in [-2.5f32, -1.0, -0.1, 0.0, 0.7, 3.0, 1e6] {
            assert_eq!(fast_floor(x), x.floor() as i32);
        }
    }

    #[test]
    fn mip_chain_and_sampling() {
        let data: Vec<u8> = (0..64).map(|i| (i * 4) as u8).collect();
        let t = MipTexture::from_base(8, 8, data, true);
        assert_eq!(t.level_count(), 3);
        let l0 = t.level(0);
        assert_eq!(l0.sample_wrap(0.5, 0.5), 0.0);
        assert_eq!(l0.sample_clamp(1.5, 0.5), 4.0);
        assert_eq!(l0.sample_wrap(8.5, 8.5), 0.0);
        assert!(l0.sample_clamp(f32::NAN, -5.0).is_finite());
        assert_eq!(t.level(99).width, 2);
    }
}
