//! Tests of the stereo matcher (`stereo.rs`).
use super::*;

/// Value noise: hashed grid values at a 2.5-px spacing, bilinearly interpolated.
pub(crate) fn texture(x: f64, y: f64) -> f64 {
    let hash = |i: i64, j: i64| {
        let mut z = (i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
            ^ (j as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F);
        z ^= z >> 29;
        z = z.wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z ^= z >> 32;
        (z % 1000) as f64 / 1000.0
    };
    let (gx, gy) = (x / 2.5, y / 2.5);
    let (i, j) = (gx.floor(), gy.floor());
    let (a, b) = (gx - i, gy - j);
    let (i, j) = (i as i64, j as i64);
    let v = hash(i, j) * (1.0 - a) * (1.0 - b)
        + hash(i + 1, j) * a * (1.0 - b)
        + hash(i, j + 1) * (1.0 - a) * b
        + hash(i + 1, j + 1) * a * b;
    40.0 + 170.0 * v
}

/// Intrinsics of the 160 × 60 test views.
fn small_view_params() -> StereoParams {
    StereoParams {
        fx_px: 100.0,
        fy_px: 100.0,
        cx_px: 80.0,
        cy_px: 30.0,
        ..StereoParams::default()
    }
}

#[test]
fn recovers_subpixel_disparity_and_rejects_flat() {
    let (w, h) = (160usize, 60usize);
    for &d in &[3.3f64, 12.75, 40.4] {
        let left: Vec<u8> = (0..w * h)
            .map(|i| texture((i % w) as f64, (i / w) as f64) as u8)
            .collect();
        let right: Vec<u8> = (0..w * h)
            .map(|i| texture((i % w) as f64 + d, (i / w) as f64) as u8)
            .collect();
        let mut m = StereoMatcher::new(w as u32, h as u32, small_view_params()).unwrap();
        let l = ImageView::packed(&left, w, h).unwrap();
        let r = ImageView::packed(&right, w, h).unwrap();
        let p = m.match_point(&l, &r, 120.3, 30.6).unwrap();
        assert!(
            (p.disparity_px - d).abs() < 0.15,
            "d {d} got {}",
            p.disparity_px
        );
        assert!((p.point_camera_m.z - 20.0 / d).abs() < 0.1 * 20.0 / d);
        let flat = vec![100u8; w * h];
        let f = ImageView::packed(&flat, w, h).unwrap();
        assert_eq!(m.match_point(&f, &f, 120.0, 30.0), Err(NoMatch::LowTexture));
        // A right view of unrelated content: no consistent match.
        let other: Vec<u8> = (0..w * h)
            .map(|i| texture((i / w) as f64 * 3.0, (i % w) as f64 * 1.7) as u8)
            .collect();
        let o = ImageView::packed(&other, w, h).unwrap();
        assert!(m.match_point(&l, &o, 120.0, 30.0).is_err());
    }
}

/// A left and right view of a contrasted rock face (left-image columns below 100,
/// disparity 12 px) in front of faintly textured ground (disparity 8 px).
fn rock_edge_pair(w: usize, h: usize) -> (Vec<u8>, Vec<u8>) {
    let rock = |x: f64, y: f64| 250.0 - texture(1.3 * x + 50.0, 0.9 * y + 7.0);
    // Sunlit rock is far more contrasted than the dusty ground around it.
    let ground = |x: f64, y: f64| 100.0 + 0.25 * texture(x, y);
    let left = (0..w * h)
        .map(|i| {
            let (x, y) = ((i % w) as f64, (i / w) as f64);
            (if x < 100.0 { rock(x, y) } else { ground(x, y) }) as u8
        })
        .collect();
    let right = (0..w * h)
        .map(|i| {
            let (x, y) = ((i % w) as f64, (i / w) as f64);
            (if x + 12.0 < 100.0 {
                rock(x + 12.0, y)
            } else {
                ground(x + 8.0, y)
            }) as u8
        })
        .collect();
    (left, right)
}

#[test]
fn a_patch_across_a_rocks_edge_is_refused_and_either_side_alone_matched() {
    let (w, h) = (160usize, 60usize);
    let (left, right) = rock_edge_pair(w, h);
    let l = ImageView::packed(&left, w, h).unwrap();
    let r = ImageView::packed(&right, w, h).unwrap();
    let params = small_view_params();
    let checked = StereoParams {
        max_half_disagreement_px: 1.0,
        ..params
    };
    let mut unchecked = StereoMatcher::new(w as u32, h as u32, params).unwrap();
    let mut matcher = StereoMatcher::new(w as u32, h as u32, checked).unwrap();
    // Ground one to three columns beside the rock: the rock's texture wins the whole patch
    // and the ground is placed at the rock's depth.
    for x_px in [100.0, 101.0, 102.0] {
        let straddling = unchecked.match_point(&l, &r, x_px, 30.0).unwrap();
        assert!(
            straddling.disparity_px > 11.0,
            "x {x_px}: the unchecked match takes the rock's disparity: {}",
            straddling.disparity_px
        );
        assert_eq!(
            matcher.match_point(&l, &r, x_px, 30.0),
            Err(NoMatch::DepthEdge),
            "x {x_px}"
        );
    }
    let ground = matcher.match_point(&l, &r, 130.0, 30.0).unwrap();
    assert!(
        (ground.disparity_px - 8.0).abs() < 0.2,
        "{}",
        ground.disparity_px
    );
    let rock = matcher.match_point(&l, &r, 70.0, 30.0).unwrap();
    assert!(
        (rock.disparity_px - 12.0).abs() < 0.2,
        "{}",
        rock.disparity_px
    );
}

#[test]
fn a_negative_or_infinite_half_disagreement_limit_is_refused() {
    for limit in [-1.0, f64::NAN, f64::INFINITY] {
        let params = StereoParams {
            max_half_disagreement_px: limit,
            ..StereoParams::default()
        };
        assert!(matches!(
            StereoMatcher::new(320, 240, params),
            Err(StereoError::BadParameter {
                name: "max_half_disagreement_px",
                ..
            })
        ));
    }
}
