//! The pixel windows the tracker works on: bounds checks, bilinear sampling of a window (plain,
//! in whole SIMD lanes, or fused with the Gauss–Newton mismatch sums) and the template with its
//! gradients.

use nalgebra::Point2;

use crate::pyramid::PaddedPlane;
use crate::simd::{F4, LANES};

/// Whether the bilinear window of radius `r + 1` around `p` (template plus its gradient
/// margin) stays inside the padded plane.
pub(super) fn window_fits(plane: &PaddedPlane, p: Point2<f32>, r: usize) -> bool {
    let r = r + 1;
    if !(p.x.is_finite() && p.y.is_finite()) {
        return false;
    }
    let pad = plane.pad() as f32;
    let r = r as f32;
    let lo = -pad + r;
    // floor(p) + r + 1 must be < size + pad.
    p.x >= lo
        && p.y >= lo
        && p.x < plane.width() as f32 + pad - r - 2.0
        && p.y < plane.height() as f32 + pad - r - 2.0
}

/// `floor(v)` for `v` inside a padded plane (`v > -FLOOR_OFFSET`), without a libm call (the
/// baseline x86-64 target has no `roundss`).
#[inline]
pub(super) fn fast_floor(v: f32) -> f32 {
    const FLOOR_OFFSET: f32 = 4096.0;
    ((v + FLOOR_OFFSET) as i32) as f32 - FLOOR_OFFSET
}

/// The top-left pixel `(x0, y0)` of the `(2r+1)²` window centred on `p` and the bilinear
/// weights `(w00, w01, w10, w11)` of `p`'s fractional part (`w01` weighs the pixel to the
/// right, `w10` the one below).
#[inline]
fn bilinear_window(p: Point2<f32>, r: usize) -> ((isize, isize), (f32, f32, f32, f32)) {
    let fx = fast_floor(p.x);
    let fy = fast_floor(p.y);
    let (a, b) = (p.x - fx, p.y - fy);
    let weights = ((1.0 - a) * (1.0 - b), a * (1.0 - b), (1.0 - a) * b, a * b);
    (
        (fx as isize - r as isize, fy as isize - r as isize),
        weights,
    )
}

/// Bilinear samples of the `(2r+1)²` window centred on `p` (caller checked [`window_fits`]):
/// the reference of [`sample_window_strided`].
/// The four bilinear weights in every lane.
#[inline]
fn lane_weights((w00, w01, w10, w11): (f32, f32, f32, f32)) -> (F4, F4, F4, F4) {
    (
        F4::splat(w00),
        F4::splat(w01),
        F4::splat(w10),
        F4::splat(w11),
    )
}

/// Row `k` of the window at `origin` and the row below it, `width` pixels each from the
/// window's left edge.
#[inline]
fn source_rows(
    plane: &PaddedPlane,
    (x0, y0): (isize, isize),
    k: usize,
    width: usize,
) -> (&[f32], &[f32]) {
    let data = plane.data();
    let i0 = plane.index(x0, y0 + k as isize);
    let below = i0 + plane.stride();
    (&data[i0..i0 + width], &data[below..below + width])
}

#[cfg(test)]
pub(super) fn sample_window(plane: &PaddedPlane, p: Point2<f32>, r: usize, out: &mut [f32]) {
    sample_window_strided(plane, p, r, 2 * r + 1, out);
}

/// Bilinear samples of the `(2r+1)²` window centred on `p` (caller checked [`window_fits`]),
/// into rows of `stride ≥ 2r+1` elements; the columns past `2r+1`
/// are set to zero.
pub(super) fn sample_window_strided(
    plane: &PaddedPlane,
    p: Point2<f32>,
    r: usize,
    stride: usize,
    out: &mut [f32],
) {
    let n = 2 * r + 1;
    let (origin, (w00, w01, w10, w11)) = bilinear_window(p, r);
    for (k, o_row) in out.chunks_exact_mut(stride).take(n).enumerate() {
        let (row0, row1) = source_rows(plane, origin, k, n + 1);
        let (o_row, o_pad) = o_row.split_at_mut(n);
        for ((((o, &p00), &p01), &p10), &p11) in o_row
            .iter_mut()
            .zip(&row0[..n])
            .zip(&row0[1..])
            .zip(&row1[..n])
            .zip(&row1[1..])
        {
            *o = w00 * p00 + w01 * p01 + w10 * p10 + w11 * p11;
        }
        o_pad.fill(0.0);
    }
}

/// Bilinear samples of the `(2r+1)²` window centred on `p` (caller checked [`window_fits`])
/// into rows of `stride` elements, computed in whole lanes: row `k` gets `2r+1` rounded up to
/// [`LANES`] samples (`stride` must be at least that); those past column `2r+1` are samples of
/// the pixels further right (finite, to be masked by the caller), and any further columns are
/// left as they were.
pub(super) fn sample_window_lanes(
    plane: &PaddedPlane,
    p: Point2<f32>,
    r: usize,
    stride: usize,
    out: &mut [f32],
) {
    let n = 2 * r + 1;
    let cols = n.next_multiple_of(LANES);
    let (origin, weights) = bilinear_window(p, r);
    let (w00, w01, w10, w11) = lane_weights(weights);
    for (k, o_row) in out.chunks_exact_mut(stride).take(n).enumerate() {
        // [`window_fits`] keeps `floor(p) + r + 2` inside the padded row and a row below the
        // window's last, so the `cols + 1 ≤ n + LANES` elements read from the window's left
        // edge stay inside `data` (at worst they run into the next row's left border).
        let (row0, row1) = source_rows(plane, origin, k, cols + 1);
        for c in (0..cols).step_by(LANES) {
            let j = (w00 * F4::load(row0, c) + w01 * F4::load(row0, c + 1))
                + (w10 * F4::load(row1, c) + w11 * F4::load(row1, c + 1));
            j.store(o_row, c);
        }
    }
}

/// `(Σ (I − J) gx, Σ (I − J) gy)` with `J` the bilinear `(2r+1)²` window of `plane` at `p`
/// (caller checked [`window_fits`]): [`sample_window`] and [`mismatch`] in one pass, without
/// writing the window.
///
/// `template`, `gx` and `gy` have rows of `stride` elements (a multiple of [`LANES`], at most
/// `2r+1 + LANES − 1`), zero past column `2r+1`. Whole lanes are computed with one partial sum
/// per lane, which the compiler keeps in SIMD registers; the padding columns read up to
/// `LANES − 1` pixels past the window's right edge (still inside the padded plane: see below),
/// and their zero gradients cancel them.
pub(super) fn sampled_mismatch(
    plane: &PaddedPlane,
    p: Point2<f32>,
    r: usize,
    stride: usize,
    template: &[f32],
    gx: &[f32],
    gy: &[f32],
) -> (f32, f32) {
    let n = 2 * r + 1;
    let (origin, weights) = bilinear_window(p, r);
    let (w00, w01, w10, w11) = lane_weights(weights);
    let (mut sx, mut sy) = (F4::zero(), F4::zero());
    for (k, ((t_row, x_row), y_row)) in template
        .chunks_exact(stride)
        .zip(gx.chunks_exact(stride))
        .zip(gy.chunks_exact(stride))
        .take(n)
        .enumerate()
    {
        // [`window_fits`] keeps `floor(p) + r + 2` inside the padded row and two more rows
        // below the window, so reading `stride + 1 ≤ n + LANES` elements from the window's
        // left edge stays inside `data` (at worst it runs into the next row's left border,
        // whose values the zero padding of the gradients cancels).
        let (row0, row1) = source_rows(plane, origin, k, stride + 1);
        for c in (0..stride).step_by(LANES) {
            let j = (w00 * F4::load(row0, c) + w01 * F4::load(row0, c + 1))
                + (w10 * F4::load(row1, c) + w11 * F4::load(row1, c + 1));
            let diff = F4::load(t_row, c) - j;
            sx = sx + diff * F4::load(x_row, c);
            sy = sy + diff * F4::load(y_row, c);
        }
    }
    (sx.sum(), sy.sum())
}

/// Splits a `(n+2)²` window (rows of `padded_stride = stride + LANES` elements) into the inner
/// `n²` template and its central-difference gradients, in rows of `stride = mask.len()`
/// elements that are zero where `mask` is 0 (past column `n`); returns the structure tensor
/// `(Σ gx², Σ gx gy, Σ gy²)`.
pub(super) fn template_from_padded(
    padded: &[f32],
    padded_stride: usize,
    mask: &[f32],
    template: &mut [f32],
    gx: &mut [f32],
    gy: &mut [f32],
) -> (f32, f32, f32) {
    let stride = mask.len();
    let half = F4::splat(0.5);
    let (mut xx, mut xy, mut yy) = (F4::zero(), F4::zero(), F4::zero());
    for (k, ((t, x), y)) in template
        .chunks_exact_mut(stride)
        .zip(gx.chunks_exact_mut(stride))
        .zip(gy.chunks_exact_mut(stride))
        .enumerate()
    {
        let up = &padded[k * padded_stride..(k + 1) * padded_stride];
        let mid = &padded[(k + 1) * padded_stride..(k + 2) * padded_stride];
        let down = &padded[(k + 2) * padded_stride..(k + 3) * padded_stride];
        for c in (0..stride).step_by(LANES) {
            let m = F4::load(mask, c);
            let tv = m * F4::load(mid, c + 1);
            let xv = m * (half * (F4::load(mid, c + 2) - F4::load(mid, c)));
            let yv = m * (half * (F4::load(down, c + 1) - F4::load(up, c + 1)));
            tv.store(t, c);
            xv.store(x, c);
            yv.store(y, c);
            xx = xx + xv * xv;
            xy = xy + xv * yv;
            yy = yy + yv * yv;
        }
    }
    (xx.sum(), xy.sum(), yy.sum())
}

/// `(Σ (I − J) gx, Σ (I − J) gy)` of a sampled window (the reference of [`sampled_mismatch`]).
#[cfg(test)]
pub(super) fn mismatch(template: &[f32], window: &[f32], gx: &[f32], gy: &[f32]) -> (f32, f32) {
    let (mut sx, mut sy) = ([0.0f32; 8], [0.0f32; 8]);
    let (ct, cw, cx, cy) = (
        template.chunks_exact(8),
        window.chunks_exact(8),
        gx.chunks_exact(8),
        gy.chunks_exact(8),
    );
    let (rt, rw, rx, ry) = (
        ct.remainder(),
        cw.remainder(),
        cx.remainder(),
        cy.remainder(),
    );
    for ((t, w), (x, y)) in ct.zip(cw).zip(cx.zip(cy)) {
        for k in 0..8 {
            let diff = t[k] - w[k];
            sx[k] += diff * x[k];
            sy[k] += diff * y[k];
        }
    }
    let mut s = (sx.iter().sum::<f32>(), sy.iter().sum::<f32>());
    for ((t, w), (x, y)) in rt.iter().zip(rw).zip(rx.iter().zip(ry)) {
        let diff = t - w;
        s.0 += diff * x;
        s.1 += diff * y;
    }
    s
}
