//! The patch arithmetic of the stereo matcher (`stereo.rs`): rows interpolated at a sub-pixel
//! height into a band, a patch's mean and spread, zero-mean normalized cross-correlation
//! between two patches, and the parabola through three scores that refines a disparity.

use hopnav_vision::image::ImageView;

/// Interpolates `rows` rows starting at sub-pixel `y_top`, columns `x_lo..=x_hi`.
pub(crate) fn fill_band(
    image: &ImageView<'_>,
    band: &mut [f32],
    width: usize,
    y_top: f32,
    rows: usize,
    x_lo: usize,
    x_hi: usize,
) {
    let y0 = y_top.floor();
    let a = y_top - y0;
    let y0 = y0 as usize;
    for k in 0..rows {
        let (Some(r0), Some(r1)) = (image.row(y0 + k), image.row(y0 + k + 1)) else {
            continue;
        };
        let out = &mut band[k * width..(k + 1) * width];
        for x in x_lo..=x_hi.min(width - 1) {
            out[x] = f32::from(r0[x]) * (1.0 - a) + f32::from(r1[x]) * a;
        }
    }
}

pub(crate) fn patch_stats(
    band: &[f32],
    width: usize,
    rows: usize,
    xc: usize,
    r: usize,
) -> Option<(f32, f32)> {
    let n = (rows * (2 * r + 1)) as f32;
    let (mut s, mut s2) = (0.0f32, 0.0f32);
    for k in 0..rows {
        for &v in band.get(k * width + xc - r..=k * width + xc + r)? {
            s += v;
            s2 += v * v;
        }
    }
    let mean = s / n;
    let var = (s2 / n - mean * mean).max(0.0);
    Some((mean, var.sqrt()))
}

#[allow(clippy::too_many_arguments)]
pub(crate) fn zncc(
    a: &[f32],
    xa: usize,
    mean_a: f32,
    std_a: f32,
    b: &[f32],
    xb: usize,
    width: usize,
    rows: usize,
    r: usize,
) -> f32 {
    let n = (rows * (2 * r + 1)) as f32;
    let (mut sb, mut sb2, mut sab) = (0.0f32, 0.0f32, 0.0f32);
    for k in 0..rows {
        let ra = &a[k * width + xa - r..=k * width + xa + r];
        let rb = &b[k * width + xb - r..=k * width + xb + r];
        for (&va, &vb) in ra.iter().zip(rb) {
            sb += vb;
            sb2 += vb * vb;
            sab += (va - mean_a) * vb;
        }
    }
    let mean_b = sb / n;
    let var_b = (sb2 / n - mean_b * mean_b).max(0.0);
    if var_b < 1e-6 || std_a < 1e-6 {
        return -1.0;
    }
    (sab / n) / (std_a * var_b.sqrt())
}

/// Sub-sample offset of the peak of a parabola through `(−1, a), (0, b), (1, c)`, in [−0.5, 0.5].
pub(crate) fn parabola(a: f32, b: f32, c: f32) -> f64 {
    let (a, b, c) = (f64::from(a), f64::from(b), f64::from(c));
    let denom = a - 2.0 * b + c;
    if denom.is_nan() || denom >= -1e-9 || !a.is_finite() || !c.is_finite() {
        return 0.0;
    }
    (0.5 * (a - c) / denom).clamp(-0.5, 0.5)
}
