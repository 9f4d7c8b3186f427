//! Triangle setup, near-plane clipping and span filling (the hot loop).
//!
//! Screen coordinates are OpenCV pixel coordinates; pixel `(x, y)` is sampled at its centre,
//! the integer point `(x, y)`. A pixel belongs to a triangle when `ceil(x_left) ≤ x < ceil(x_right)`
//! and `ceil(y_top) ≤ y < ceil(y_bottom)`; edges are evaluated with their endpoints in a fixed
//! order, so triangles sharing an edge neither overlap nor leave gaps.
//!
//! Attributes (`u`, `v`, `s`) are interpolated perspective-correctly: `1/z`, `u/z`, `v/z` and
//! `s/z` are affine in screen space; each pixel divides by `1/z` once. The z-buffer holds `1/z`
//! (larger is nearer, cleared to 0).

/// A vertex in the camera frame with its attributes.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct ClipVertex {
    /// Camera-frame position, metres.
    pub p: [f32; 3],
    /// Texture coordinate u (level-0 texels).
    pub u: f32,
    /// Texture coordinate v (level-0 texels).
    pub v: f32,
    /// Shade / brightness factor.
    pub s: f32,
}

/// A projected vertex: pixel position and attributes pre-multiplied by `1/z`.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct ScreenVertex {
    pub x: f32,
    pub y: f32,
    pub iz: f32,
    pub uz: f32,
    pub vz: f32,
    pub sz: f32,
    /// The attributes themselves (for affine interpolation of nearly fronto-parallel triangles).
    pub u: f32,
    pub v: f32,
    pub s: f32,
}

/// Pinhole projection in `f32`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Projector {
    pub fx: f32,
    pub fy: f32,
    pub cx: f32,
    pub cy: f32,
    pub near: f32,
}

impl Projector {
    /// Projects a vertex with `z ≥ near`.
    #[inline(always)]
    pub fn project(&self, v: &ClipVertex) -> ScreenVertex {
        let iz = 1.0 / v.p[2];
        ScreenVertex {
            x: self.fx * v.p[0] * iz + self.cx,
            y: self.fy * v.p[1] * iz + self.cy,
            iz,
            uz: v.u * iz,
            vz: v.v * iz,
            sz: v.s * iz,
            u: v.u,
            v: v.v,
            s: v.s,
        }
    }
}

/// The colour and depth targets of one frame.
pub(crate) struct Target<'a> {
    pub zbuf: &'a mut [f32],
    pub out: &'a mut [u8],
    pub stride: usize,
    pub width: usize,
    pub height: usize,
}

/// Computes a pixel value from perspective-corrected attributes.
pub(crate) trait Shader {
    /// Value of one pixel.
    fn shade(&self, u: f32, v: f32, s: f32) -> u8;

    /// Depth-tests and shades one block of a span with linearly interpolated attributes.
    /// Shaders override this with fixed-point fast paths.
    #[inline(always)]
    fn shade_block(&self, zb: &mut [f32], ob: &mut [u8], b: &Block) {
        shade_block_generic(self, zb, ob, b);
    }
}

/// Attributes at the first pixel of a block and their per-pixel steps.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Block {
    pub iz: f32,
    pub diz: f32,
    pub u: f32,
    pub du: f32,
    pub v: f32,
    pub dv: f32,
    pub s: f32,
    pub ds: f32,
}

/// The reference block loop: float attributes, [`Shader::shade`] per visible pixel.
#[inline(always)]
pub(crate) fn shade_block_generic<S: Shader + ?Sized>(
    shader: &S,
    zb: &mut [f32],
    ob: &mut [u8],
    b: &Block,
) {
    let (mut iz, mut u, mut v, mut s) = (b.iz, b.u, b.v, b.s);
    for (zp, op) in zb.iter_mut().zip(ob.iter_mut()) {
        if iz > *zp {
            *zp = iz;
            *op = shader.shade(u, v, s);
        }
        iz += b.diz;
        u += b.du;
        v += b.dv;
        s += b.ds;
    }
}

/// Picks a shader for a set-up triangle (e.g. its mip level) and fills it.
pub(crate) trait Material {
    /// `uv_area` is the triangle's area in level-0 texel units squared.
    fn draw(&self, target: &mut Target<'_>, setup: &Setup, uv_area: f32);
}

/// Mip level for `uv_area` texels² drawn over `screen_area` px²: `floor(log2(ratio) / 2)`.
#[inline(always)]
pub(crate) fn mip_level(uv_area: f32, screen_area: f32) -> usize {
    let ratio = uv_area / screen_area.max(1e-12);
    let e = ((ratio.to_bits() >> 23) & 0xff) as i32 - 127;
    (e.max(0) >> 1) as usize
}

/// `ceil(v)` for `v` clamped to `[0, max]`, as an index.
#[inline(always)]
fn ceil_clamped(v: f32, max: f32) -> usize {
    // `as i32` is one instruction plus saturation fix-ups; `as usize` is far more on x86-64.
    let v = v.max(0.0).min(max);
    let t = v as i32;
    (t + i32::from((t as f32) < v)) as usize
}

/// The vertices sorted by (y, x), so every edge is always walked from the same endpoint.
#[inline(always)]
fn sorted_by_row<'v>(
    a: &'v ScreenVertex,
    b: &'v ScreenVertex,
    c: &'v ScreenVertex,
) -> (&'v ScreenVertex, &'v ScreenVertex, &'v ScreenVertex) {
    let key = |v: &ScreenVertex| (v.y, v.x);
    let less = |p: &ScreenVertex, q: &ScreenVertex| key(p) < key(q);
    let (mut t, mut m, mut bt) = (a, b, c);
    if less(m, t) {
        std::mem::swap(&mut t, &mut m);
    }
    if less(bt, m) {
        std::mem::swap(&mut m, &mut bt);
    }
    if less(m, t) {
        std::mem::swap(&mut t, &mut m);
    }
    (t, m, bt)
}

/// Screen-space x and y gradients of the four attributes `attrs` of the triangle `(a, b, c)`;
/// `inv` is one over its twice-signed area.
#[inline(always)]
fn gradients(
    (a, b, c): (&ScreenVertex, &ScreenVertex, &ScreenVertex),
    (a0, a1, a2): ([f32; 4], [f32; 4], [f32; 4]),
    inv: f32,
) -> ([f32; 4], [f32; 4]) {
    let (dx1, dy1) = (b.x - a.x, b.y - a.y);
    let (dx2, dy2) = (c.x - a.x, c.y - a.y);
    let mut ddx = [0f32; 4];
    let mut ddy = [0f32; 4];
    for k in 0..4 {
        let d1 = a1[k] - a0[k];
        let d2 = a2[k] - a0[k];
        ddx[k] = (d1 * dy2 - d2 * dy1) * inv;
        ddy[k] = (d2 * dx1 - d1 * dx2) * inv;
    }
    (ddx, ddy)
}

/// A triangle ready to fill: sorted vertices, edge slopes, attribute gradients.
pub(crate) struct Setup {
    top: (f32, f32),
    mid: (f32, f32),
    slope_long: f32,
    slope_top: f32,
    slope_bot: f32,
    mid_left: bool,
    row0: usize,
    row1: usize,
    /// Twice the screen area (positive), px².
    pub area2: f32,
    /// Attributes 1..4 are u, v, s themselves (screen-affine), not divided by z.
    affine: bool,
    base: [f32; 4],
    ref_xy: (f32, f32),
    ddx: [f32; 4],
    ddy: [f32; 4],
}

impl Setup {
    /// Sets up a front-facing triangle (counter-clockwise as seen in the image, i.e.
    /// counter-clockwise seen from outside); `None` for back faces, degenerate triangles and
    /// triangles that cover no pixel centre.
    #[inline(always)]
    pub fn new(
        a: &ScreenVertex,
        b: &ScreenVertex,
        c: &ScreenVertex,
        w: usize,
        h: usize,
    ) -> Option<Self> {
        let area2 = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
        // Also rejects NaN areas (any comparison with NaN is false).
        if area2.partial_cmp(&0.0) != Some(std::cmp::Ordering::Less) {
            return None;
        }
        let (wf, hf) = (w as f32, h as f32);
        let ymin = a.y.min(b.y).min(c.y);
        let ymax = a.y.max(b.y).max(c.y);
        let row0 = ceil_clamped(ymin, hf);
        let row_end = ceil_clamped(ymax, hf);
        if row0 >= row_end {
            return None;
        }
        let xmin = a.x.min(b.x).min(c.x);
        let xmax = a.x.max(b.x).max(c.x);
        if ceil_clamped(xmin, wf) >= ceil_clamped(xmax, wf) {
            return None;
        }
        let (t, m, bt) = sorted_by_row(a, b, c);
        let slope = |p: &ScreenVertex, q: &ScreenVertex| (q.x - p.x) / (q.y - p.y);
        let slope_long = slope(t, bt);
        let x_long_at_mid = t.x + (m.y - t.y) * slope_long;
        let inv = 1.0 / area2;
        // When 1/z varies by less than AFFINE_DEPTH_RATIO over the triangle, screen-affine
        // interpolation of u, v, s differs from the perspective-correct one by less than
        // (ratio − 1)/4 of the triangle's texture extent: use it and skip the divisions.
        let iz_min = a.iz.min(b.iz).min(c.iz);
        let iz_max = a.iz.max(b.iz).max(c.iz);
        let affine = iz_max <= iz_min * AFFINE_DEPTH_RATIO;
        let attrs = |v: &ScreenVertex| {
            if affine {
                [v.iz, v.u, v.v, v.s]
            } else {
                [v.iz, v.uz, v.vz, v.sz]
            }
        };
        let a0 = attrs(a);
        let (ddx, ddy) = gradients((a, b, c), (a0, attrs(b), attrs(c)), inv);
        Some(Self {
            top: (t.x, t.y),
            mid: (m.x, m.y),
            slope_long,
            slope_top: slope(t, m),
            slope_bot: slope(m, bt),
            mid_left: m.x < x_long_at_mid,
            affine,
            row0,
            row1: row_end,
            area2: -area2,
            base: a0,
            ref_xy: (a.x, a.y),
            ddx,
            ddy,
        })
    }

    /// Fills the covered pixels that pass the depth test.
    ///
    /// `1/z` is interpolated exactly per pixel (depth test); the attributes are divided by it
    /// exactly at the ends of 32-pixel blocks and interpolated linearly in between (along an
    /// image row the depth of the ground changes slowly, so the error stays far below a texel;
    /// one division per block instead of per pixel).
    #[inline(always)]
    pub fn fill<S: Shader>(&self, t: &mut Target<'_>, shader: &S) {
        let wf = t.width as f32;
        for y in self.row0..self.row1 {
            let yf = y as f32;
            let x_long = self.top.0 + (yf - self.top.1) * self.slope_long;
            let x_short = if yf < self.mid.1 {
                self.top.0 + (yf - self.top.1) * self.slope_top
            } else {
                self.mid.0 + (yf - self.mid.1) * self.slope_bot
            };
            let (xl, xr) = if self.mid_left {
                (x_short, x_long)
            } else {
                (x_long, x_short)
            };
            let x0 = ceil_clamped(xl, wf);
            let x1 = ceil_clamped(xr, wf);
            if x0 >= x1 {
                continue;
            }
            let (ox, oy) = (x0 as f32 - self.ref_xy.0, yf - self.ref_xy.1);
            let mut a = [0f32; 4];
            for (k, v) in a.iter_mut().enumerate() {
                *v = self.base[k] + self.ddx[k] * ox + self.ddy[k] * oy;
            }
            let zrow = &mut t.zbuf[y * t.width + x0..y * t.width + x1];
            let orow = &mut t.out[y * t.stride + x0..y * t.stride + x1];
            if self.affine {
                let d = self.ddx;
                let block = Block {
                    iz: a[0],
                    diz: d[0],
                    u: a[1],
                    du: d[1],
                    v: a[2],
                    dv: d[2],
                    s: a[3],
                    ds: d[3],
                };
                shader.shade_block(zrow, orow, &block);
            } else {
                fill_span(zrow, orow, a, self.ddx, shader);
            }
        }
    }
}

/// Pixels per block of affine attribute interpolation.
const BLOCK: usize = 32;
/// Largest max/min ratio of 1/z over a triangle drawn with screen-affine attributes.
const AFFINE_DEPTH_RATIO: f32 = 1.02;

/// One span: `a = [1/z, u/z, v/z, s/z]` at its first pixel, `d` their x-increments.
#[inline(always)]
fn fill_span<S: Shader>(zrow: &mut [f32], orow: &mut [u8], a: [f32; 4], d: [f32; 4], shader: &S) {
    let mut iz = a[0];
    let z = 1.0 / iz;
    let (mut u, mut v, mut s) = (a[1] * z, a[2] * z, a[3] * z);
    let mut a = a;
    for (zb, ob) in zrow.chunks_mut(BLOCK).zip(orow.chunks_mut(BLOCK)) {
        let n = zb.len() as f32;
        let mut e = [0f32; 4];
        for k in 0..4 {
            e[k] = a[k] + d[k] * n;
        }
        let ze = 1.0 / e[0];
        let (ue, ve, se) = (e[1] * ze, e[2] * ze, e[3] * ze);
        let inv_n = 1.0 / n;
        let block = Block {
            iz,
            diz: d[0],
            u,
            du: (ue - u) * inv_n,
            v,
            dv: (ve - v) * inv_n,
            s,
            ds: (se - s) * inv_n,
        };
        shader.shade_block(zb, ob, &block);
        a = e;
        iz = e[0];
        (u, v, s) = (ue, ve, se);
    }
}

/// Draws a triangle whose vertices are already projected (all in front of the near plane).
#[inline(always)]
pub(crate) fn draw_projected<M: Material>(
    t: &mut Target<'_>,
    m: &M,
    a: &ScreenVertex,
    b: &ScreenVertex,
    c: &ScreenVertex,
    uv_area: f32,
) -> bool {
    match Setup::new(a, b, c, t.width, t.height) {
        Some(s) => {
            m.draw(t, &s, uv_area);
            true
        }
        None => false,
    }
}

/// Texture-space area of a triangle, level-0 texels².
#[inline(always)]
pub(crate) fn uv_area(a: &ClipVertex, b: &ClipVertex, c: &ClipVertex) -> f32 {
    0.5 * ((b.u - a.u) * (c.v - a.v) - (c.u - a.u) * (b.v - a.v)).abs()
}

/// Clips a camera-frame triangle against `z = near` (keeping the part in front), projects it
/// and draws it. Triangles crossing the plane are cut, not dropped.
pub(crate) fn draw_clipped<M: Material>(
    t: &mut Target<'_>,
    m: &M,
    proj: &Projector,
    tri: [&ClipVertex; 3],
) {
    let near = proj.near;
    let inside = tri.map(|v| v.p[2] >= near);
    if inside.iter().all(|&i| !i) {
        return;
    }
    let mut poly = [ClipVertex::default(); 4];
    let mut n = 0;
    for k in 0..3 {
        let cur = tri[k];
        let nxt = tri[(k + 1) % 3];
        let (ci, ni) = (inside[k], inside[(k + 1) % 3]);
        if ci && n < 4 {
            poly[n] = *cur;
            n += 1;
        }
        if ci != ni && n < 4 {
            // Always interpolate from the inside vertex, so a shared edge gives the same point.
            let (i, o) = if ci { (cur, nxt) } else { (nxt, cur) };
            let f = (near - i.p[2]) / (o.p[2] - i.p[2]);
            let lerp = |a: f32, b: f32| a + (b - a) * f;
            poly[n] = ClipVertex {
                p: [lerp(i.p[0], o.p[0]), lerp(i.p[1], o.p[1]), near],
                u: lerp(i.u, o.u),
                v: lerp(i.v, o.v),
                s: lerp(i.s, o.s),
            };
            n += 1;
        }
    }
    let screen = poly.map(|v| proj.project(&v));
    for k in 1..n.saturating_sub(1) {
        if let Some(s) = Setup::new(&screen[0], &screen[k], &screen[k + 1], t.width, t.height) {
            m.draw(t, &s, uv_area(&poly[0], &poly[k], &poly[k + 1]));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Flat(u8);
    impl Material for Flat {
        fn draw(&self, t: &mut Target<'_>, s: &Setup, _uv: f32) {
            s.fill(t, self);
        }
    }
    impl Shader for Flat {
        fn shade(&self, _u: f32, _v: f32, _s: f32) -> u8 {
            self.0
        }
    }

    /// A `w`×`h` target whose rows follow each other without padding.
    fn packed_target<'a>(z: &'a mut [f32], out: &'a mut [u8], w: usize, h: usize) -> Target<'a> {
        Target {
            zbuf: z,
            out,
            stride: w,
            width: w,
            height: h,
        }
    }

    fn sv(x: f32, y: f32) -> ScreenVertex {
        ScreenVertex {
            x,
            y,
            iz: 1.0,
            ..Default::default()
        }
    }

    #[test]
    fn shared_edges_cover_each_pixel_once() {
        // Two triangles of a quad, drawn with additive-like check: each pixel exactly once.
        let (w, h) = (16, 16);
        let mut z = vec![0f32; w * h];
        let mut out = vec![0u8; w * h];
        let quad = [sv(1.3, 2.7), sv(13.1, 1.9), sv(14.6, 12.2), sv(2.2, 14.8)];
        let mut count = vec![0u8; w * h];
        for tri in [[0, 2, 1], [0, 3, 2]] {
            z.iter_mut().for_each(|v| *v = 0.0);
            out.iter_mut().for_each(|v| *v = 0);
            let mut t = packed_target(&mut z, &mut out, w, h);
            assert!(draw_projected(
                &mut t,
                &Flat(1),
                &quad[tri[0]],
                &quad[tri[1]],
                &quad[tri[2]],
                1.0
            ));
            for (c, o) in count.iter_mut().zip(&out) {
                *c += *o;
            }
        }
        assert!(count.iter().all(|&c| c <= 1));
        // Pixel centres well inside the quad are covered.
        assert_eq!(count[8 * w + 8], 1);
        assert_eq!(count[3 * w + 3], 1);
        assert_eq!(count[0], 0);
    }

    #[test]
    fn back_faces_are_culled() {
        let (w, h) = (8, 8);
        let mut z = vec![0f32; w * h];
        let mut out = vec![0u8; w * h];
        let mut t = packed_target(&mut z, &mut out, w, h);
        let (a, b, c) = (sv(0.0, 0.0), sv(7.0, 0.0), sv(0.0, 7.0));
        assert!(!draw_projected(&mut t, &Flat(1), &a, &b, &c, 1.0));
        assert!(draw_projected(&mut t, &Flat(1), &a, &c, &b, 1.0));
    }

    #[test]
    fn mip_level_from_ratio() {
        assert_eq!(mip_level(1.0, 1.0), 0);
        assert_eq!(mip_level(4.0, 1.0), 1);
        assert_eq!(mip_level(16.5, 1.0), 2);
        assert_eq!(mip_level(0.01, 1.0), 0);
    }
}
