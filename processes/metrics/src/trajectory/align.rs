//! Umeyama alignment (1991): the similarity or rigid transform that best maps one point set
//! onto another in the least-squares sense.

use nalgebra::{Matrix3, Point3, Rotation3, Vector3};

/// `target ≈ scale · rotation · source + translation`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Similarity {
    /// Rotation.
    pub rotation: Rotation3<f64>,
    /// Translation, metres.
    pub translation: Vector3<f64>,
    /// Scale (1 for SE(3)).
    pub scale: f64,
}

impl Similarity {
    /// Applies the transform to `p`.
    pub fn apply(&self, p: &Point3<f64>) -> Point3<f64> {
        Point3::from(self.rotation * p.coords * self.scale + self.translation)
    }
}

/// Umeyama alignment of `source` onto `target`; `with_scale` selects Sim(3) over SE(3).
/// `None` with fewer than 3 pairs, unequal lengths or degenerate (zero-variance) input.
pub fn umeyama(
    source: &[Point3<f64>],
    target: &[Point3<f64>],
    with_scale: bool,
) -> Option<Similarity> {
    let n = source.len();
    if n < 3 || n != target.len() {
        return None;
    }
    let nf = n as f64;
    let mu_s = source.iter().map(|p| p.coords).sum::<Vector3<f64>>() / nf;
    let mu_t = target.iter().map(|p| p.coords).sum::<Vector3<f64>>() / nf;
    let mut cov = Matrix3::zeros();
    let mut var_s = 0.0;
    for (s, t) in source.iter().zip(target) {
        let (ds, dt) = (s.coords - mu_s, t.coords - mu_t);
        cov += dt * ds.transpose();
        var_s += ds.norm_squared();
    }
    cov /= nf;
    var_s /= nf;
    if var_s.is_nan() || var_s <= 1e-15 || !cov.iter().all(|v| v.is_finite()) {
        return None;
    }
    let svd = cov.try_svd(true, true, 1e-14, 200)?;
    let (u, v_t) = (svd.u?, svd.v_t?);
    let mut d = Matrix3::identity();
    if (u.determinant() * v_t.determinant()) < 0.0 {
        d[(2, 2)] = -1.0;
    }
    let r = u * d * v_t;
    let scale = if with_scale {
        (svd.singular_values.component_mul(&d.diagonal())).sum() / var_s
    } else {
        1.0
    };
    let rotation = Rotation3::from_matrix_unchecked(r);
    let translation = mu_t - rotation * mu_s * scale;
    Some(Similarity {
        rotation,
        translation,
        scale,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recovers_known_similarity() {
        let truth = Similarity {
            rotation: Rotation3::from_euler_angles(0.2, -0.4, 1.1),
            translation: Vector3::new(3.0, -2.0, 0.5),
            scale: 1.7,
        };
        let src: Vec<Point3<f64>> = (0..30)
            .map(|i| {
                let t = i as f64 * 0.1;
                Point3::new(5.0 * t, 0.3 * t.sin(), 8.0 * t - 1.8 * t * t)
            })
            .collect();
        let dst: Vec<Point3<f64>> = src.iter().map(|p| truth.apply(p)).collect();
        let est = umeyama(&src, &dst, true).unwrap();
        assert!((est.scale - 1.7).abs() < 1e-9);
        assert!(est.rotation.angle_to(&truth.rotation) < 1e-9);
        assert!((est.translation - truth.translation).norm() < 1e-9);
        // SE(3) on a rigidly moved copy.
        let rigid: Vec<Point3<f64>> = src
            .iter()
            .map(|p| Point3::from(truth.rotation * p.coords + truth.translation))
            .collect();
        let est = umeyama(&src, &rigid, false).unwrap();
        assert_eq!(est.scale, 1.0);
        assert!((est.translation - truth.translation).norm() < 1e-9);
        assert!(umeyama(&src[..2], &dst[..2], true).is_none());
    }
}
