//! Compositing associated colors along a ray.
//!
//! Front to back: `C ← C + (1 − A)·C̃_s`, `A ← A + (1 − A)·α_s`, optionally stopping once
//! `A ≥ A_stop` ([`Threshold`]). Back to front: `C ← C̃_s + (1 − α_s)·C`,
//! `A ← α_s + (1 − α_s)·A`. Over a background `B`: `C + (1 − A)·B` ([`over`]).
//!
//! Both orders keep `0 ≤ C ≤ A ≤ 1` in `f32` for valid samples: the products round
//! monotonically, and `A + fl(1 − A)` cannot round above 1.

use crate::error::Error;
use crate::lanes::Lanes;
use crate::sample::{Interp, Sample};

/// One front-to-back step: `acc` is in front of `s`.
///
/// Error bound: each output within 2 ulp of 1 of the exact value for the given `f32` input;
/// over `n` steps the error grows at most linearly, `n·3·2⁻²³` (`COMPOSITE_STEP` in the
/// tests).
#[inline(always)]
pub fn front_to_back(acc: Sample, s: Sample) -> Sample {
    Sample::from(front_to_back_in(acc.into(), s.into(), true))
}

/// [`front_to_back`] in any [`Lanes`] (the one front-to-back step of every kernel), kept in
/// the lanes of `live` only: `T = 1 − A`, `C + T·C̃_s`, `A + T·α_s`.
#[inline(always)]
pub(crate) fn front_to_back_in<T: Lanes>(acc: Interp<T>, s: Interp<T>, live: T::Mask) -> Interp<T> {
    let t = T::ONE - acc.a;
    let [r, g, b] = acc.c;
    let [sr, sg, sb] = s.c;
    Interp {
        c: [
            T::select(live, r + t * sr, r),
            T::select(live, g + t * sg, g),
            T::select(live, b + t * sb, b),
        ],
        a: T::select(live, acc.a + t * s.a, acc.a),
    }
}

/// One back-to-front step: `s` is in front of `acc`.
///
/// Error bound: as [`front_to_back`].
#[inline(always)]
pub fn back_to_front(acc: Sample, s: Sample) -> Sample {
    let t = 1.0 - s.a;
    let [r, g, b] = acc.c;
    let [sr, sg, sb] = s.c;
    Sample {
        c: [sr + t * r, sg + t * g, sb + t * b],
        a: s.a + t * acc.a,
    }
}

/// `front` over `back`: `C_f + (1 − A_f)·C_b`, `A_f + (1 − A_f)·A_b` (one front-to-back step).
#[inline(always)]
pub fn over(front: Sample, back: Sample) -> Sample {
    front_to_back(front, back)
}

mod sealed {
    pub trait Sealed {}
    impl Sealed for super::Never {}
    impl Sealed for super::Threshold {}
    impl<K: super::Termination> Sealed for super::FrontToBack<K> {}
    impl Sealed for super::BackToFront {}
}

/// When a front-to-back ray may stop early.
pub trait Termination: sealed::Sealed + Copy + core::fmt::Debug {
    /// `true` once the accumulated opacity `a` is high enough to stop.
    fn done(&self, a: f32) -> bool;

    /// The `A_stop` of [`done`](Self::done) (`done(a)` is `a ≥ A_stop`): `+∞` for [`Never`].
    #[doc(hidden)]
    fn a_stop_or_inf(&self) -> f32;
}

/// Never stop early (`A_stop = 1`): no test in the inner loop.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Never;

impl Termination for Never {
    #[inline(always)]
    fn done(&self, _a: f32) -> bool {
        false
    }

    #[inline(always)]
    fn a_stop_or_inf(&self) -> f32 {
        f32::INFINITY
    }
}

/// Stop once `A ≥ A_stop`. The color then misses at most `(1 − A_stop)` (times the largest
/// remaining straight color) of its value.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Threshold {
    a_stop: f32,
}

impl Threshold {
    /// Stop at `a_stop ∈ (0, 1]`.
    ///
    /// # Errors
    /// [`Error::InvalidThreshold`] outside `(0, 1]` or NaN.
    pub fn new(a_stop: f32) -> Result<Self, Error> {
        if a_stop > 0.0 && a_stop <= 1.0 {
            Ok(Self { a_stop })
        } else {
            Err(Error::InvalidThreshold)
        }
    }

    /// `A_stop`.
    pub fn a_stop(&self) -> f32 {
        self.a_stop
    }
}

impl Termination for Threshold {
    #[inline(always)]
    fn done(&self, a: f32) -> bool {
        a >= self.a_stop
    }

    #[inline(always)]
    fn a_stop_or_inf(&self) -> f32 {
        self.a_stop
    }
}

/// The compositing order of a ray, chosen by type.
pub trait Order: sealed::Sealed + Copy + core::fmt::Debug {
    /// `true`: samples are visited from the eye outwards.
    const FRONT_TO_BACK: bool;
    /// The early-termination rule (always [`Never`] back to front).
    type Term: Termination;
    /// The early-termination rule.
    fn termination(&self) -> Self::Term;
}

/// Front-to-back compositing with termination rule `K` ([`Never`] by default).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct FrontToBack<K: Termination = Never>(pub K);

impl FrontToBack<Never> {
    /// Front to back, no early termination.
    pub const fn new() -> Self {
        Self(Never)
    }
}

impl FrontToBack<Threshold> {
    /// Front to back, stopping once `A ≥ a_stop`.
    ///
    /// # Errors
    /// [`Error::InvalidThreshold`] outside `(0, 1]`.
    pub fn with_threshold(a_stop: f32) -> Result<Self, Error> {
        Threshold::new(a_stop).map(Self)
    }
}

impl<K: Termination> Order for FrontToBack<K> {
    const FRONT_TO_BACK: bool = true;
    type Term = K;
    #[inline(always)]
    fn termination(&self) -> K {
        self.0
    }
}

/// Back-to-front compositing (no early termination possible).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BackToFront;

impl Order for BackToFront {
    const FRONT_TO_BACK: bool = false;
    type Term = Never;
    #[inline(always)]
    fn termination(&self) -> Never {
        Never
    }
}
