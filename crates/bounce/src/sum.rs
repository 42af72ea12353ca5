//! Exact sums: totals that do not depend on the order of their terms.
//!
//! A step's fluxes (the collision virial, the walls' impulses) are sums over events that
//! threads, storage order and, in a distributed run, the ranks meet in different orders.
//! Floating-point addition is not associative, so a plain `+=` would give totals that differ
//! in their last bits with the order. [`ExactSum`] keeps the sum exactly, as a fixed-point
//! integer wide enough for every finite `f64` (a "superaccumulator": 32-bit limbs of `i64`;
//! a term's 53 bits go into two of them, so a limb has room for 2^10 additions before
//! carries are propagated), so any order, any
//! grouping and any merge of partial sums give the same total, and [`ExactSum::value`] turns
//! that one total into the same `f64`. Infinities and NaN are kept apart in an `f64` whose
//! sum does not depend on order either (`inf + -inf` is NaN whichever comes first).
//!
//! The limbs are allocated on the first non-zero term, so a sum that stays empty (a chunk of
//! discs none of which met a wall) costs nothing.

use serde::{Deserialize, Serialize};

/// 32-bit limbs from 2^-1074 (the smallest subnormal) up: 2046 exponents plus 53 mantissa bits
/// need 66, and one more holds the carries of a total above `f64::MAX`.
const LIMBS: usize = 67;
/// Additions a limb takes before carries must be propagated to keep it within `i64`: each
/// adds less than 2^52 in magnitude (a term's bits above the lowest 32 of its window), to a
/// limb below 2^32 after a carry.
const ADDS_BEFORE_CARRY: u32 = 1 << 10;

/// Momentum magnitude delivered to each wall (sum of `m |Δv|` of the discs it reflected).
/// Divide by the elapsed time and the wall's length for the pressure. See
/// [`crate::StepSums`] for an example.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct WallImpulse {
    /// The wall at `min[0]`.
    pub left: f64,
    /// The wall at `max[0]`.
    pub right: f64,
    /// The wall at `min[1]`.
    pub bottom: f64,
    /// The wall at `max[1]`.
    pub top: f64,
}

impl WallImpulse {
    /// Sum over the four walls. See [`crate::StepStats`] for an example.
    pub fn total(&self) -> f64 {
        self.left + self.right + self.bottom + self.top
    }
}

/// An exact, order-independent sum of `f64` terms.
///
/// ```
/// use bounce::ExactSum;
/// let mut a = ExactSum::new();
/// for t in [1e16, 1.0, -1e16, 0.1, 0.2] {
///     a.add(t);
/// }
/// // Added left to right in f64 the 1.0 is lost (0.30000000000000004); exactly it is not.
/// assert_eq!(a.value(), 1.3);
/// // Another order and grouping, merged: the same bits.
/// let (mut b, mut c) = (ExactSum::new(), ExactSum::new());
/// b.add_all(&[0.2, 0.1]);
/// c.add_all(&[-1e16, 1.0, 1e16]);
/// b.merge(&c);
/// assert_eq!(b.value().to_bits(), a.value().to_bits());
/// // As words (what a distributed run adds limb by limb) and back.
/// let words = a.to_words();
/// assert_eq!(words.len(), ExactSum::WORDS);
/// let limbs = &words[..ExactSum::WORDS - 1];
/// let special = f64::from_bits(words[ExactSum::WORDS - 1] as u64);
/// assert_eq!(ExactSum::from_words(limbs, special).value(), 1.3);
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ExactSum {
    /// Lane `k` weighs `2^(32 k - 1074)`; `None` until a non-zero finite term arrives.
    limbs: Option<Box<[i64; LIMBS]>>,
    /// Additions since carries were last propagated.
    adds: u32,
    /// The sum of the non-finite terms (0 when there are none).
    special: f64,
}

impl ExactSum {
    /// An empty sum (zero). See [`ExactSum`] for an example.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds `v` exactly. See [`ExactSum`] for an example.
    #[inline]
    pub fn add(&mut self, v: f64) {
        self.add_all(&[v]);
    }

    /// Adds each of `terms` exactly (zeros add nothing): the carry interval checked and the
    /// limbs found once for all of them (the solver adds its SIMD lanes' virial terms
    /// together).
    /// See [`ExactSum`] for an example.
    #[inline]
    pub fn add_all(&mut self, terms: &[f64]) {
        debug_assert!(terms.len() <= ADDS_BEFORE_CARRY as usize);
        if terms.iter().all(|&v| v == 0.0) {
            // The limbs stay unallocated (and the sum equal to an empty one) until a term
            // that is not zero.
            return;
        }
        if self.adds as usize + terms.len() > ADDS_BEFORE_CARRY as usize {
            self.carry();
        }
        self.adds += terms.len() as u32;
        let limbs = self.limbs.get_or_insert_with(|| Box::new([0; LIMBS]));
        for &v in terms {
            let bits = v.to_bits();
            let exponent = ((bits >> 52) & 0x7ff) as u32;
            if exponent == 0x7ff {
                self.special += v;
                continue;
            }
            // `v = ±mantissa × 2^(position − 1074)`; subnormals (exponent 0) have position
            // 0, as do the smallest normals (exponent 1), with the implicit bit. (A zero has
            // mantissa 0 and adds 0.)
            let mantissa = (bits & ((1 << 52) - 1)) | (u64::from(exponent != 0) << 52);
            let position = exponent.saturating_sub(1);
            // `position < 2046`, so `limb < 64` (the mask says so to the compiler, which then
            // needs no bounds check for `limb + 1 < LIMBS`).
            let (limb, shift) = ((position / 32) as usize & 63, position % 32);
            // The sign applied without a branch (terms of either sign come at random): all
            // ones where negative, so `(m ^ sign) - sign` is `-m` there and `m` else.
            let sign = -((bits >> 63) as i64);
            let signed = (mantissa as i64 ^ sign) - sign;
            // `signed × 2^shift` (85 bits at most) as its lowest 32 bits (two's complement,
            // in `[0, 2^32)`) and the rest (the arithmetic shift's floor, below 2^52 in
            // magnitude), in two limbs: no 128-bit shift and one limb fewer than 32-bit
            // pieces (the virial is a fifth of a settled pile's resolution).
            limbs[limb] += signed.wrapping_shl(shift) & 0xffff_ffff;
            limbs[limb + 1] += signed >> (32 - shift);
        }
    }

    /// Adds every term of `other` (the two sums merged: still exact). See [`ExactSum`] for an example.
    pub fn merge(&mut self, other: &ExactSum) {
        self.special += other.special;
        let Some(theirs) = &other.limbs else {
            return;
        };
        // Ours normalised (each limb below 2^32 in magnitude) and theirs at most 2^10
        // additions of less than 2^52 each past a carry: the limb sums stay within `i64`.
        self.carry();
        let limbs = self.limbs.get_or_insert_with(|| Box::new([0; LIMBS]));
        for (mine, theirs) in limbs.iter_mut().zip(theirs.iter()) {
            *mine += theirs;
        }
        self.carry();
    }

    /// Propagates carries so every limb but the top one lies in `[0, 2^32)`.
    fn carry(&mut self) {
        if let Some(limbs) = &mut self.limbs {
            carry_limbs(limbs);
        }
        self.adds = 0;
    }

    /// The sum as one `f64` (within a unit in the last place of the exact total). Equal
    /// totals give equal bits, however their terms were ordered or grouped. See [`ExactSum`]
    /// for an example.
    pub fn value(&self) -> f64 {
        let finite = match &self.limbs {
            None => 0.0,
            Some(limbs) => {
                let mut limbs = limbs.clone();
                carry_limbs(&mut limbs);
                let negative = limbs[LIMBS - 1] < 0;
                if negative {
                    // The magnitude, in the same canonical form.
                    for limb in limbs.iter_mut() {
                        *limb = -*limb;
                    }
                    carry_limbs(&mut limbs);
                }
                // Top limb down: each limb is exact in an f64, and the first non-zero limbs
                // fix the result.
                let mut total = 0.0;
                for (k, &limb) in limbs.iter().enumerate().rev() {
                    if limb != 0 {
                        total += scale(limb as f64, 32 * k as i32 - 1074);
                    }
                }
                if negative { -total } else { total }
            }
        };
        finite + self.special
    }

    /// The sum's canonical words, for sending (a distributed run reduces these by adding
    /// them limb by limb, then [`ExactSum::from_words`]): `LIMBS` limbs then the non-finite
    /// part's bits. See [`ExactSum`] for an example.
    pub fn to_words(&self) -> Vec<i64> {
        let mut words = match &self.limbs {
            Some(limbs) => {
                let mut limbs = limbs.clone();
                carry_limbs(&mut limbs);
                limbs.to_vec()
            }
            None => vec![0; LIMBS],
        };
        words.push(self.special.to_bits() as i64);
        words
    }

    /// The number of words [`ExactSum::to_words`] gives. See [`ExactSum`] for an example.
    pub const WORDS: usize = LIMBS + 1;

    /// The sum of several sums' limbs (added limb by limb, at most 2^31 of them) and the
    /// non-finite parts summed separately, as `special`. See [`ExactSum`] for an example.
    pub fn from_words(limbs: &[i64], special: f64) -> ExactSum {
        let mut sum = ExactSum {
            limbs: None,
            adds: 0,
            special,
        };
        if limbs.iter().take(LIMBS).any(|&l| l != 0) {
            let mut all = [0; LIMBS];
            all.copy_from_slice(&limbs[..LIMBS]);
            carry_limbs(&mut all);
            sum.limbs = Some(Box::new(all));
        }
        sum
    }
}

/// Carries every limb's bits above 32 into the next limb (the top limb keeps its sign).
fn carry_limbs(limbs: &mut [i64; LIMBS]) {
    for k in 0..LIMBS - 1 {
        let carry = limbs[k] >> 32;
        limbs[k] -= carry << 32;
        limbs[k + 1] += carry;
    }
}

/// `v × 2^e`, in steps of exact powers of two (so `e` may go past the `f64` exponent range
/// while the result stays in it).
fn scale(mut v: f64, mut e: i32) -> f64 {
    while e > 1000 {
        v *= f64::from_bits(2023 << 52); // 2^1000
        e -= 1000;
    }
    while e < -1000 {
        v *= f64::from_bits(23 << 52); // 2^-1000
        e += 1000;
    }
    v * f64::from_bits(((e + 1023) as u64) << 52)
}

/// The momentum each wall received, and the energy the walls' friction removed, summed
/// exactly (see [`ExactSum`]). See [`StepSums`] for an example.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WallSums {
    /// Left (`min[0]`), right, bottom (`min[1]`), top.
    pub walls: [ExactSum; 4],
    /// The energy friction and rolling resistance at the walls removed (rough discs).
    pub friction: ExactSum,
}

impl WallSums {
    /// Adds one disc's impulses on the left, right, bottom and top walls.
    #[inline]
    pub(crate) fn add(&mut self, impulses: [f64; 4]) {
        for (sum, j) in self.walls.iter_mut().zip(impulses) {
            sum.add(j);
        }
    }

    /// Merges another set of sums (exactly, as [`ExactSum::merge`]). See [`StepSums`] for
    /// an example.
    pub fn merge(&mut self, other: &WallSums) {
        for (mine, theirs) in self.walls.iter_mut().zip(&other.walls) {
            mine.merge(theirs);
        }
        self.friction.merge(&other.friction);
    }

    /// The totals as a [`WallImpulse`]. See [`StepSums`] for an example.
    pub fn impulse(&self) -> WallImpulse {
        let [left, right, bottom, top] = [0, 1, 2, 3].map(|k| self.walls[k].value());
        WallImpulse {
            left,
            right,
            bottom,
            top,
        }
    }
}

/// What a step sums over its events, exactly: the raw collision virial `Σ r_ij · Δp_ij` over
/// every resolved pair of every substep and pass, and the walls' impulses. In a distributed
/// run each rank sums the events it is responsible for ([`crate::World::set_tally`]) and the
/// ranks' sums are merged: the totals equal one process's, bit for bit.
///
/// ```
/// use bounce::{Boundary, Config, Particle, World};
/// let mut world = World::new(Config {
///     boundary: Boundary::walls([0.0, 0.0], [10.0, 10.0]),
///     ..Config::default()
/// })?;
/// // Mass 0.5 (the seed's mass = radius) at speed 2 into the right wall: m |Δv| = 2.
/// world.add_particle(Particle::new([9.0, 5.0], [2.0, 0.0], 0.5))?;
/// world.step(1.0)?;
/// let sums = world.step_sums();
/// assert_eq!(sums.walls.impulse().right, 2.0);
/// assert_eq!(sums.walls.impulse(), world.stats().wall_impulse);
/// assert_eq!((sums.virial.value(), sums.friction_work()), (0.0, 0.0)); // no pair, smooth
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StepSums {
    /// `Σ r_ij · Δp_ij` (the step's [`crate::StepStats::virial`] is half of it over `dt`).
    pub virial: ExactSum,
    /// The momentum given to each wall, and the energy the walls' friction removed.
    pub walls: WallSums,
    /// The energy friction and rolling resistance removed at pairs and obstacles (rough
    /// discs; the walls' is in `walls`).
    pub friction: ExactSum,
}

impl StepSums {
    /// The energy friction and rolling resistance removed in the step, everywhere
    /// ([`crate::StepStats::friction_work`]). See [`StepSums`] for an example.
    pub fn friction_work(&self) -> f64 {
        let mut all = self.friction.clone();
        all.merge(&self.walls.friction);
        all.value()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small deterministic generator of awkward terms: mixed signs, magnitudes over 600
    /// binary orders, subnormals.
    fn terms(n: usize) -> Vec<f64> {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        (0..n)
            .map(|_| {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                let mantissa = (state >> 11) as f64 / (1u64 << 53) as f64;
                let exponent = (state % 600) as i32 - 300;
                let sign = if state & 1 == 0 { 1.0 } else { -1.0 };
                let v = sign * mantissa * 2f64.powi(exponent);
                if state.is_multiple_of(97) {
                    v * 1e-310
                } else {
                    v
                }
            })
            .collect()
    }

    fn sum_of(values: &[f64]) -> ExactSum {
        let mut s = ExactSum::new();
        for &v in values {
            s.add(v);
        }
        s
    }

    #[test]
    fn integers_and_halves_sum_exactly() {
        let s = sum_of(&[1.0, 2.0, 3.0, 0.5, -0.25]);
        assert_eq!(s.value(), 6.25);
        // Catastrophic cancellation a plain sum loses: 1e16 + 1 - 1e16 is 0 in f64.
        let s = sum_of(&[1e16, 1.0, -1e16]);
        assert_eq!(s.value(), 1.0);
        assert_eq!((1e16 + 1.0) - 1e16, 0.0);
        assert_eq!(sum_of(&[]).value(), 0.0);
        assert_eq!(sum_of(&[-3.5]).value(), -3.5);
        assert_eq!(sum_of(&[f64::MAX, f64::MAX, -f64::MAX]).value(), f64::MAX);
        assert_eq!(sum_of(&[5e-324, 5e-324]).value(), 1e-323);
        // Across the subnormal boundary, either sign: the smallest normal less the largest
        // subnormal is the smallest subnormal.
        let largest_subnormal = f64::MIN_POSITIVE - 5e-324;
        assert!(largest_subnormal.is_subnormal());
        assert_eq!(
            sum_of(&[f64::MIN_POSITIVE, -largest_subnormal]).value(),
            5e-324
        );
        assert_eq!(
            sum_of(&[-f64::MIN_POSITIVE, largest_subnormal]).value(),
            -5e-324
        );
        assert_eq!(sum_of(&[-5e-324, -f64::MAX, f64::MAX]).value(), -5e-324);
    }

    #[test]
    fn any_order_and_any_grouping_give_the_same_bits() {
        let values = terms(5000);
        let forward = sum_of(&values).value();
        let mut reversed = values.clone();
        reversed.reverse();
        assert_eq!(sum_of(&reversed).value().to_bits(), forward.to_bits());
        // Split into uneven groups, merged in another order.
        for cut in [1, 17, 2500, 4999] {
            let mut merged = sum_of(&values[cut..]);
            merged.merge(&sum_of(&values[..cut]));
            assert_eq!(merged.value().to_bits(), forward.to_bits());
        }
        // Through the words of three parts added limb by limb, as ranks reduce them.
        let parts = [&values[..1000], &values[1000..3000], &values[3000..]];
        let mut limbs = vec![0i64; ExactSum::WORDS - 1];
        for part in parts {
            for (l, w) in limbs.iter_mut().zip(sum_of(part).to_words()) {
                *l += w;
            }
        }
        assert_eq!(
            ExactSum::from_words(&limbs, 0.0).value().to_bits(),
            forward.to_bits()
        );
    }

    #[test]
    fn a_plain_sum_depends_on_the_order_where_the_exact_one_does_not() {
        // Terms of one magnitude, like a step's virial terms.
        let mut state = 88172645463325252u64;
        let values: Vec<f64> = (0..5000)
            .map(|_| {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                (state >> 11) as f64 / (1u64 << 53) as f64 + 0.5
            })
            .collect();
        let mut reversed = values.clone();
        reversed.reverse();
        let plain: f64 = values.iter().sum();
        let plain_reversed: f64 = reversed.iter().sum();
        assert_ne!(plain.to_bits(), plain_reversed.to_bits());
        let exact = sum_of(&values).value();
        assert_eq!(exact.to_bits(), sum_of(&reversed).value().to_bits());
        assert!((exact - plain).abs() <= plain.abs() * 1e-12);
    }

    #[test]
    fn a_sum_is_the_exact_total_rounded() {
        // Terms whose exact total is known: k × 2^-60 for k in 1..=1000, and their
        // negatives shifted by one: total 1000 × 2^-60.
        let mut s = ExactSum::new();
        for k in 1..=1000 {
            s.add(k as f64 * 2f64.powi(-60));
            s.add(-((k - 1) as f64) * 2f64.powi(-60));
        }
        assert_eq!(s.value(), 1000.0 * 2f64.powi(-60));
        // 0.1 ten times is not 1 in f64 arithmetic, but the exact sum of those ten doubles
        // rounds to the double nearest 10 × 0.1's exact value.
        let s = sum_of(&[0.1; 10]);
        assert_eq!(s.value(), 1.0);
        assert_ne!([0.1f64; 10].iter().sum::<f64>(), 1.0);
    }

    #[test]
    fn infinities_and_nan_are_kept_whatever_the_order() {
        assert_eq!(sum_of(&[1.0, f64::INFINITY]).value(), f64::INFINITY);
        assert!(
            sum_of(&[f64::INFINITY, 1.0, f64::NEG_INFINITY])
                .value()
                .is_nan()
        );
        assert!(sum_of(&[f64::NAN, 1.0]).value().is_nan());
    }

    #[test]
    fn thousands_of_full_mantissas_in_one_window_sum_exactly() {
        // Terms just below 4 fill a term's window up to its top limb's 52 bits: thousands
        // of them in one limb (past the carry interval) still give the exact total.
        let t = 4.0f64.next_down(); // (2^53 - 1) × 2^-51
        let mantissa = (1i128 << 53) - 1;
        for (up, down) in [(5000, 0), (3000, 2999), (0, 4096), (7000, 2000)] {
            let mut s = ExactSum::new();
            for k in 0..up.max(down) {
                if k < up {
                    s.add(t);
                }
                if k < down {
                    s.add(-t);
                }
            }
            let exact = (up - down) as i128 * mantissa;
            let expected = exact as f64 * 2f64.powi(-51);
            assert_eq!(
                s.value().to_bits(),
                expected.to_bits(),
                "{up} up, {down} down"
            );
        }
    }

    #[test]
    fn many_additions_carry_without_overflow() {
        // Carries forced partway through give the same total as none.
        let values = terms(10);
        let mut s = ExactSum::new();
        s.adds = ADDS_BEFORE_CARRY - 3;
        for &v in &values {
            s.add(v);
        }
        assert_eq!(s.adds, 7);
        assert_eq!(s.value().to_bits(), sum_of(&values).value().to_bits());
    }
}
