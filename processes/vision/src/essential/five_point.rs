//! Nistér's five-point relative-pose solver, in Stewénius' Gröbner-basis formulation.
//!
//! 1. The five epipolar constraints `x2ᵀ E x1 = 0` leave a 4-dimensional null space:
//!    `E = x·X + y·Y + z·Z + W` (basis from the SVD of the 5×9 system).
//! 2. The essential-matrix constraints `det E = 0` and `2 E Eᵀ E − tr(E Eᵀ) E = 0` give ten cubic
//!    equations in `(x, y, z)`, i.e. a 10×20 coefficient matrix over the monomials of degree ≤ 3.
//! 3. Eliminating the ten cubic monomials (`C⁻¹ D`, with `C` the cubic block) expresses each as a
//!    combination of the ten monomials of degree ≤ 2. Multiplying that basis
//!    `[x², xy, y², xz, yz, z², x, y, z, 1]` by `x` then lands back in the span, giving a 10×10
//!    action matrix whose eigenvectors are the basis evaluated at the (up to ten) solutions.
//! 4. Real eigenvalues (Schur decomposition) → eigenvectors by inverse iteration → `(x, y, z)`
//!    → `E`.
//!
//! ```
//! use hopnav_vision::essential::{essential_from_pose, five_point::essential_five_point};
//! use nalgebra::{Isometry3, Point3, Vector2, Vector3};
//! let pose = Isometry3::new(Vector3::new(0.5, 0.1, 0.2), Vector3::new(0.02, 0.1, -0.03));
//! let pts = [Point3::new(0.1, 0.2, 4.0), Point3::new(-1.0, 0.5, 6.0), Point3::new(0.8, -0.7, 5.0),
//!            Point3::new(-0.3, -0.9, 7.0), Point3::new(1.2, 1.1, 8.0)];
//! let x1: Vec<_> = pts.iter().map(|p| Vector2::new(p.x / p.z, p.y / p.z)).collect();
//! let x2: Vec<_> = pts.iter().map(|p| { let q = pose * p; Vector2::new(q.x / q.z, q.y / q.z) }).collect();
//! let mut solutions = Vec::new();
//! essential_five_point(&x1, &x2, &[0, 1, 2, 3, 4], &mut solutions);
//! let truth = essential_from_pose(&pose).normalize();
//! assert!(solutions.iter().any(|e| (e - truth).norm().min((e + truth).norm()) < 1e-6));
//! ```

use nalgebra::{Matrix3, SMatrix, SVector, Vector2};

type Mat10 = SMatrix<f64, 10, 10>;

/// Exponents `(x, y, z)` of every monomial of degree ≤ `max_degree`, highest degree first and,
/// within a degree, `z` then `y` rising (`x²`, `xy`, `y²`, `xz`, `yz`, `z²` for degree 2). `N` must
/// be the number of such monomials, `(d + 1)(d + 2)(d + 3) / 6`.
const fn monomials<const N: usize>(max_degree: u8) -> [[u8; 3]; N] {
    let mut table = [[0; 3]; N];
    let mut k = 0;
    let mut degree = max_degree as i32;
    while degree >= 0 {
        let d = degree as u8;
        let mut z = 0;
        while z <= d {
            let mut y = 0;
            while y <= d - z {
                table[k] = [d - z - y, y, z];
                k += 1;
                y += 1;
            }
            z += 1;
        }
        degree -= 1;
    }
    assert!(
        k == N,
        "N is not the number of monomials of degree <= max_degree"
    );
    table
}

/// The linear monomials `[x, y, z, 1]`.
const LIN: [[u8; 3]; 4] = monomials(1);
/// Monomials of degree ≤ 2: `[x², xy, y², xz, yz, z², x, y, z, 1]` (also the quotient basis).
const QUAD: [[u8; 3]; 10] = monomials(2);
/// Monomials of degree ≤ 3: the ten cubics `[x³, x²y, xy², y³, x²z, xyz, y²z, xz², yz², z³]`
/// followed by [`QUAD`].
const CUB: [[u8; 3]; 20] = monomials(3);

const fn find<const N: usize>(table: &[[u8; 3]; N], e: [u8; 3]) -> usize {
    let mut i = 0;
    while i < N {
        if table[i][0] == e[0] && table[i][1] == e[1] && table[i][2] == e[2] {
            return i;
        }
        i += 1;
    }
    usize::MAX
}

const fn add(a: [u8; 3], b: [u8; 3]) -> [u8; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// `left[i] · LIN[j]` as an index into `product_basis`.
const fn times_lin_indices<const L: usize, const P: usize>(
    left: &[[u8; 3]; L],
    product_basis: &[[u8; 3]; P],
) -> [[usize; 4]; L] {
    let mut t = [[0; 4]; L];
    let mut i = 0;
    while i < L {
        let mut j = 0;
        while j < 4 {
            t[i][j] = find(product_basis, add(left[i], LIN[j]));
            j += 1;
        }
        i += 1;
    }
    t
}

/// `LIN[i] · LIN[j]` as an index into [`QUAD`].
const LIN_LIN: [[usize; 4]; 4] = times_lin_indices(&LIN, &QUAD);
/// `QUAD[i] · LIN[j]` as an index into [`CUB`].
const QUAD_LIN: [[usize; 4]; 10] = times_lin_indices(&QUAD, &CUB);

type Lin = [f64; 4];
type Quad = [f64; 10];
type Cub = [f64; 20];

/// The product of the polynomial `a` and the linear polynomial `b`; `indices` is
/// [`times_lin_indices`] of `a`'s basis into the product's.
fn times_lin<const L: usize, const P: usize>(
    a: &[f64; L],
    b: &Lin,
    indices: &[[usize; 4]; L],
) -> [f64; P] {
    let mut out = [0.0; P];
    for i in 0..L {
        for j in 0..4 {
            out[indices[i][j]] += a[i] * b[j];
        }
    }
    out
}

fn lin_mul(a: &Lin, b: &Lin) -> Quad {
    times_lin(a, b, &LIN_LIN)
}

fn quad_mul(a: &Quad, b: &Lin) -> Cub {
    times_lin(a, b, &QUAD_LIN)
}

fn quad_add(a: &mut Quad, b: &Quad) {
    a.iter_mut().zip(b).for_each(|(x, y)| *x += y);
}

fn cub_axpy(a: &mut Cub, s: f64, b: &Cub) {
    a.iter_mut().zip(b).for_each(|(x, y)| *x += s * y);
}

/// Solves the five-point problem for the correspondences `indices` (the first five are used).
///
/// Clears `solutions` and pushes every real solution (at most 10), each with unit Frobenius
/// norm. Degenerate or invalid input yields no solution; it never panics.
pub fn essential_five_point(
    x1: &[Vector2<f64>],
    x2: &[Vector2<f64>],
    indices: &[usize],
    solutions: &mut Vec<Matrix3<f64>>,
) {
    solutions.clear();
    let Some(basis) = null_space_basis(x1, x2, indices) else {
        return;
    };
    let Some(action) = action_matrix(&basis) else {
        return;
    };
    let Some(schur) = action.try_schur(1e-14, 1000) else {
        return;
    };
    let eigenvalues = schur.complex_eigenvalues();
    for lambda in eigenvalues.iter() {
        if lambda.im.abs() > 1e-8 * (1.0 + lambda.re.abs()) {
            continue;
        }
        let Some(v) = eigenvector(&action, lambda.re) else {
            continue;
        };
        // v = [x², xy, y², xz, yz, z², x, y, z, 1] up to scale.
        if v[9].abs() < 1e-12 * v.norm() {
            continue;
        }
        let (x, y, z) = (v[6] / v[9], v[7] / v[9], v[8] / v[9]);
        let e_vec = basis[0] * x + basis[1] * y + basis[2] * z + basis[3];
        let norm = e_vec.norm();
        if !(norm.is_finite() && norm > 0.0) {
            continue;
        }
        let e = Matrix3::from_row_slice(e_vec.as_slice()) / norm;
        if solutions.len() < 10 {
            solutions.push(e);
        }
    }
}

/// `[X, Y, Z, W]`: the right null space of the 5×9 epipolar system (row-major `E` entries).
fn null_space_basis(
    x1: &[Vector2<f64>],
    x2: &[Vector2<f64>],
    indices: &[usize],
) -> Option<[SVector<f64, 9>; 4]> {
    if indices.len() < 5 {
        return None;
    }
    let mut q = SMatrix::<f64, 9, 9>::zeros();
    for (r, &i) in indices.iter().take(5).enumerate() {
        let (a, b) = (x1.get(i)?, x2.get(i)?);
        let row = super::epipolar_row([a.x, a.y], [b.x, b.y]);
        for (c, v) in row.iter().enumerate() {
            q[(r, c)] = *v;
        }
    }
    if !q.iter().all(|v| v.is_finite()) {
        return None;
    }
    let svd = q.try_svd(false, true, 1e-15, 500)?;
    let v_t = svd.v_t?;
    let s = svd.singular_values;
    // Rank 5 expected: a smaller rank means a degenerate sample.
    if s[4] <= 1e-10 * s[0] {
        return None;
    }
    Some([
        v_t.row(5).transpose(),
        v_t.row(6).transpose(),
        v_t.row(7).transpose(),
        v_t.row(8).transpose(),
    ])
}

/// The action matrix of multiplication by `x` on the basis [`QUAD`].
fn action_matrix(basis: &[SVector<f64, 9>; 4]) -> Option<Mat10> {
    // E entries as linear polynomials in (x, y, z, 1).
    let mut e: [[Lin; 3]; 3] = [[[0.0; 4]; 3]; 3];
    for (r, row) in e.iter_mut().enumerate() {
        for (c, entry) in row.iter_mut().enumerate() {
            let k = 3 * r + c;
            *entry = [basis[0][k], basis[1][k], basis[2][k], basis[3][k]];
        }
    }
    // E Eᵀ (quadratic) and its trace.
    let mut eet: [[Quad; 3]; 3] = [[[0.0; 10]; 3]; 3];
    for (i, row) in eet.iter_mut().enumerate() {
        for (j, entry) in row.iter_mut().enumerate() {
            for (a, b) in e[i].iter().zip(&e[j]) {
                quad_add(entry, &lin_mul(a, b));
            }
        }
    }
    let mut trace = [0.0; 10];
    for (i, row) in eet.iter().enumerate() {
        quad_add(&mut trace, &row[i]);
    }
    let mut rows: [Cub; 10] = [[0.0; 20]; 10];
    // 2 E Eᵀ E − tr(E Eᵀ) E = 0 (nine equations).
    for i in 0..3 {
        for j in 0..3 {
            let out = &mut rows[3 * i + j];
            for k in 0..3 {
                cub_axpy(out, 2.0, &quad_mul(&eet[i][k], &e[k][j]));
            }
            cub_axpy(out, -1.0, &quad_mul(&trace, &e[i][j]));
        }
    }
    // det E = 0.
    let minor = |a: usize, b: usize, c: usize, d: usize| {
        // e[1][a] e[2][b] − e[1][c] e[2][d]
        let mut m = lin_mul(&e[1][a], &e[2][b]);
        let n = lin_mul(&e[1][c], &e[2][d]);
        m.iter_mut().zip(&n).for_each(|(x, y)| *x -= y);
        m
    };
    let det = &mut rows[9];
    cub_axpy(det, 1.0, &quad_mul(&minor(1, 2, 2, 1), &e[0][0]));
    cub_axpy(det, -1.0, &quad_mul(&minor(0, 2, 2, 0), &e[0][1]));
    cub_axpy(det, 1.0, &quad_mul(&minor(0, 1, 1, 0), &e[0][2]));

    let mut cubic_block = Mat10::zeros();
    let mut rest_block = Mat10::zeros();
    for (r, row) in rows.iter().enumerate() {
        // Scale each equation to unit norm for conditioning.
        let norm = row.iter().map(|v| v * v).sum::<f64>().sqrt();
        if !(norm.is_finite() && norm > 0.0) {
            return None;
        }
        for c in 0..10 {
            cubic_block[(r, c)] = row[c] / norm;
            rest_block[(r, c)] = row[c + 10] / norm;
        }
    }
    // cubic monomials = −G · basis.
    let g = cubic_block.full_piv_lu().solve(&rest_block)?;
    if !g.iter().all(|v| v.is_finite()) {
        return None;
    }
    let mut action = Mat10::zeros();
    for r in 0..10 {
        let product = QUAD_LIN[r][0]; // x · QUAD[r]
        if product < 10 {
            for c in 0..10 {
                action[(r, c)] = -g[(product, c)];
            }
        } else {
            action[(r, product - 10)] = 1.0;
        }
    }
    Some(action)
}

/// Eigenvector of `a` for the real eigenvalue `lambda`, by two steps of inverse iteration.
fn eigenvector(a: &Mat10, lambda: f64) -> Option<SVector<f64, 10>> {
    let shift = lambda + 1e-10 * (1.0 + lambda.abs());
    let lu = (a - Mat10::identity() * shift).full_piv_lu();
    let mut v = SVector::<f64, 10>::from_element(1.0);
    for _ in 0..2 {
        let w = lu.solve(&v)?;
        let n = w.norm();
        if !(n.is_finite() && n > 0.0) {
            return None;
        }
        v = w / n;
    }
    Some(v)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::essential::{essential_from_pose, sampson_error_sq};
    use crate::rng::XorShiftRng;
    use nalgebra::Isometry3;

    #[test]
    fn monomial_tables_are_complete() {
        assert!(LIN_LIN.iter().flatten().all(|&i| i < 10));
        assert!(QUAD_LIN.iter().flatten().all(|&i| i < 20));
    }

    #[test]
    fn monomial_tables_list_the_documented_order() {
        assert_eq!(LIN, [[1, 0, 0], [0, 1, 0], [0, 0, 1], [0, 0, 0]]);
        assert_eq!(QUAD[6..], LIN);
        assert_eq!(CUB[10..], QUAD);
        // Highest degree first; within a degree, z then y rising.
        let order = |e: &[u8; 3]| (u8::MAX - (e[0] + e[1] + e[2]), e[2], e[1]);
        assert!(CUB.windows(2).all(|w| order(&w[0]) < order(&w[1])));
        assert!(QUAD[..6].windows(2).all(|w| order(&w[0]) < order(&w[1])));
    }

    #[test]
    fn recovers_random_poses_exactly() {
        let mut rng = XorShiftRng::new(42);
        let mut found = 0;
        let trials = 50;
        for trial in 0..trials {
            let pose = Isometry3::new(
                rng.uniform_vector3(-1.0, 1.0),
                rng.uniform_vector3(-0.3, 0.3),
            );
            let pts = crate::synthetic::random_points_in_box(5, 2.0, 4.0, 10.0, trial);
            let (x1, x2) = crate::synthetic::exact_views(&pose, &pts);
            let mut sols = Vec::new();
            essential_five_point(&x1, &x2, &[0, 1, 2, 3, 4], &mut sols);
            assert!(sols.len() <= 10);
            for e in &sols {
                for i in 0..5 {
                    assert!(sampson_error_sq(e, &x1[i], &x2[i]) < 1e-14);
                }
            }
            let truth = essential_from_pose(&pose).normalize();
            if sols
                .iter()
                .any(|e| (e - truth).norm().min((e + truth).norm()) < 1e-6)
            {
                found += 1;
            }
        }
        assert!(found >= trials - 1, "found {found}/{trials}");
    }

    #[test]
    fn degenerate_input_gives_no_solution() {
        let x = vec![Vector2::new(0.1, 0.1); 5];
        let mut sols = vec![Matrix3::identity()];
        essential_five_point(&x, &x, &[0, 1, 2, 3, 4], &mut sols);
        assert!(sols.is_empty());
        essential_five_point(&x, &x, &[0, 1, 2], &mut sols);
        assert!(sols.is_empty());
        let nan = vec![Vector2::new(f64::NAN, 0.0); 5];
        essential_five_point(&nan, &x, &[0, 1, 2, 3, 4], &mut sols);
        assert!(sols.is_empty());
        essential_five_point(&x, &x, &[0, 1, 2, 3, 40], &mut sols);
        assert!(sols.is_empty());
    }
}
