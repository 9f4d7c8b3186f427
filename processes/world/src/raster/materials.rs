//! Materials (per-triangle mip selection) and shaders (per-pixel value) of terrain, rocks and
//! flat markers.

use super::tri::{Block, Material, Setup, Shader, Target, mip_level, shade_block_generic};
use crate::texture::{MipTexture, TextureLevel};

/// The detail tile only matters while the atlas is magnified (atlas texels larger than a
/// pixel, i.e. closer than ~5 m); beyond this detail level it is skipped.
const DETAIL_MAX_LEVEL: usize = 1;

/// Terrain: baked atlas (shading included), optionally times the detail tile.
pub(crate) struct TerrainMaterial<'a> {
    pub atlas: &'a MipTexture,
    pub detail: Option<(&'a MipTexture, [f32; 2])>,
}

struct AtlasShader<'a> {
    a: &'a TextureLevel,
}

impl Shader for AtlasShader<'_> {
    #[inline(always)]
    fn shade(&self, u: f32, v: f32, _s: f32) -> u8 {
        self.a.sample_clamp(u * self.a.scale_u, v * self.a.scale_v) as u8
    }

    #[inline(always)]
    fn shade_block(&self, zb: &mut [f32], ob: &mut [u8], b: &Block) {
        let Some(mut c) = ClampRamp::new(self.a, b, zb.len()) else {
            return shade_block_generic(self, zb, ob, b);
        };
        let mut iz = b.iz;
        for (zp, op) in zb.iter_mut().zip(ob.iter_mut()) {
            if iz > *zp {
                *zp = iz;
                *op = c.sample() as u8;
            }
            iz += b.diz;
            c.uv.step();
        }
    }
}

/// Fixed-point (16.16) texture coordinates and their step per pixel along a block.
#[derive(Debug, Clone, Copy)]
struct FixedUv {
    u: i32,
    v: i32,
    du: i32,
    dv: i32,
}

impl FixedUv {
    #[inline(always)]
    fn new(u: f32, v: f32, du: f32, dv: f32) -> Self {
        Self {
            u: (u * 65536.0) as i32,
            v: (v * 65536.0) as i32,
            du: (du * 65536.0) as i32,
            dv: (dv * 65536.0) as i32,
        }
    }

    #[inline(always)]
    fn step(&mut self) {
        // Wrapping: the block loop steps once past its last pixel, where a grazing view's
        // step (tens of thousands of texels per pixel) leaves i32; that value is never sampled.
        self.u = self.u.wrapping_add(self.du);
        self.v = self.v.wrapping_add(self.dv);
    }

    /// Column and row of the texel at or before the coordinates.
    #[inline(always)]
    fn texel(&self) -> (usize, usize) {
        ((self.u >> 16) as usize, (self.v >> 16) as usize)
    }

    /// Bilinear blend of texels `[t00, t01]` (row 0) and `[t10, t11]` (row 1) with the
    /// fractions in bits 8..16 of the coordinates.
    #[inline(always)]
    fn blend(&self, [t00, t01]: [u32; 2], [t10, t11]: [u32; 2]) -> u32 {
        let fx = ((self.u >> 8) & 0xff) as u32;
        let fy = ((self.v >> 8) & 0xff) as u32;
        let top = t00 * (256 - fx) + t01 * fx;
        let bot = t10 * (256 - fx) + t11 * fx;
        (top * (256 - fy) + bot * fy) >> 16
    }
}

/// Texture coordinates stepping along a block, for a clamped level whose block stays inside
/// the texture (so no clamping per pixel).
struct ClampRamp<'a> {
    data: &'a [u8],
    w: usize,
    uv: FixedUv,
}

impl<'a> ClampRamp<'a> {
    #[inline(always)]
    fn new(l: &'a TextureLevel, b: &Block, n: usize) -> Option<Self> {
        let u0 = b.u * l.scale_u - 0.5;
        let v0 = b.v * l.scale_v - 0.5;
        let du = b.du * l.scale_u;
        let dv = b.dv * l.scale_v;
        let last = n.saturating_sub(1) as f32;
        let (u1, v1) = (u0 + du * last, v0 + dv * last);
        let (lim_u, lim_v) = (l.lim_u, l.lim_v);
        let inside =
            u0.min(u1) >= 0.0 && u0.max(u1) <= lim_u && v0.min(v1) >= 0.0 && v0.max(v1) <= lim_v;
        inside.then(|| Self {
            data: &l.data,
            w: l.width,
            uv: FixedUv::new(u0, v0, du, dv),
        })
    }

    /// Bilinear sample, 0..=255; 0 where a texel would be out of range (instead of panicking).
    #[inline(always)]
    fn sample(&self) -> u32 {
        let (x, y) = self.uv.texel();
        let i0 = y * self.w + x;
        let i1 = i0 + self.w;
        let (Some(r0), Some(r1)) = (self.data.get(i0..i0 + 2), self.data.get(i1..i1 + 2)) else {
            return 0;
        };
        let texels = |row: &[u8]| [u32::from(row[0]), u32::from(row[1])];
        self.uv.blend(texels(r0), texels(r1))
    }
}

/// Fixed-point coordinates on a wrapping power-of-two level.
struct WrapRamp<'a> {
    data: &'a [u8],
    w: usize,
    mx: usize,
    my: usize,
    uv: FixedUv,
}

impl<'a> WrapRamp<'a> {
    #[inline(always)]
    fn new(l: &'a TextureLevel, u: f32, v: f32, du: f32, dv: f32) -> Self {
        // Reduce to one period so the fixed-point values cannot overflow.
        let (wf, hf) = (l.width as f32, l.height as f32);
        let u0 = u - 0.5;
        let v0 = v - 0.5;
        let u0 = u0 - crate::texture::fast_floor(u0 / wf) as f32 * wf;
        let v0 = v0 - crate::texture::fast_floor(v0 / hf) as f32 * hf;
        let lim = 4096.0; // keep |step| · 16 px far below 2^15 texels
        Self {
            data: &l.data,
            w: l.width,
            mx: l.width - 1,
            my: l.height - 1,
            uv: FixedUv::new(u0, v0, du.clamp(-lim, lim), dv.clamp(-lim, lim)),
        }
    }

    #[inline(always)]
    fn sample(&self) -> u32 {
        let (x, y) = self.uv.texel();
        let (x0, y0) = (x & self.mx, y & self.my);
        let x1 = (x0 + 1) & self.mx;
        let y1 = (y0 + 1) & self.my;
        let (r0, r1) = (y0 * self.w, y1 * self.w);
        let px = |i: usize| u32::from(self.data.get(i).copied().unwrap_or(0));
        self.uv
            .blend([px(r0 + x0), px(r0 + x1)], [px(r1 + x0), px(r1 + x1)])
    }
}

struct AtlasDetailShader<'a> {
    a: &'a TextureLevel,
    d: &'a TextureLevel,
    du: f32,
    dv: f32,
}

impl Shader for AtlasDetailShader<'_> {
    #[inline(always)]
    fn shade(&self, u: f32, v: f32, _s: f32) -> u8 {
        let a = self.a.sample_clamp(u * self.a.scale_u, v * self.a.scale_v);
        let d = self.d.sample_wrap(u * self.du, v * self.dv);
        (a * d * (1.0 / 128.0)).min(255.0) as u8
    }

    #[inline(always)]
    fn shade_block(&self, zb: &mut [f32], ob: &mut [u8], b: &Block) {
        let Some(mut c) = ClampRamp::new(self.a, b, zb.len()) else {
            return shade_block_generic(self, zb, ob, b);
        };
        let mut d = WrapRamp::new(
            self.d,
            b.u * self.du,
            b.v * self.dv,
            b.du * self.du,
            b.dv * self.dv,
        );
        let mut iz = b.iz;
        for (zp, op) in zb.iter_mut().zip(ob.iter_mut()) {
            if iz > *zp {
                *zp = iz;
                *op = ((c.sample() * d.sample()) >> 7).min(255) as u8;
            }
            iz += b.diz;
            c.uv.step();
            d.uv.step();
        }
    }
}

impl Material for TerrainMaterial<'_> {
    #[inline(always)]
    fn draw(&self, t: &mut Target<'_>, s: &Setup, uv_area: f32) {
        let screen_area = 0.5 * s.area2;
        let a = self.atlas.level(mip_level(uv_area, screen_area));
        if let Some((detail, per_atlas)) = self.detail {
            let ld = mip_level(uv_area * per_atlas[0] * per_atlas[1], screen_area);
            if ld <= DETAIL_MAX_LEVEL {
                let d = detail.level(ld);
                let shader = AtlasDetailShader {
                    a,
                    d,
                    du: per_atlas[0] * d.scale_u,
                    dv: per_atlas[1] * d.scale_v,
                };
                s.fill(t, &shader);
                return;
            }
        }
        s.fill(t, &AtlasShader { a });
    }
}

/// Rocks: wrapping rock tile times the per-vertex brightness `s` (albedo × shading / 128).
pub(crate) struct RockMaterial<'a> {
    pub tex: &'a MipTexture,
}

struct RockShader<'a> {
    l: &'a TextureLevel,
}

impl Shader for RockShader<'_> {
    #[inline(always)]
    fn shade(&self, u: f32, v: f32, s: f32) -> u8 {
        (self.l.sample_wrap(u * self.l.scale_u, v * self.l.scale_v) * s).clamp(0.0, 255.0) as u8
    }

    #[inline(always)]
    fn shade_block(&self, zb: &mut [f32], ob: &mut [u8], b: &Block) {
        let (su, sv) = (self.l.scale_u, self.l.scale_v);
        let mut t = WrapRamp::new(self.l, b.u * su, b.v * sv, b.du * su, b.dv * sv);
        // Brightness in 8.8 fixed point.
        let mut s = (b.s.clamp(0.0, 64.0) * 256.0) as i32;
        let ds = (b.ds.clamp(-64.0, 64.0) * 256.0) as i32;
        let mut iz = b.iz;
        for (zp, op) in zb.iter_mut().zip(ob.iter_mut()) {
            if iz > *zp {
                *zp = iz;
                *op = ((t.sample() * s.max(0) as u32) >> 8).min(255) as u8;
            }
            iz += b.diz;
            t.uv.step();
            s += ds;
        }
    }
}

impl Material for RockMaterial<'_> {
    #[inline(always)]
    fn draw(&self, t: &mut Target<'_>, s: &Setup, uv_area: f32) {
        let l = self.tex.level(mip_level(uv_area, 0.5 * s.area2));
        s.fill(t, &RockShader { l });
    }
}

/// A constant value (markers).
pub(crate) struct FlatMaterial(pub u8);

impl Shader for FlatMaterial {
    #[inline(always)]
    fn shade(&self, _u: f32, _v: f32, _s: f32) -> u8 {
        self.0
    }
}

impl Material for FlatMaterial {
    fn draw(&self, t: &mut Target<'_>, s: &Setup, _uv_area: f32) {
        s.fill(t, self);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Regression: the camera process panicked ("attempt to add with overflow", debug build)
    /// on a one-pixel block seen at a grazing angle.
    #[test]
    fn a_clamped_ramp_steps_past_its_block_without_overflow() {
        let texture = MipTexture::from_base(4, 4, vec![100; 16], false);
        let block = Block {
            iz: 1.0,
            diz: 0.0,
            u: 1.0,
            du: 1.0e5,
            v: 1.0,
            dv: 1.0e5,
            s: 0.0,
            ds: 0.0,
        };
        let mut ramp = ClampRamp::new(texture.level(0), &block, 1).expect("inside");
        assert!(ramp.sample() > 0);
        ramp.uv.step();
    }
}
