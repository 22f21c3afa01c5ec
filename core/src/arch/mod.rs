//! Instruction sets: which instance of a kernel runs, chosen at run time.
//!
//! Every kernel has a portable instance, the only one linked on Cortex-M and other
//! targets. On x86-64 the AVX2 + FMA instances are compiled into every build (functions with
//! `#[target_feature(enable = "avx2,fma")]`, the portable code inlined into them), and a
//! marcher runs them when its [`Isa`] says so: by default the best the CPU has
//! ([`Isa::detect`], CPUID from `core::arch`, no `std`, nothing cached in global state), or the
//! one a caller forces ([`RayMarcher::with_isa`](crate::RayMarcher::with_isa),
//! [`IntRayMarcher::with_isa`](crate::render::IntRayMarcher::with_isa)) to compare them.
//! Every instance gives bit-identical results: the float ones those of one sample of one ray
//! at a time, the integer ones those of the bit-exact model.
//!
//! A marcher has an AVX2 instance where its types have an eight-lane AVX2 kernel
//! (`Filter::lanes8`: trilinear `OpacityWeighted`, `Separate` and the two extinction modes over
//! the formats those kernels read, and the integer `OpacityWeighted` over RGBA8); there its
//! whole march (one ray, packets, `sample_into`) is compiled for AVX2 (`InIsa`). Every other
//! marcher (B-spline, nearest, the trilinear tree, `Preweighted`, post-classification) has one
//! instance, the portable one, whatever its [`Isa`]: compiled for AVX2 the same code ran no
//! faster (the performance log, 2026-12-07 (morning)) and took a second copy of every march
//! in the build.
//!
//! The portable code reaches an AVX2 entry through `#[inline(always)]` at every level, the
//! closure handed to the entry included: LLVM is otherwise free to keep a large kernel out of
//! line, compiled for the baseline, behind an entry that only jumps to it (same results, the
//! baseline's speed). CI reads the CLI's machine code for that (`.ci/avx2_entries.py`).
//!
//! This module is the one place in the crate with `unsafe` code (every other module is
//! `forbid(unsafe_code)`): the entries into the AVX2 instances, whose proof is an [`Isa`]
//! value that only detection makes; the SSE2 kernel's entry (SSE2 is part of x86-64); and the
//! unchecked voxel loads of the AVX2 packets, each after its bounds test. Each block carries
//! its `SAFETY` proof (`clippy::undocumented_unsafe_blocks` is denied here).

#[cfg(target_arch = "x86_64")]
pub(crate) mod avx2;
#[cfg(target_arch = "x86_64")]
pub(crate) mod sse2;

use crate::error::Error;

/// The reads of a tap format ([`TapRead`](crate::mode)) in the instruction sets of the target:
/// on x86-64 its AVX2 reads; elsewhere none (only the portable kernels are linked). A
/// supertrait of the formats, so that a mode's type alone picks its reads.
mod reads {
    #[cfg(target_arch = "x86_64")]
    pub use super::avx2::ReadTaps as TapReads;

    /// (No instruction-specific reads on this target.)
    #[cfg(not(target_arch = "x86_64"))]
    pub trait TapReads {}
    #[cfg(not(target_arch = "x86_64"))]
    impl TapReads for crate::mode::Unorm8 {}
    #[cfg(not(target_arch = "x86_64"))]
    impl TapReads for crate::mode::TauOfAlpha8 {}
    #[cfg(not(target_arch = "x86_64"))]
    impl TapReads for crate::mode::StoredF32x4 {}
}
pub(crate) use reads::TapReads;

/// `$body` in the instruction set of the marcher `$m` ([`InIsa::run`]); on targets with one
/// instruction set, `$body` itself, without the closure (whose extra level of inlining
/// changed the Cortex-M code: 108 more bytes in the minimal float image).
///
/// The closure is `#[inline(always)]`: without it LLVM may keep a large body (a whole march)
/// as a function of its own, compiled for the baseline, and the AVX2 entry only jumps to it
/// (found in the CLI binary: 58 of the one-ray marches' AVX2 entries were such jumps).
macro_rules! in_isa {
    ($m:expr, $body:expr) => {{
        #[cfg(target_arch = "x86_64")]
        {
            $crate::arch::InIsa::run(
                $m,
                #[inline(always)]
                || $body,
            )
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            let _ = $m;
            $body
        }
    }};
}
pub(crate) use in_isa;

/// How a marcher enters its instruction set: the AVX2 instance exists only where the
/// marcher's types have an eight-lane AVX2 kernel, so that no other marcher compiles a second
/// copy of its march (see the module's docs). (Without methods on targets with one
/// instruction set.)
pub(crate) trait InIsa {
    /// The marcher's instruction set.
    #[cfg(target_arch = "x86_64")]
    fn isa_of(&self) -> Isa;

    /// `Ok(f())` inside the AVX2 entry where this marcher's types have an eight-lane AVX2
    /// kernel (its filter's `lanes8` visits [`InAvx2`]); `Err(f)` for every other marcher, by
    /// type, so that their AVX2 instance is never compiled.
    #[cfg(target_arch = "x86_64")]
    fn in_avx2<R, G: FnOnce() -> R>(&self, cpu: avx2::Avx2, f: G) -> Result<R, G>;

    /// `f()` in the marcher's instruction set where the marcher has an instance there
    /// ([`in_avx2`](Self::in_avx2)): inside a function compiled for it, into which `f` and
    /// the `#[inline(always)]` code it calls are inlined (the portable code compiled with
    /// the instruction set's instructions: the same operations, so the same results); else
    /// in the baseline, by one call of `f`, so that the portable march is inlined once. `f`
    /// must be `#[inline(always)]` itself (as `in_isa!` makes it): LLVM may otherwise keep a
    /// large closure out of line, compiled for the baseline.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn run<R>(&self, f: impl FnOnce() -> R) -> R {
        let f = match self.isa_of().avx2_token() {
            Some(cpu) => match self.in_avx2(cpu, f) {
                Ok(r) => return r,
                Err(f) => f,
            },
            None => f,
        };
        f()
    }
}

/// The visitor that [`InIsa::in_avx2`] hands to a filter's `lanes8`: visited (the marcher's
/// types have an eight-lane kernel), it runs its closure in AVX2; otherwise the filter
/// returns it, closure and all, unvisited.
#[cfg(target_arch = "x86_64")]
pub(crate) struct InAvx2<G, R>(avx2::Avx2, G, core::marker::PhantomData<fn() -> R>);

#[cfg(target_arch = "x86_64")]
impl<G: FnOnce() -> R, R> InAvx2<G, R> {
    /// `f`, to run in AVX2 on the CPU that `cpu` proves has it.
    #[inline(always)]
    pub(crate) fn new(cpu: avx2::Avx2, f: G) -> Self {
        Self(cpu, f, core::marker::PhantomData)
    }

    /// The closure, unvisited.
    #[inline(always)]
    pub(crate) fn into_inner(self) -> G {
        self.1
    }
}

#[cfg(target_arch = "x86_64")]
impl<G: FnOnce() -> R, R> crate::mode::LaneVisitor for InAvx2<G, R> {
    type Out = R;

    #[inline(always)]
    fn visit<K: crate::mode::LaneMode>(self, _mode: &K) -> R {
        self.0.run(self.1)
    }
}

#[cfg(target_arch = "x86_64")]
impl<G: FnOnce() -> R, R> crate::fixed_point::IntLaneVisitor for InAvx2<G, R> {
    type Out = R;

    #[inline(always)]
    fn visit<K: crate::fixed_point::IntLaneMode>(self, _mode: &K) -> R {
        self.0.run(self.1)
    }
}

/// Asks the CPU to bring the cache line holding `v` into its caches: a hint, which changes no
/// result (`prefetcht0` on x86-64, part of its baseline; nothing elsewhere).
#[inline(always)]
pub(crate) fn prefetch<T>(v: &T) {
    #[cfg(target_arch = "x86_64")]
    {
        use core::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        // SAFETY: SSE, which `_mm_prefetch` needs, is part of x86-64; a prefetch reads nothing
        // and cannot fault (and `v` is a reference besides).
        unsafe { _mm_prefetch::<_MM_HINT_T0>(core::ptr::from_ref(v).cast::<i8>()) }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = v;
}

/// An instruction set the kernels run in: a token that the CPU has it.
///
/// Made only by detection ([`detect`](Self::detect), [`avx2`](Self::avx2),
/// [`by_name`](Self::by_name)) or as [`BASELINE`](Self::BASELINE), so holding one proves that
/// its instructions run on this CPU. On targets without alternative instances the type has one
/// value and no size.
///
/// ```
/// use volsample::Isa;
/// let best = Isa::detect();
/// assert!(Isa::available().contains(&best));
/// assert_eq!(Isa::by_name("baseline"), Ok(Isa::BASELINE));
/// assert_eq!(Isa::by_name(best.name()), Ok(best));
/// assert!(Isa::by_name("sse9").is_err());
/// ```
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Isa(Kind);

impl core::fmt::Debug for Isa {
    /// `Isa(baseline)`, `Isa(avx2)`.
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "Isa({})", self.name())
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
enum Kind {
    Baseline,
    #[cfg(target_arch = "x86_64")]
    Avx2(avx2::Avx2),
}

impl Isa {
    /// The portable instances, which run on every CPU of the target.
    pub const BASELINE: Isa = Isa(Kind::Baseline);

    /// Every name [`by_name`](Self::by_name) knows, on any target.
    pub const NAMES: [&'static str; 2] = ["baseline", "avx2"];

    /// The best instruction set this CPU has: [`avx2`](Self::avx2) where it is `Some`, else
    /// [`BASELINE`](Self::BASELINE). Runs CPUID on x86-64 (a few hundred nanoseconds, more in a
    /// virtual machine): detect once and keep the value, as the marchers do at construction.
    #[inline]
    pub fn detect() -> Isa {
        Self::avx2().unwrap_or(Self::BASELINE)
    }

    /// AVX2 with FMA, where this is an x86-64 CPU that has both and the operating system
    /// saves the 256-bit registers; `None` elsewhere.
    #[inline]
    pub fn avx2() -> Option<Isa> {
        #[cfg(target_arch = "x86_64")]
        {
            avx2::Avx2::detect().map(|t| Isa(Kind::Avx2(t)))
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            None
        }
    }

    /// Every instruction set this CPU has, baseline first.
    pub fn available() -> heapless::Vec<Isa, 2> {
        let mut all = heapless::Vec::new();
        for isa in [Some(Self::BASELINE), Self::avx2()].into_iter().flatten() {
            // Capacity 2, at most 2 values: `push` cannot fail.
            let _ = all.push(isa);
        }
        all
    }

    /// The instruction set named `name` (one of [`NAMES`](Self::NAMES)), if this CPU has it.
    ///
    /// # Errors
    /// [`Error::UnknownIsa`] for any other name, [`Error::IsaUnavailable`] where this CPU
    /// (or target) lacks it.
    pub fn by_name(name: &str) -> Result<Isa, Error> {
        match name {
            "baseline" => Ok(Self::BASELINE),
            "avx2" => Self::avx2().ok_or(Error::IsaUnavailable),
            _ => Err(Error::UnknownIsa),
        }
    }

    /// The name: `"baseline"` or `"avx2"`.
    pub fn name(self) -> &'static str {
        match self.0 {
            Kind::Baseline => "baseline",
            #[cfg(target_arch = "x86_64")]
            Kind::Avx2(_) => "avx2",
        }
    }

    /// The AVX2 token, where this is AVX2.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    pub(crate) fn avx2_token(self) -> Option<avx2::Avx2> {
        match self.0 {
            Kind::Avx2(t) => Some(t),
            Kind::Baseline => None,
        }
    }
}

impl Default for Isa {
    /// [`Isa::detect`].
    fn default() -> Self {
        Self::detect()
    }
}

impl core::fmt::Display for Isa {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;

    /// The core's CPUID detection agrees with `std`'s (an independent implementation), so
    /// that the AVX2 instances run wherever the CPU has them and nowhere else.
    #[test]
    fn detection_agrees_with_std() {
        #[cfg(target_arch = "x86_64")]
        {
            let std_says =
                std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma");
            assert_eq!(Isa::avx2().is_some(), std_says);
            assert_eq!(
                Isa::detect().name(),
                if std_says { "avx2" } else { "baseline" }
            );
        }
        assert_eq!(Isa::available().first(), Some(&Isa::BASELINE));
        for isa in Isa::available() {
            assert_eq!(Isa::by_name(isa.name()), Ok(isa));
        }
        assert_eq!(Isa::by_name("AVX2"), Err(Error::UnknownIsa));
    }
}
