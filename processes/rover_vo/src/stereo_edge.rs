//! The depth-edge check of the stereo matcher (`stereo.rs`): a patch that straddles a rock's
//! silhouette holds two depths, and its match lands between them, pulled toward the nearer
//! surface's stronger texture. Ground just behind a rock is then placed a few per cent nearer
//! than it is, which on a downward-looking ray reads as a point standing beside the rock at
//! rock height (measured: 22 % of the rover's tall cloud points were such ground, their depth
//! 4.7 % short at the median; `examples/rover_cloud_vs_zbuffer.rs` in hopnav-eval).
//!
//! The check matches the halves of the patch on their own (left and right columns, top and
//! bottom rows, each sharing the centre line) near the whole patch's disparity: on one surface
//! they agree, across a depth edge they part by the depth step's disparity.

use crate::stereo_patch::parabola;

/// Disparities either side of the whole patch's searched for each half, pixels.
const HALF_SEARCH_PX: isize = 3;

/// One half of the patch: its rows and columns, offsets from the feature's row band and
/// column.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PatchPart {
    /// First and last band row.
    pub rows: (usize, usize),
    /// First and last column, relative to the feature's column.
    pub cols: (isize, isize),
}

impl PatchPart {
    /// The four halves of a patch of half size `r`: left, right, top, bottom.
    pub(crate) fn halves(r: usize) -> [PatchPart; 4] {
        let (ri, side) = (r as isize, 2 * r);
        let all_rows = (0, side);
        let all_cols = (-ri, ri);
        [
            PatchPart {
                rows: all_rows,
                cols: (-ri, 0),
            },
            PatchPart {
                rows: all_rows,
                cols: (0, ri),
            },
            PatchPart {
                rows: (0, r),
                cols: all_cols,
            },
            PatchPart {
                rows: (r, side),
                cols: all_cols,
            },
        ]
    }
}

/// The views' rows around a feature, interpolated at its sub-pixel height (`width` per row).
pub(crate) struct Bands<'a> {
    pub left: &'a [f32],
    pub right: &'a [f32],
    pub width: usize,
}

impl Bands<'_> {
    /// ZNCC of `part` of the left patch at column `xl` against the right view at `xl − d`
    /// (`None` when a side is flat or out of the band).
    fn score(&self, part: PatchPart, xl: isize, d: isize) -> Option<f32> {
        let (mut sa, mut sa2, mut sb, mut sb2, mut sab, mut n) = (0.0f32, 0.0, 0.0, 0.0, 0.0, 0.0);
        for k in part.rows.0..=part.rows.1 {
            for c in part.cols.0..=part.cols.1 {
                let xa = usize::try_from(xl + c).ok()?;
                let xb = usize::try_from(xl - d + c).ok()?;
                let a = *self.left.get(k * self.width + xa)?;
                let b = *self.right.get(k * self.width + xb)?;
                sa += a;
                sa2 += a * a;
                sb += b;
                sb2 += b * b;
                sab += a * b;
                n += 1.0;
            }
        }
        let covariance = sab / n - (sa / n) * (sb / n);
        let var_a = sa2 / n - (sa / n).powi(2);
        let var_b = sb2 / n - (sb / n).powi(2);
        (var_a > 1e-3 && var_b > 1e-3).then(|| covariance / (var_a * var_b).sqrt())
    }

    /// The sub-pixel disparity at which `part` matches best within [`HALF_SEARCH_PX`] of
    /// `disparity`, kept inside `d_range` (at an end of the search, that end; `None` when it
    /// has no texture to match).
    fn part_disparity(
        &self,
        part: PatchPart,
        xl: isize,
        disparity: f64,
        d_range: (isize, isize),
    ) -> Option<f64> {
        let centre = disparity.round() as isize;
        let lo = (centre - HALF_SEARCH_PX).max(d_range.0);
        let hi = (centre + HALF_SEARCH_PX).min(d_range.1);
        // Each candidate's score, kept for the parabola around the best.
        let mut scores = [0.0f32; 2 * HALF_SEARCH_PX as usize + 1];
        let mut best: Option<(f32, isize)> = None;
        for d in lo..=hi {
            let score = self.score(part, xl, d)?;
            scores[(d - lo) as usize] = score;
            if best.is_none_or(|(best_score, _)| score > best_score) {
                best = Some((score, d));
            }
        }
        let (score, d) = best?;
        if d <= lo || d >= hi {
            // The half matches best at least this far from the whole: no parabola needed.
            return Some(d as f64);
        }
        let at = (d - lo) as usize;
        Some(d as f64 + parabola(scores[at - 1], score, scores[at + 1]))
    }

    /// The larger of the disparity gaps between the left and right halves and between the top
    /// and bottom halves of the patch of half size `r` at `xl` (0 where a pair cannot be
    /// compared).
    pub(crate) fn half_disagreement_px(
        &self,
        r: usize,
        xl: isize,
        disparity: f64,
        d_range: (isize, isize),
    ) -> f64 {
        let [left, right, top, bottom] =
            PatchPart::halves(r).map(|part| self.part_disparity(part, xl, disparity, d_range));
        let gap = |a: Option<f64>, b: Option<f64>| match (a, b) {
            (Some(a), Some(b)) => (a - b).abs(),
            _ => 0.0,
        };
        gap(left, right).max(gap(top, bottom))
    }
}
