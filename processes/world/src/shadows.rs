//! Cast shadows baked into the terrain texture: terrain self-shadowing (per grid node, ray
//! marched towards the sun) and rock shadows (per texel, ray–ellipsoid tests).
//!
//! ```
//! use hopnav_world::shadows::terrain_shadow;
//! use hopnav_world::terrain::Heightfield;
//! let hf = Heightfield::flat(9, 9, 0.5, 0.0);
//! let s = terrain_shadow(&hf, [0.6, 0.0, 0.8]);
//! assert!(s.iter().all(|&v| v == 0.0)); // flat ground casts no shadow
//! ```

use crate::rocks::Rock;
use crate::terrain::Heightfield;

/// Per-node shadow (1 = in shadow, 0 = lit) of the heightfield for the unit vector `sun`
/// (pointing towards the sun, z up). Row-major like the heights.
pub fn terrain_shadow(hf: &Heightfield, sun: [f64; 3]) -> Vec<f32> {
    let (nx, ny) = (hf.nx(), hf.ny());
    let mut out = vec![0f32; nx * ny];
    let horiz = (sun[0] * sun[0] + sun[1] * sun[1]).sqrt();
    if horiz < 1e-9 || sun[2] <= 0.0 {
        return out;
    }
    let (dx, dy) = (sun[0] / horiz, sun[1] / horiz);
    let slope = sun[2] / horiz; // rise per metre along the ground
    let step = hf.spacing_m();
    let (_, zmax) = hf.height_range_m();
    for j in 0..ny {
        for i in 0..nx {
            let [x, y] = hf.node_xy_m(i, j);
            let z = hf.node_height_m(i, j);
            let mut k = 1.0;
            loop {
                let ray_z = z + k * step * slope;
                if ray_z > zmax {
                    break;
                }
                let (qx, qy) = (x + k * step * dx, y + k * step * dy);
                if !hf.contains(qx, qy) {
                    break;
                }
                if hf.height_at(qx, qy) > ray_z + 1e-3 {
                    out[j * nx + i] = 1.0;
                    break;
                }
                k += 1.0;
            }
        }
    }
    out
}

/// Marks (255) the texels of a `tw × th` texture covering the heightfield (texel size `texel`)
/// that lie in the shadow of a rock, each rock approximated by its ellipsoid.
pub fn rock_shadow_mask(
    hf: &Heightfield,
    rocks: &[Rock],
    sun: [f64; 3],
    size: (usize, usize),
    texel: [f64; 2],
) -> Vec<u8> {
    let (tw, th) = size;
    let mut mask = vec![0u8; tw * th];
    let horiz = (sun[0] * sun[0] + sun[1] * sun[1]).sqrt();
    if sun[2] <= 0.0 {
        return mask;
    }
    let [ox, oy] = hf.origin_m();
    for r in rocks {
        let [a, b, c] = r.half_extents_m;
        let reach = a.max(b);
        let len = if horiz > 1e-9 {
            c * horiz / sun[2]
        } else {
            0.0
        };
        let (sx, sy) = if horiz > 1e-9 {
            (-sun[0] / horiz * len, -sun[1] / horiz * len)
        } else {
            (0.0, 0.0)
        };
        let [cx, cy, cz] = r.center_m;
        let (x0, x1) = (
            (cx - reach).min(cx + sx - reach),
            (cx + reach).max(cx + sx + reach),
        );
        let (y0, y1) = (
            (cy - reach).min(cy + sy - reach),
            (cy + reach).max(cy + sy + reach),
        );
        let to_tx = |x: f64| ((x - ox) / texel[0]).floor().clamp(0.0, tw as f64) as usize;
        let to_ty = |y: f64| ((y - oy) / texel[1]).floor().clamp(0.0, th as f64) as usize;
        let (s, co) = r.yaw_rad.sin_cos();
        // Ray direction in the rock's unit-sphere frame (constant per rock).
        let dl = [
            (co * sun[0] + s * sun[1]) / a,
            (-s * sun[0] + co * sun[1]) / b,
            sun[2] / c,
        ];
        let dd = dl[0] * dl[0] + dl[1] * dl[1] + dl[2] * dl[2];
        for ty in to_ty(y0)..to_ty(y1).saturating_add(1).min(th) {
            let y = oy + (ty as f64 + 0.5) * texel[1];
            for tx in to_tx(x0)..to_tx(x1).saturating_add(1).min(tw) {
                let x = ox + (tx as f64 + 0.5) * texel[0];
                let z = hf.height_at(x, y);
                let (px, py, pz) = (x - cx, y - cy, z - cz);
                let o = [(co * px + s * py) / a, (-s * px + co * py) / b, pz / c];
                let od = o[0] * dl[0] + o[1] * dl[1] + o[2] * dl[2];
                let oo = o[0] * o[0] + o[1] * o[1] + o[2] * o[2];
                // |o + t·d|² = 1 has a root t > 0 ⇔ the ray towards the sun hits the rock.
                let disc = od * od - dd * (oo - 1.0);
                if disc >= 0.0 && -od + disc.sqrt() > 0.0 {
                    mask[ty * tw + tx] = 255;
                }
            }
        }
    }
    mask
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rocks::RockSource;

    #[test]
    fn a_rock_shadows_the_ground_away_from_the_sun() {
        let hf = Heightfield::flat(41, 41, 0.1, 0.0);
        let rock = Rock {
            center_m: [0.0, 0.0, 0.0],
            diameter_m: 0.4,
            height_m: 0.2,
            half_extents_m: [0.2, 0.2, 0.2],
            yaw_rad: 0.0,
            shape_seed: 1,
            source: RockSource::Explicit(0),
        };
        let sun = [
            std::f64::consts::FRAC_1_SQRT_2,
            0.0,
            std::f64::consts::FRAC_1_SQRT_2,
        ];
        let mask = rock_shadow_mask(&hf, &[rock], sun, (40, 40), [0.1, 0.1]);
        let at =
            |x: f64, y: f64| mask[(((y + 2.0) / 0.1) as usize) * 40 + ((x + 2.0) / 0.1) as usize];
        // A hemisphere of radius r under a 45° sun shades the ground out to r·√2 ≈ 0.28 m.
        assert_eq!(at(-0.25, 0.02), 255, "shadow on the side away from the sun");
        assert_eq!(at(0.25, 0.02), 0, "lit on the sunny side");
        assert_eq!(at(-0.35, 0.02), 0, "beyond the tangent ray");
    }

    #[test]
    fn a_wall_shadows_the_ground_behind_it() {
        let mut hf = Heightfield::flat(21, 3, 0.5, 0.0);
        // A 1 m step at x ≥ 0 (i ≥ 10); sun low from +x.
        for j in 0..3 {
            for i in 10..21 {
                hf.heights_mut()[j * 21 + i] = 1.0;
            }
        }
        let sun = [0.894, 0.0, 0.447]; // elevation ≈ 26.6°, shadow ≈ 2 m long
        let s = terrain_shadow(&hf, sun);
        assert_eq!(s[21 + 8], 1.0); // x = -1 m, right behind the step
        assert_eq!(s[21 + 4], 0.0); // x = -3 m, beyond the shadow
        assert_eq!(s[21 + 15], 0.0); // on top
    }
}
