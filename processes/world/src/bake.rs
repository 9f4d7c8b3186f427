//! Baking the procedural textures: the terrain atlas (albedo noise, pebbles, bump shading, cast
//! shadows), the fine-detail tile (sand, grit, gravel) and the rock tile.
//!
//! Rows are baked on a few threads, each row independently, so the bytes never depend on the
//! thread count; everything else is sequential and seeded.

use crate::World;
use crate::config::TextureConfig;
use crate::noise::{NoiseKind, fbm, fbm_periodic, fbm_range, fbm_row_add};
use crate::rng::{Rng, derive_seed};
use crate::texture::{DETAIL_TILE_TEXELS, MipTexture, ROCK_TILE_TEXELS, TerrainTexture};

const ALBEDO_STREAM: u64 = 0x616c_6265_646f; // "albedo"
const BUMP_STREAM: u64 = 0x6275_6d70; // "bump"
const PEBBLE_STREAM: u64 = 0x7065_6262_6c65; // "pebble"
const DETAIL_STREAM: u64 = 0x6465_7461_696c; // "detail"
const ROCKTEX_STREAM: u64 = 0x726f_636b_7478; // "rocktx"

/// Runs `f(row, row_slice)` for every row of `data` (`width` items per row) on a few scoped
/// threads pulling rows from a shared queue; the calling thread works too, so nothing is lost
/// if a thread cannot be spawned. Rows are computed independently, so the result does not
/// depend on the thread count or order.
fn par_rows<T: Send>(data: &mut [T], width: usize, f: impl Fn(usize, &mut [T]) + Sync) {
    if width == 0 {
        return;
    }
    let queue = std::sync::Mutex::new(data.chunks_mut(width).enumerate());
    let work = || {
        loop {
            let next = match queue.lock() {
                Ok(mut q) => q.next(),
                Err(poisoned) => poisoned.into_inner().next(),
            };
            match next {
                Some((r, row)) => f(r, row),
                None => break,
            }
        }
    };
    let helpers = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .clamp(1, 4)
        - 1;
    std::thread::scope(|scope| {
        for _ in 0..helpers {
            // A failed spawn only means fewer helpers.
            let _ = std::thread::Builder::new().spawn_scoped(scope, work);
        }
        work();
    });
}

/// Grid step of the coarse albedo octaves, texels.
const COARSE_STEP: usize = 8;
/// Albedo octaves (of 7, 4 m first) evaluated on the coarse grid.
const COARSE_OCTAVES: u32 = 4;

/// Bakes the terrain atlas: albedo noise, pebbles and shading (sun from `lighting`).
pub fn bake_terrain_texture(world: &World) -> TerrainTexture {
    let cfg = &world.config().texture;
    let light = &world.config().lighting;
    let hf = world.terrain();
    let seed = world.config().seed;
    let [ex, ey] = hf.extent_m();
    let tw = ((ex / cfg.texel_m).ceil() as usize).clamp(2, crate::config::MAX_TEXTURE_TEXELS);
    let th = ((ey / cfg.texel_m).ceil() as usize).clamp(2, crate::config::MAX_TEXTURE_TEXELS);
    let texel = [ex / tw as f64, ey / th as f64];
    let [ox, oy] = hf.origin_m();

    // Centimetre-scale bump heights (for shading) and pebble albedo offsets.
    let mut bump = bump_heights(seed, cfg, texel, (tw, th));
    let mut pebble_albedo = vec![0f32; tw * th];
    splat_pebbles(
        seed,
        cfg,
        [ex, ey],
        texel,
        tw,
        th,
        &mut bump,
        &mut pebble_albedo,
    );

    let s_alb = derive_seed(seed, ALBEDO_STREAM);
    let (coarse, (cw, chh)) = coarse_albedo(s_alb, texel, (tw, th));

    let sun = light.sun_direction();
    let node_shadow = crate::shadows::terrain_shadow(hf, sun);
    let rock_shadow = crate::shadows::rock_shadow_mask(hf, world.rocks(), sun, (tw, th), texel);
    let (nx, spacing) = (hf.nx(), hf.spacing_m());
    let flat_shade = light.ambient + (1.0 - light.ambient) * sun[2];
    let mut data = vec![0u8; tw * th];
    par_rows(&mut data, tw, |ty, row| {
        let yl = (ty as f64 + 0.5) * texel[1];
        let y = oy + yl;
        let gy = (ty as f64 + 0.5) / COARSE_STEP as f64;
        let (cy0, fy) = (gy as usize, gy.fract());
        let mut fine_row = vec![0f64; row.len()];
        let (x0, dx) = (0.5 * texel[0] / 4.0, texel[0] / 4.0);
        fbm_row_add(
            s_alb,
            x0,
            dx,
            yl / 4.0,
            COARSE_OCTAVES..7,
            0.6,
            0.5,
            &mut fine_row,
        );
        for (tx, out) in row.iter_mut().enumerate() {
            let xl = (tx as f64 + 0.5) * texel[0];
            let x = ox + xl;
            let gx = (tx as f64 + 0.5) / COARSE_STEP as f64;
            let (cx0, fx) = (gx as usize, gx.fract());
            let c = |i: usize, j: usize| coarse[(j.min(chh - 1)) * cw + i.min(cw - 1)];
            let low = (c(cx0, cy0) * (1.0 - fx) + c(cx0 + 1, cy0) * fx) * (1.0 - fy)
                + (c(cx0, cy0 + 1) * (1.0 - fx) + c(cx0 + 1, cy0 + 1) * fx) * fy;
            let fine = fine_row[tx];
            let k = ty * tw + tx;
            let albedo = cfg.albedo_dn
                * (1.0 + cfg.macro_contrast * (low + fine) + f64::from(pebble_albedo[k])).max(0.05);
            // Shading: terrain normal tilted by the bump gradient.
            let n = hf.normal_at(x, y);
            let lambert = bumped_lambert(n, &bump, (tx, ty), (tw, th), texel, sun);
            // Cast shadows: terrain (bilinear over nodes, soft edges) and rocks (per texel).
            let terrain_sh = node_shadow_at(&node_shadow, (nx, hf.ny()), spacing, (xl, yl));
            let shadow = terrain_sh.max(f64::from(rock_shadow[k]) / 255.0);
            let lit = lambert * (1.0 - shadow);
            let shade = (light.ambient + (1.0 - light.ambient) * lit) / flat_shade;
            *out = (albedo * shade + 0.5).clamp(1.0, 255.0) as u8;
        }
    });
    TerrainTexture {
        atlas: MipTexture::from_base(tw, th, data, false),
        origin_m: [ox, oy],
        texel_m: texel,
    }
}

/// Lambert factor of texel `(tx, ty)` for the terrain normal `n` tilted by the gradient of
/// the bump heights.
fn bumped_lambert(
    n: [f64; 3],
    bump: &[f32],
    (tx, ty): (usize, usize),
    (tw, th): (usize, usize),
    texel: [f64; 2],
    sun: [f64; 3],
) -> f64 {
    let kx0 = ty * tw + tx.saturating_sub(1);
    let kx1 = ty * tw + (tx + 1).min(tw - 1);
    let ky0 = ty.saturating_sub(1) * tw + tx;
    let ky1 = (ty + 1).min(th - 1) * tw + tx;
    let gxb = f64::from(bump[kx1] - bump[kx0]) / (2.0 * texel[0]);
    let gyb = f64::from(bump[ky1] - bump[ky0]) / (2.0 * texel[1]);
    let (mx, my, mz) = (n[0] - gxb * n[2], n[1] - gyb * n[2], n[2]);
    let len = (mx * mx + my * my + mz * mz).sqrt();
    ((mx * sun[0] + my * sun[1] + mz * sun[2]) / len).max(0.0)
}

/// The terrain's cast shadow at `(xl, yl)` metres from the grid origin: the node shadows
/// interpolated bilinearly (soft edges).
fn node_shadow_at(
    node_shadow: &[f32],
    (nx, ny): (usize, usize),
    spacing: f64,
    (xl, yl): (f64, f64),
) -> f64 {
    let (gx, gy) = (xl / spacing, yl / spacing);
    let (i0, j0) = ((gx as usize).min(nx - 2), (gy as usize).min(ny - 2));
    let (fx, fy) = ((gx - i0 as f64).min(1.0), (gy - j0 as f64).min(1.0));
    let sh = |i: usize, j: usize| f64::from(node_shadow[j * nx + i]);
    (sh(i0, j0) * (1.0 - fx) + sh(i0 + 1, j0) * fx) * (1.0 - fy)
        + (sh(i0, j0 + 1) * (1.0 - fx) + sh(i0 + 1, j0 + 1) * fx) * fy
}

/// Centimetre-scale bump heights (for shading), one a texel of the `tw`×`th` atlas.
fn bump_heights(
    seed: u64,
    cfg: &TextureConfig,
    texel: [f64; 2],
    (tw, th): (usize, usize),
) -> Vec<f32> {
    let mut bump = vec![0f32; tw * th];
    let bump_wl_m = 0.5;
    let octaves = ((bump_wl_m / (2.0 * texel[0].max(texel[1])))
        .log2()
        .floor()
        .max(0.0) as u32
        + 1)
    .min(8);
    if cfg.bump_amplitude_m > 0.0 {
        let s = derive_seed(seed, BUMP_STREAM);
        par_rows(&mut bump, tw, |ty, row| {
            let y = (ty as f64 + 0.5) * texel[1];
            let mut acc = vec![0f64; row.len()];
            let (x0, dx) = (0.5 * texel[0] / bump_wl_m, texel[0] / bump_wl_m);
            fbm_row_add(
                s,
                x0,
                dx,
                y / bump_wl_m,
                0..octaves,
                0.5,
                cfg.bump_amplitude_m,
                &mut acc,
            );
            for (b, a) in row.iter_mut().zip(&acc) {
                *b = *a as f32;
            }
        });
    }
    bump
}

/// Coarse albedo octaves (16 m patches and 4 m … 0.5 m) on a grid every `COARSE_STEP`
/// texels (one row and column beyond the atlas); returns the grid and its size.
fn coarse_albedo(
    s_alb: u64,
    texel: [f64; 2],
    (tw, th): (usize, usize),
) -> (Vec<f64>, (usize, usize)) {
    let (cw, chh) = (tw / COARSE_STEP + 2, th / COARSE_STEP + 2);
    let mut coarse = vec![0f64; cw * chh];
    for cy in 0..chh {
        for cx in 0..cw {
            let xl = (cx * COARSE_STEP) as f64 * texel[0];
            let yl = (cy * COARSE_STEP) as f64 * texel[1];
            let patches = fbm(NoiseKind::Value, s_alb ^ 1, xl / 16.0, yl / 16.0, 2, 0.5);
            let mid = fbm_range(
                NoiseKind::Value,
                s_alb,
                xl / 4.0,
                yl / 4.0,
                0..COARSE_OCTAVES,
                0.6,
            );
            coarse[cy * cw + cx] = 0.4 * patches + 0.5 * mid;
        }
    }
    (coarse, (cw, chh))
}

/// Pebbles: small domes added to the bump map with a per-pebble albedo offset.
#[allow(clippy::too_many_arguments)]
fn splat_pebbles(
    seed: u64,
    cfg: &TextureConfig,
    extent_m: [f64; 2],
    texel: [f64; 2],
    tw: usize,
    th: usize,
    bump: &mut [f32],
    albedo: &mut [f32],
) {
    let count = (cfg.pebble_density_per_m2 * extent_m[0] * extent_m[1]) as usize;
    let mut rng = Rng::new(seed, PEBBLE_STREAM);
    let (ln_lo, ln_hi) = (0.01f64.ln(), 0.08f64.ln());
    for _ in 0..count {
        let cx = rng.uniform(0.0, extent_m[0]);
        let cy = rng.uniform(0.0, extent_m[1]);
        let u = rng.next_f64();
        let r = (ln_lo + (ln_hi - ln_lo) * u * u).exp() / 2.0; // radius, skewed small
        let dome = (0.6 * r) as f32;
        let offset = rng.uniform(-0.25, 0.2) as f32;
        let rx = (r / texel[0]).ceil() as isize;
        let ry = (r / texel[1]).ceil() as isize;
        let ctx = (cx / texel[0]) as isize;
        let cty = (cy / texel[1]) as isize;
        for dy in -ry..=ry {
            let ty = cty + dy;
            if ty < 0 || ty >= th as isize {
                continue;
            }
            for dx in -rx..=rx {
                let tx = ctx + dx;
                if tx < 0 || tx >= tw as isize {
                    continue;
                }
                let px = (tx as f64 + 0.5) * texel[0] - cx;
                let py = (ty as f64 + 0.5) * texel[1] - cy;
                let q = (px * px + py * py) / (r * r);
                if q < 1.0 {
                    let k = ty as usize * tw + tx as usize;
                    let h = (1.0 - q).sqrt() as f32;
                    bump[k] += dome * h;
                    albedo[k] = albedo[k] * 0.3 + offset * h.sqrt();
                }
            }
        }
    }
}

/// Bakes the wrapping fine-detail tile, mean ≈ 128: sand (noise), grit (1–3 texel dots) and
/// gravel (6–20 mm stones shaded by the sun `sun`, with a small shadow on the far side), so
/// close views (≲ 5 m) have corners at centimetre scale.
pub fn bake_detail_texture(seed: u64, cfg: &TextureConfig, sun: [f64; 3]) -> MipTexture {
    let n = DETAIL_TILE_TEXELS;
    let s = derive_seed(seed, DETAIL_STREAM);
    let mut rng = Rng::new(seed, DETAIL_STREAM);
    let mut v = vec![0f64; n * n];
    for y in 0..n {
        for x in 0..n {
            let (fx, fy) = (x as f64 / 16.0, y as f64 / 16.0);
            v[y * n + x] = 0.5 * fbm_periodic(s, fx, fy, 4, 0.6, (n / 16) as i64)
                + 0.2 * (rng.next_f64() * 2.0 - 1.0);
        }
    }
    let wrap = |px: isize, py: isize| {
        py.rem_euclid(n as isize) as usize * n + px.rem_euclid(n as isize) as usize
    };
    // Grit: 1–3 texel dots, dark or bright.
    for _ in 0..(n * n / 40) {
        let (cx, cy) = (rng.uniform(0.0, n as f64), rng.uniform(0.0, n as f64));
        let r = rng.uniform(0.7, 2.5);
        let a = rng.uniform(-1.0, 0.8);
        let ri = r.ceil() as isize;
        for dy in -ri..=ri {
            for dx in -ri..=ri {
                let (px, py) = (cx.floor() as isize + dx, cy.floor() as isize + dy);
                let d2 = (px as f64 + 0.5 - cx).powi(2) + (py as f64 + 0.5 - cy).powi(2);
                if d2 < r * r {
                    let k = wrap(px, py);
                    v[k] = v[k] * 0.4 + a * 0.8;
                }
            }
        }
    }
    // Gravel: shaded domes with a shadow on the side away from the sun.
    let horiz = (sun[0] * sun[0] + sun[1] * sun[1]).sqrt().max(1e-9);
    let (hx, hy) = (sun[0] / horiz, sun[1] / horiz);
    let flat = sun[2].max(0.05);
    for _ in 0..(n * n / 300) {
        let (cx, cy) = (rng.uniform(0.0, n as f64), rng.uniform(0.0, n as f64));
        let r = rng.uniform(1.0, 4.5);
        let elong = rng.uniform(0.6, 1.0); // elliptical outline, random orientation
        let (sa, ca) = rng.uniform(0.0, std::f64::consts::PI).sin_cos();
        let albedo = rng.uniform(-0.6, 0.2);
        let ri = (2.0 * r).ceil() as isize;
        for dy in -ri..=ri {
            for dx in -ri..=ri {
                let (px, py) = (cx.floor() as isize + dx, cy.floor() as isize + dy);
                let (ox, oy) = (px as f64 + 0.5 - cx, py as f64 + 0.5 - cy);
                let (lx, ly) = ((ca * ox + sa * oy) / r, (-sa * ox + ca * oy) / (r * elong));
                let d2 = lx * lx + ly * ly;
                let k = wrap(px, py);
                if d2 < 1.0 {
                    // Flattish dome: the normal's z is doubled before normalising.
                    let (gx, gy) = (ca * lx - sa * ly, sa * lx + ca * ly);
                    let nz = 2.0 * (1.0 - d2).sqrt();
                    let len = (gx * gx + gy * gy + nz * nz).sqrt();
                    let lambert = ((gx * sun[0] + gy * sun[1] + nz * sun[2]) / len).max(0.0);
                    v[k] = albedo + 0.8 * (lambert / flat - 1.0).clamp(-1.0, 0.6);
                } else {
                    // Shadow: a disc shifted away from the sun, outside the stone.
                    let (sx, sy) = (ox + hx * 0.5 * r, oy + hy * 0.5 * r);
                    if sx * sx + sy * sy < r * r {
                        v[k] -= 0.4;
                    }
                }
            }
        }
    }
    let data = v
        .iter()
        .map(|&x| {
            (128.0 * (1.0 + cfg.detail_contrast * x))
                .round()
                .clamp(0.0, 255.0) as u8
        })
        .collect();
    MipTexture::from_base(n, n, data, true)
}

/// Bakes the wrapping rock tile, mean ≈ 128.
pub fn bake_rock_texture(seed: u64) -> MipTexture {
    let n = ROCK_TILE_TEXELS;
    let s = derive_seed(seed, ROCKTEX_STREAM);
    let mut rng = Rng::new(seed, ROCKTEX_STREAM);
    let data = (0..n * n)
        .map(|k| {
            let (x, y) = ((k % n) as f64, (k / n) as f64);
            let base = fbm_periodic(s, x / 32.0, y / 32.0, 5, 0.55, (n / 32) as i64);
            let vein = fbm_periodic(s ^ 7, x / 64.0, y / 64.0, 3, 0.5, (n / 64) as i64);
            let vein = (1.0 - (vein * 6.0).abs()).max(0.0);
            let speck = rng.next_f64() * 2.0 - 1.0;
            let v = 1.0 + 0.35 * base - 0.35 * vein + 0.15 * speck;
            (128.0 * v).round().clamp(0.0, 255.0) as u8
        })
        .collect();
    MipTexture::from_base(n, n, data, true)
}
