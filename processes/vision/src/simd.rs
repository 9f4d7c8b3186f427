//! Four `f32` lanes ([`F4`]) for the inner loops of KLT: SSE registers on x86-64 (part of its
//! baseline, so no runtime detection), a plain array elsewhere. Both give bitwise the same
//! results: every operation is lane-wise IEEE single precision, and [`F4::sum`] adds the lanes
//! in one fixed order.
//!
//! The compiler does not vectorize these loops on its own: their float sums cannot be
//! reassociated, and its attempts interleave the x and y sums with more shuffles than
//! arithmetic.
//!
//! ```
//! use hopnav_vision::simd::F4;
//! let a = F4::load(&[1.0, 2.0, 3.0, 4.0, 5.0], 1);
//! let b = a * F4::splat(2.0) - F4::splat(1.0);
//! assert_eq!(b.sum(), (3.0 + 5.0) + (7.0 + 9.0));
//! ```

use std::ops::{Add, Mul, Sub};

/// Lanes of an [`F4`].
pub const LANES: usize = 4;

#[cfg(target_arch = "x86_64")]
mod imp {
    use std::arch::x86_64::{
        __m128, _mm_add_ps, _mm_loadu_ps, _mm_mul_ps, _mm_set1_ps, _mm_storeu_ps, _mm_sub_ps,
    };

    /// Four `f32` in an SSE register.
    #[derive(Debug, Clone, Copy)]
    pub struct F4(__m128);

    impl F4 {
        #[inline(always)]
        pub fn splat(v: f32) -> Self {
            // SAFETY: SSE is part of the x86-64 baseline (every x86-64 CPU has it); the
            // intrinsic only writes a register.
            Self(unsafe { _mm_set1_ps(v) })
        }

        #[inline(always)]
        pub fn load(s: &[f32], offset: usize) -> Self {
            let v = &s[offset..offset + 4];
            // SAFETY: `v` holds exactly 4 initialized `f32` (the indexing above checked the
            // bounds): the 16 bytes `_mm_loadu_ps` reads, with no alignment requirement. SSE is
            // part of the x86-64 baseline.
            Self(unsafe { _mm_loadu_ps(v.as_ptr()) })
        }

        #[inline(always)]
        pub fn store(self, s: &mut [f32], offset: usize) {
            let v = &mut s[offset..offset + 4];
            // SAFETY: `v` is exactly 4 writable `f32` (bounds checked above): the 16 bytes
            // `_mm_storeu_ps` writes, with no alignment requirement. SSE is baseline.
            unsafe { _mm_storeu_ps(v.as_mut_ptr(), self.0) }
        }

        #[inline(always)]
        pub fn add(self, o: Self) -> Self {
            // SAFETY: register-only SSE arithmetic; SSE is part of the x86-64 baseline.
            Self(unsafe { _mm_add_ps(self.0, o.0) })
        }

        #[inline(always)]
        pub fn sub(self, o: Self) -> Self {
            // SAFETY: register-only SSE arithmetic; SSE is part of the x86-64 baseline.
            Self(unsafe { _mm_sub_ps(self.0, o.0) })
        }

        #[inline(always)]
        pub fn mul(self, o: Self) -> Self {
            // SAFETY: register-only SSE arithmetic; SSE is part of the x86-64 baseline.
            Self(unsafe { _mm_mul_ps(self.0, o.0) })
        }

        #[inline(always)]
        pub fn to_array(self) -> [f32; 4] {
            let mut a = [0.0f32; 4];
            self.store(&mut a, 0);
            a
        }
    }
}

#[cfg(not(target_arch = "x86_64"))]
mod imp {
    /// Four `f32` in an array.
    #[derive(Debug, Clone, Copy)]
    pub struct F4([f32; 4]);

    impl F4 {
        #[inline(always)]
        pub fn splat(v: f32) -> Self {
            Self([v; 4])
        }

        #[inline(always)]
        pub fn load(s: &[f32], offset: usize) -> Self {
            let v = &s[offset..offset + 4];
            Self([v[0], v[1], v[2], v[3]])
        }

        #[inline(always)]
        pub fn store(self, s: &mut [f32], offset: usize) {
            s[offset..offset + 4].copy_from_slice(&self.0);
        }

        #[inline(always)]
        pub fn add(self, o: Self) -> Self {
            Self(std::array::from_fn(|l| self.0[l] + o.0[l]))
        }

        #[inline(always)]
        pub fn sub(self, o: Self) -> Self {
            Self(std::array::from_fn(|l| self.0[l] - o.0[l]))
        }

        #[inline(always)]
        pub fn mul(self, o: Self) -> Self {
            Self(std::array::from_fn(|l| self.0[l] * o.0[l]))
        }

        #[inline(always)]
        pub fn to_array(self) -> [f32; 4] {
            self.0
        }
    }
}

/// Four `f32` lanes.
#[derive(Debug, Clone, Copy)]
pub struct F4(imp::F4);

impl F4 {
    /// All lanes zero.
    #[inline(always)]
    pub fn zero() -> Self {
        Self::splat(0.0)
    }

    /// All lanes `v`.
    #[inline(always)]
    pub fn splat(v: f32) -> Self {
        Self(imp::F4::splat(v))
    }

    /// `s[offset..offset + 4]`; panics if `s` is shorter.
    #[inline(always)]
    pub fn load(s: &[f32], offset: usize) -> Self {
        Self(imp::F4::load(s, offset))
    }

    /// Writes the lanes to `s[offset..offset + 4]`; panics if `s` is shorter.
    #[inline(always)]
    pub fn store(self, s: &mut [f32], offset: usize) {
        self.0.store(s, offset);
    }

    /// The lanes as an array.
    #[inline(always)]
    pub fn to_array(self) -> [f32; 4] {
        self.0.to_array()
    }

    /// `(l0 + l1) + (l2 + l3)`.
    #[inline(always)]
    pub fn sum(self) -> f32 {
        let a = self.to_array();
        (a[0] + a[1]) + (a[2] + a[3])
    }
}

impl Add for F4 {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Self(self.0.add(o.0))
    }
}

impl Sub for F4 {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Self(self.0.sub(o.0))
    }
}

impl Mul for F4 {
    type Output = Self;
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        Self(self.0.mul(o.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lane_ops_match_scalar() {
        let a = [1.5f32, -2.25, 3.0, 1e-3, 7.0];
        let b = [0.5f32, 4.0, -1.0, 2.0];
        let x = F4::load(&a, 1);
        let y = F4::load(&b, 0);
        let r = ((x * y) + F4::splat(0.25) - y).to_array();
        for l in 0..4 {
            assert_eq!(r[l], a[l + 1] * b[l] + 0.25 - b[l]);
        }
        let mut out = [0.0f32; 6];
        x.store(&mut out, 2);
        assert_eq!(&out[2..], &a[1..]);
        assert_eq!(F4::zero().sum(), 0.0);
        assert_eq!(y.sum(), (0.5 + 4.0) + (-1.0 + 2.0));
    }

    #[test]
    #[should_panic]
    fn short_load_panics() {
        let _ = F4::load(&[1.0, 2.0, 3.0], 0);
    }
}
