//! Lanes: the arithmetic the collision law is written in, for one pair at a time (`f64`),
//! two at once ([`F64x2`]) or four ([`F64x4`]).
//!
//! A pair's resolution is one long chain of dependent operations (a square root, then
//! divisions by its result, then by the sum of the masses), longer than the processor can
//! look ahead, so resolving pairs one after another waits on that chain and nothing else.
//! Two independent pairs in the two lanes of one set of instructions share the wait. Every
//! lane does exactly the scalar operations in the scalar order (`+ - * /` and `sqrt` are
//! correctly rounded, and comparisons and selections move bits unchanged), so a pair gives
//! the same bits in either form: the law is written once, generic over [`Lanes`].

use std::ops::{Add, Div, Mul, Neg, Sub};

/// Numbers the collision law computes with: `f64`, or several `f64` lanes at once.
pub trait Lanes:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// How many lanes.
    const LANES: usize;
    /// Per-lane truth values.
    type Mask: Copy;
    /// Every lane `v`.
    fn splat(v: f64) -> Self;
    /// The correctly rounded square root of each lane.
    fn sqrt(self) -> Self;
    /// `self > other` per lane (false where either is NaN).
    fn gt(self, other: Self) -> Self::Mask;
    /// `self < other` per lane (false where either is NaN).
    fn lt(self, other: Self) -> Self::Mask;
    /// `a` where `mask` holds, else `b`, per lane (bits unchanged).
    fn select(mask: Self::Mask, a: Self, b: Self) -> Self;
    /// `self` where `self < other`, else `other` (so `other` where either is NaN, and
    /// `other` of two zeros), per lane: `select(self.lt(other), self, other)` in one
    /// instruction (SSE2's `minpd` is exactly this).
    fn min_else(self, other: Self) -> Self;
    /// `self` where `self > other`, else `other`, per lane (SSE2's `maxpd`).
    fn max_else(self, other: Self) -> Self;
    /// Lane `k` set to `f(k)`.
    fn gather(f: impl FnMut(usize) -> f64) -> Self;
    /// `f(k, lane k)` for each lane, in order.
    fn each(self, f: impl FnMut(usize, f64));
}

impl Lanes for f64 {
    const LANES: usize = 1;
    type Mask = bool;
    #[inline(always)]
    fn splat(v: f64) -> Self {
        v
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
    #[inline(always)]
    fn gt(self, other: Self) -> bool {
        self > other
    }
    #[inline(always)]
    fn lt(self, other: Self) -> bool {
        self < other
    }
    #[inline(always)]
    fn select(mask: bool, a: Self, b: Self) -> Self {
        if mask { a } else { b }
    }
    #[inline(always)]
    fn min_else(self, other: Self) -> Self {
        if self < other { self } else { other }
    }
    #[inline(always)]
    fn max_else(self, other: Self) -> Self {
        if self > other { self } else { other }
    }
    #[inline(always)]
    fn gather(mut f: impl FnMut(usize) -> f64) -> Self {
        f(0)
    }
    #[inline(always)]
    fn each(self, mut f: impl FnMut(usize, f64)) {
        f(0, self)
    }
}

pub use imp::F64x2;

/// Four `f64` lanes: two [`F64x2`] side by side. Four pairs read their discs before any of
/// them writes back, so the processor sees two independent chains at once (two pairs of
/// lanes resolved one after the other in the program would make the second pair's loads wait
/// behind the first pair's stores, which the processor cannot tell apart from its own).
#[derive(Clone, Copy, Debug)]
pub struct F64x4([F64x2; 2]);

/// Four lane masks.
#[derive(Clone, Copy, Debug)]
pub struct Mask4([<F64x2 as Lanes>::Mask; 2]);

impl F64x4 {
    /// The four lanes.
    #[cfg(test)]
    #[inline(always)]
    pub fn lanes(self) -> [f64; 4] {
        let ([a, b], [c, d]) = (self.0[0].lanes(), self.0[1].lanes());
        [a, b, c, d]
    }
}

macro_rules! op4 {
    ($trait:ident, $method:ident) => {
        impl $trait for F64x4 {
            type Output = F64x4;
            #[inline(always)]
            fn $method(self, other: F64x4) -> F64x4 {
                F64x4([
                    $trait::$method(self.0[0], other.0[0]),
                    $trait::$method(self.0[1], other.0[1]),
                ])
            }
        }
    };
}
op4!(Add, add);
op4!(Sub, sub);
op4!(Mul, mul);
op4!(Div, div);

impl Neg for F64x4 {
    type Output = F64x4;
    #[inline(always)]
    fn neg(self) -> F64x4 {
        F64x4([-self.0[0], -self.0[1]])
    }
}

impl Lanes for F64x4 {
    const LANES: usize = 4;
    type Mask = Mask4;
    #[inline(always)]
    fn splat(v: f64) -> Self {
        F64x4([F64x2::splat(v); 2])
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        F64x4([self.0[0].sqrt(), self.0[1].sqrt()])
    }
    #[inline(always)]
    fn gt(self, other: Self) -> Mask4 {
        Mask4([self.0[0].gt(other.0[0]), self.0[1].gt(other.0[1])])
    }
    #[inline(always)]
    fn lt(self, other: Self) -> Mask4 {
        Mask4([self.0[0].lt(other.0[0]), self.0[1].lt(other.0[1])])
    }
    #[inline(always)]
    fn select(mask: Mask4, a: Self, b: Self) -> Self {
        F64x4([
            F64x2::select(mask.0[0], a.0[0], b.0[0]),
            F64x2::select(mask.0[1], a.0[1], b.0[1]),
        ])
    }
    #[inline(always)]
    fn min_else(self, other: Self) -> Self {
        F64x4([
            self.0[0].min_else(other.0[0]),
            self.0[1].min_else(other.0[1]),
        ])
    }
    #[inline(always)]
    fn max_else(self, other: Self) -> Self {
        F64x4([
            self.0[0].max_else(other.0[0]),
            self.0[1].max_else(other.0[1]),
        ])
    }
    #[inline(always)]
    fn gather(mut f: impl FnMut(usize) -> f64) -> Self {
        let low = F64x2::gather(&mut f);
        F64x4([low, F64x2::gather(|k| f(k + 2))])
    }
    #[inline(always)]
    fn each(self, mut f: impl FnMut(usize, f64)) {
        self.0[0].each(&mut f);
        self.0[1].each(|k, v| f(k + 2, v));
    }
}

#[cfg(target_arch = "x86_64")]
mod imp {
    //! SSE2, which every x86-64 processor has.
    use super::Lanes;
    use std::arch::x86_64::*;
    use std::ops::{Add, BitOr, Div, Mul, Neg, Sub};

    /// Two `f64` lanes.
    #[derive(Clone, Copy, Debug)]
    pub struct F64x2(__m128d);

    /// Two lane masks (all bits set where true).
    #[derive(Clone, Copy, Debug)]
    pub struct Mask2(__m128d);

    impl F64x2 {
        /// Lanes `[a, b]`.
        #[inline(always)]
        pub fn new(a: f64, b: f64) -> Self {
            // SAFETY: SSE2 is part of x86-64.
            F64x2(unsafe { _mm_set_pd(b, a) })
        }

        /// The two lanes.
        #[inline(always)]
        pub fn lanes(self) -> [f64; 2] {
            let mut out = [0.0; 2];
            // SAFETY: SSE2; `out` holds two f64.
            unsafe { _mm_storeu_pd(out.as_mut_ptr(), self.0) };
            out
        }
    }

    impl F64x2 {
        /// `self >= other` per lane (false where either is NaN).
        #[inline(always)]
        pub fn ge(self, other: Self) -> Mask2 {
            // SAFETY: SSE2 (ordered: false with NaN).
            Mask2(unsafe { _mm_cmpge_pd(self.0, other.0) })
        }
    }

    impl Mask2 {
        /// Both lanes' truth values.
        #[inline(always)]
        pub fn lanes(self) -> [bool; 2] {
            // SAFETY: SSE2.
            let bits = unsafe { _mm_movemask_pd(self.0) };
            [bits & 1 != 0, bits & 2 != 0]
        }

        /// Whether either lane holds.
        #[inline(always)]
        pub fn any(self) -> bool {
            // SAFETY: SSE2.
            unsafe { _mm_movemask_pd(self.0) != 0 }
        }
    }

    impl BitOr for Mask2 {
        type Output = Mask2;
        #[inline(always)]
        fn bitor(self, other: Mask2) -> Mask2 {
            // SAFETY: SSE2.
            Mask2(unsafe { _mm_or_pd(self.0, other.0) })
        }
    }

    macro_rules! op {
        ($trait:ident, $method:ident, $intrinsic:ident) => {
            impl $trait for F64x2 {
                type Output = F64x2;
                #[inline(always)]
                fn $method(self, other: F64x2) -> F64x2 {
                    // SAFETY: SSE2.
                    F64x2(unsafe { $intrinsic(self.0, other.0) })
                }
            }
        };
    }
    op!(Add, add, _mm_add_pd);
    op!(Sub, sub, _mm_sub_pd);
    op!(Mul, mul, _mm_mul_pd);
    op!(Div, div, _mm_div_pd);

    impl Neg for F64x2 {
        type Output = F64x2;
        #[inline(always)]
        fn neg(self) -> F64x2 {
            // Flips the sign bits, as scalar negation does.
            // SAFETY: SSE2.
            F64x2(unsafe { _mm_xor_pd(self.0, _mm_set1_pd(-0.0)) })
        }
    }

    impl Lanes for F64x2 {
        const LANES: usize = 2;
        type Mask = Mask2;
        #[inline(always)]
        fn splat(v: f64) -> Self {
            // SAFETY: SSE2.
            F64x2(unsafe { _mm_set1_pd(v) })
        }
        #[inline(always)]
        fn sqrt(self) -> Self {
            // SAFETY: SSE2.
            F64x2(unsafe { _mm_sqrt_pd(self.0) })
        }
        #[inline(always)]
        fn gt(self, other: Self) -> Mask2 {
            // SAFETY: SSE2 (ordered, non-signalling: false with NaN).
            Mask2(unsafe { _mm_cmpgt_pd(self.0, other.0) })
        }
        #[inline(always)]
        fn lt(self, other: Self) -> Mask2 {
            // SAFETY: SSE2 (ordered: false with NaN).
            Mask2(unsafe { _mm_cmplt_pd(self.0, other.0) })
        }
        #[inline(always)]
        fn select(mask: Mask2, a: Self, b: Self) -> Self {
            // SAFETY: SSE2.
            F64x2(unsafe { _mm_or_pd(_mm_and_pd(mask.0, a.0), _mm_andnot_pd(mask.0, b.0)) })
        }
        #[inline(always)]
        fn min_else(self, other: Self) -> Self {
            // SAFETY: SSE2 (`minpd`: the first operand where it is less, else the second).
            F64x2(unsafe { _mm_min_pd(self.0, other.0) })
        }
        #[inline(always)]
        fn max_else(self, other: Self) -> Self {
            // SAFETY: SSE2 (`maxpd`: the first operand where it is greater, else the second).
            F64x2(unsafe { _mm_max_pd(self.0, other.0) })
        }
        #[inline(always)]
        fn gather(mut f: impl FnMut(usize) -> f64) -> Self {
            let a = f(0);
            F64x2::new(a, f(1))
        }
        #[inline(always)]
        fn each(self, mut f: impl FnMut(usize, f64)) {
            let [a, b] = self.lanes();
            f(0, a);
            f(1, b);
        }
    }
}

#[cfg(not(target_arch = "x86_64"))]
mod imp {
    //! Plain arrays elsewhere (the compiler may still pair the operations).
    use super::Lanes;
    use std::ops::{Add, BitOr, Div, Mul, Neg, Sub};

    /// Two `f64` lanes.
    #[derive(Clone, Copy, Debug)]
    pub struct F64x2([f64; 2]);

    /// Two lane truth values.
    #[derive(Clone, Copy, Debug)]
    pub struct Mask2([bool; 2]);

    impl F64x2 {
        /// Lanes `[a, b]`.
        #[inline(always)]
        pub fn new(a: f64, b: f64) -> Self {
            F64x2([a, b])
        }

        /// The two lanes.
        #[inline(always)]
        pub fn lanes(self) -> [f64; 2] {
            self.0
        }
    }

    impl F64x2 {
        /// `self >= other` per lane (false where either is NaN).
        #[inline(always)]
        pub fn ge(self, other: Self) -> Mask2 {
            Mask2([self.0[0] >= other.0[0], self.0[1] >= other.0[1]])
        }
    }

    impl Mask2 {
        /// Both lanes' truth values.
        #[inline(always)]
        pub fn lanes(self) -> [bool; 2] {
            self.0
        }

        /// Whether either lane holds.
        #[inline(always)]
        pub fn any(self) -> bool {
            self.0[0] || self.0[1]
        }
    }

    impl BitOr for Mask2 {
        type Output = Mask2;
        #[inline(always)]
        fn bitor(self, other: Mask2) -> Mask2 {
            Mask2([self.0[0] || other.0[0], self.0[1] || other.0[1]])
        }
    }

    macro_rules! op {
        ($trait:ident, $method:ident, $op:tt) => {
            impl $trait for F64x2 {
                type Output = F64x2;
                #[inline(always)]
                fn $method(self, other: F64x2) -> F64x2 {
                    F64x2([self.0[0] $op other.0[0], self.0[1] $op other.0[1]])
                }
            }
        };
    }
    op!(Add, add, +);
    op!(Sub, sub, -);
    op!(Mul, mul, *);
    op!(Div, div, /);

    impl Neg for F64x2 {
        type Output = F64x2;
        #[inline(always)]
        fn neg(self) -> F64x2 {
            F64x2([-self.0[0], -self.0[1]])
        }
    }

    impl Lanes for F64x2 {
        const LANES: usize = 2;
        type Mask = Mask2;
        #[inline(always)]
        fn splat(v: f64) -> Self {
            F64x2([v, v])
        }
        #[inline(always)]
        fn sqrt(self) -> Self {
            F64x2([self.0[0].sqrt(), self.0[1].sqrt()])
        }
        #[inline(always)]
        fn gt(self, other: Self) -> Mask2 {
            Mask2([self.0[0] > other.0[0], self.0[1] > other.0[1]])
        }
        #[inline(always)]
        fn lt(self, other: Self) -> Mask2 {
            Mask2([self.0[0] < other.0[0], self.0[1] < other.0[1]])
        }
        #[inline(always)]
        fn select(mask: Mask2, a: Self, b: Self) -> Self {
            F64x2([
                if mask.0[0] { a.0[0] } else { b.0[0] },
                if mask.0[1] { a.0[1] } else { b.0[1] },
            ])
        }
        #[inline(always)]
        fn min_else(self, other: Self) -> Self {
            F64x2([
                self.0[0].min_else(other.0[0]),
                self.0[1].min_else(other.0[1]),
            ])
        }
        #[inline(always)]
        fn max_else(self, other: Self) -> Self {
            F64x2([
                self.0[0].max_else(other.0[0]),
                self.0[1].max_else(other.0[1]),
            ])
        }
        #[inline(always)]
        fn gather(mut f: impl FnMut(usize) -> f64) -> Self {
            let a = f(0);
            F64x2::new(a, f(1))
        }
        #[inline(always)]
        fn each(self, mut f: impl FnMut(usize, f64)) {
            let [a, b] = self.lanes();
            f(0, a);
            f(1, b);
        }
    }
}

/// The larger of `acc` and `v`, `acc` when `v` is NaN (as `f64::max` when `acc` is never
/// NaN, which holds for the pass's maxima, started at zero): one `maxsd` on the loop's
/// dependency chain instead of `f64::max`'s NaN blend.
#[inline(always)]
pub(crate) fn max_skipping_nan(acc: f64, v: f64) -> f64 {
    if v > acc { v } else { acc }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lanes_give_the_scalar_bits() {
        let values = [
            0.0,
            -0.0,
            1.0,
            -2.5,
            1e-310,
            3.0e300,
            f64::INFINITY,
            f64::NAN,
            0.1,
            7.0 / 3.0,
        ];
        for &a in &values {
            for &b in &values {
                let (x, y) = (F64x2::new(a, b), F64x2::new(b, a));
                let bits = |v: F64x2| v.lanes().map(f64::to_bits);
                let scalar = |f: fn(f64, f64) -> f64| [f(a, b).to_bits(), f(b, a).to_bits()];
                assert_eq!(bits(x + y), scalar(|p, q| p + q));
                assert_eq!(bits(x - y), scalar(|p, q| p - q));
                assert_eq!(bits(x * y), scalar(|p, q| p * q));
                assert_eq!(bits(x / y), scalar(|p, q| p / q));
                assert_eq!(bits(-x), [(-a).to_bits(), (-b).to_bits()]);
                assert_eq!(bits(x.sqrt()), [a.sqrt().to_bits(), b.sqrt().to_bits()]);
                assert_eq!(x.gt(y).lanes(), [a > b, b > a]);
                assert_eq!(x.lt(y).lanes(), [a < b, b < a]);
                let scalar_min = |p: f64, q: f64| if p < q { p } else { q };
                let scalar_max = |p: f64, q: f64| if p > q { p } else { q };
                assert_eq!(
                    bits(x.min_else(y)),
                    [scalar_min(a, b).to_bits(), scalar_min(b, a).to_bits()]
                );
                assert_eq!(
                    bits(x.max_else(y)),
                    [scalar_max(a, b).to_bits(), scalar_max(b, a).to_bits()]
                );
                assert_eq!(bits(x.min_else(y)), bits(F64x2::select(x.lt(y), x, y)));
                assert_eq!(bits(x.max_else(y)), bits(F64x2::select(x.gt(y), x, y)));
                let chosen = F64x2::select(x.lt(y), x, y);
                assert_eq!(
                    bits(chosen),
                    [
                        (if a < b { a } else { b }).to_bits(),
                        (if b < a { b } else { a }).to_bits()
                    ]
                );
            }
        }
    }

    #[test]
    fn four_lanes_keep_each_lane_in_its_place_with_the_scalar_bits() {
        // Lane k of a gather is f(k), and `each` hands it back as lane k; every operation
        // acts lane by lane with the scalar bits (the selection too).
        let a = [1.5, -0.0, f64::NAN, 1e-310];
        let b = [0.1, 2.0, 3.0, -7.25];
        let (x, y) = (F64x4::gather(|k| a[k]), F64x4::gather(|k| b[k]));
        let mut seen = Vec::new();
        x.each(|k, v| seen.push((k, v.to_bits())));
        assert_eq!(
            seen,
            (0..4).map(|k| (k, a[k].to_bits())).collect::<Vec<_>>()
        );
        let bits = |v: F64x4| v.lanes().map(f64::to_bits);
        let scalar = |f: &dyn Fn(f64, f64) -> f64| [0, 1, 2, 3].map(|k| f(a[k], b[k]).to_bits());
        assert_eq!(bits(x + y), scalar(&|p, q| p + q));
        assert_eq!(bits(x - y), scalar(&|p, q| p - q));
        assert_eq!(bits(x * y), scalar(&|p, q| p * q));
        assert_eq!(bits(x / y), scalar(&|p, q| p / q));
        assert_eq!(bits(-x), scalar(&|p, _| -p));
        assert_eq!(bits(x.sqrt()), scalar(&|p, _| p.sqrt()));
        assert_eq!(bits(F64x4::splat(2.5)), [2.5f64.to_bits(); 4]);
        let pick = |m: Mask4| bits(F64x4::select(m, x, y));
        assert_eq!(pick(x.gt(y)), scalar(&|p, q| if p > q { p } else { q }));
        assert_eq!(pick(x.lt(y)), scalar(&|p, q| if p < q { p } else { q }));
        assert_eq!(bits(x.min_else(y)), pick(x.lt(y)));
        assert_eq!(bits(x.max_else(y)), pick(x.gt(y)));
    }
}
