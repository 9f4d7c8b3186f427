//! Tests of the `corners` module.

use super::*;
use crate::pyramid::Pyramid;
use crate::pyramid::test_support::packed_pyramid;
use crate::synthetic::{AffineWarp, BlobTexture};

fn textured_pyramid(w: usize, h: usize, blobs: usize, seed: u64) -> Pyramid {
    let mut pixels = vec![0u8; w * h];
    BlobTexture::random(w, h, blobs, seed).render(w, h, &AffineWarp::identity(), &mut pixels);
    packed_pyramid(&pixels, w, h)
}

/// The pyramid of a `size × size` texture of `blobs` random blobs and a detector of `config`
/// for it.
fn textured_detector(
    size: usize,
    blobs: usize,
    seed: u64,
    config: CornerConfig,
) -> (Pyramid, CornerDetector) {
    let pyr = textured_pyramid(size, size, blobs, seed);
    (pyr, CornerDetector::new(size, size, config).unwrap())
}

/// Up to `max_features` corners at least `min_distance_px` apart over a `grid × grid`
/// bucketing.
fn square_grid_config(max_features: usize, grid: usize, min_distance_px: f32) -> CornerConfig {
    CornerConfig {
        max_features,
        grid_cols: grid,
        grid_rows: grid,
        min_distance_px,
        ..CornerConfig::default()
    }
}

#[test]
fn respects_cap_bucketing_and_min_distance() {
    let w = 160;
    let (pyr, mut det) = textured_detector(w, 900, 11, square_grid_config(120, 4, 5.0));
    let mut out = Vec::new();
    let n = det.detect(pyr.level(0).unwrap(), &[], &mut out).unwrap();
    assert_eq!(n, out.len());
    assert_eq!(n, 120, "dense texture should fill the cap");
    let cap = det.per_cell_cap();
    assert_eq!(cap, 8);
    let mut counts = [0usize; 16];
    for c in &out {
        counts[det.cell_of(c.position_px)] += 1;
        assert!(c.position_px.x >= 7.5 && c.position_px.x <= (w - 8) as f32 + 0.5);
    }
    assert!(counts.iter().all(|&k| k <= cap), "{counts:?}");
    for (i, a) in out.iter().enumerate() {
        for b in &out[i + 1..] {
            assert!((a.position_px - b.position_px).norm() >= 5.0);
        }
    }
    // Strongest first.
    assert!(out.windows(2).all(|p| p[0].response >= p[1].response));
}

#[test]
fn keeps_away_from_existing_tracks_and_counts_them() {
    let (pyr, mut det) = textured_detector(128, 600, 5, square_grid_config(60, 2, 8.0));
    let mut first = Vec::new();
    det.detect(pyr.level(0).unwrap(), &[], &mut first).unwrap();
    let existing: Vec<_> = first.iter().take(25).map(|c| c.position_px).collect();
    let mut second = Vec::new();
    let n = det
        .detect(pyr.level(0).unwrap(), &existing, &mut second)
        .unwrap();
    assert!(n <= 60 - 25);
    for c in &second {
        for e in &existing {
            assert!((c.position_px - e).norm() >= 8.0);
        }
    }
    // At the cap nothing new is added.
    let full: Vec<_> = (0..60).map(|i| Point2::new(i as f32, 0.0)).collect();
    assert_eq!(
        det.detect(pyr.level(0).unwrap(), &full, &mut second)
            .unwrap(),
        0
    );
}

#[test]
fn leftover_budget_goes_to_strong_corners() {
    let (w, h) = (160, 160);
    // Texture only in the left half: right-half cells stay empty.
    let mut pixels = vec![0u8; w * h];
    BlobTexture::random(w, h, 900, 11).render(w, h, &AffineWarp::identity(), &mut pixels);
    for row in pixels.chunks_exact_mut(w) {
        row[w / 2..].fill(128);
    }
    let pyr = packed_pyramid(&pixels, w, h);
    let base = square_grid_config(100, 4, 4.0);
    let mut strict = Vec::new();
    CornerDetector::new(w, h, base)
        .unwrap()
        .detect(pyr.level(0).unwrap(), &[], &mut strict)
        .unwrap();
    let mut filled = Vec::new();
    let fill = CornerConfig {
        fill_leftover_budget: true,
        ..base
    };
    CornerDetector::new(w, h, fill)
        .unwrap()
        .detect(pyr.level(0).unwrap(), &[], &mut filled)
        .unwrap();
    assert!(strict.len() <= 8 * 7 + 4, "{}", strict.len());
    assert_eq!(filled.len(), 100);
    for (i, a) in filled.iter().enumerate() {
        for b in &filled[i + 1..] {
            assert!((a.position_px - b.position_px).norm() >= 4.0);
        }
    }
}

#[test]
fn flat_image_has_no_corners() {
    let pixels = vec![90u8; 64 * 64];
    let pyr = packed_pyramid(&pixels, 64, 64);
    let mut det = CornerDetector::new(64, 64, CornerConfig::default()).unwrap();
    let mut out = Vec::new();
    assert_eq!(det.detect(pyr.level(0).unwrap(), &[], &mut out).unwrap(), 0);
    assert!(
        CornerDetector::new(
            64,
            64,
            CornerConfig {
                grid_cols: 0,
                ..CornerConfig::default()
            }
        )
        .is_err()
    );
}
