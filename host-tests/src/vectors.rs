//! Reference vectors for hardware test benches: `volsample vectors` (issue 7).
//!
//! Each vector set is a directory with
//!
//! * `inputs.hex` and `expected.hex`: one fixed-width word per line, lowercase hex, most
//!   significant digit first, no prefix or separators, readable by Verilog `$readmemh` into a
//!   `reg [W-1:0] mem [0:N-1]`;
//! * `manifest.json`: the kernel, every field's name, bit offset (0 = least significant bit of
//!   the word), width, fractional bits and meaning, the rounding rules (the names the core
//!   uses: **round half up**, **truncate**, **saturate**), the count, the seed and the
//!   generator version;
//! * for `opacity-correction` also the correction's lookup tables (`table_*.hex`), which do not
//!   depend on the ratio.
//!
//! Expected outputs come from the `volsample::fixed_point` kernels themselves (the golden
//! model); `host-tests/tests/vectors.rs` cross-checks them against the `f64` models in
//! [`int_model`](crate::int_model).
//!
//! # Kernels
//!
//! | name | core kernel | input word |
//! |---|---|---|
//! | `opacity-weighted-{nearest,trilinear}` | `IntSampler<StraightU8, OpacityWeighted, _>` | 8 straight voxels + `F`-bit fractions |
//! | `separate-{nearest,trilinear}` | `IntSampler<StraightU8, Separate, _>` | 8 straight voxels + fractions |
//! | `preweighted-{nearest,trilinear}` | `IntSampler<AssociatedU8, Preweighted, _>` | 8 associated voxels + fractions |
//! | `composite-front-to-back` | `front_to_back(acc, s)` | accumulator + sample (U8.8) |
//! | `opacity-correction` | `IntCorrection::apply` | sample + `IntRatio` (and the `f32` ratio) |
//! | `downsample-opacity-based` | `downsample_level_int(IntOpacityBased, …)` over `AssociatedU8` | 64 associated voxels + Q0.16 tap `a` |
//!
//! A sampling vector is one tap set: the eight voxels `v0…v7` of a 2×2×2 volume (voxel `i` at
//! `(i & 1, (i >> 1) & 1, i >> 2)`, the order of the core's taps and weights) sampled at
//! `IntPos::<F>::new([0, 0, 0], [fx, fy, fz])`, so every voxel is read and no edge clamping
//! happens. Nearest reads voxel `(fx ≥ 2^(F−1), fy ≥ 2^(F−1), fz ≥ 2^(F−1))`
//! (`nearest_index`, round half up).
//!
//! A downsampling vector is one coarse voxel's tap set: the 4×4×4 fine voxels `t0…t63`
//! (`t = i + 4j + 16k`, fine voxel `(2X − 1 + i, 2Y − 1 + j, 2Z − 1 + k)` of coarse voxel
//! `(X, Y, Z)`) and the filter's outer tap `a_raw` (Q0.16, taps `(a, 2^15 − a, 2^15 − a, a)`);
//! the core computes it as coarse voxel `(1, 1, 1)` of a 6×6×6 volume holding the taps at
//! `1..=4` per axis (so no edge clamping happens).
//!
//! # Generator (version [`GENERATOR_VERSION`])
//!
//! The corner cases of each kernel come first, in the fixed order of [`corner_cases`] (they
//! draw nothing from the generator); then random vectors until `count` vectors exist (if
//! `count` is smaller than the number of corner cases, the first `count` corners are kept).
//!
//! The generator is **SplitMix64** with `state = seed` before the first draw; each draw is
//! `state += 0x9E3779B97F4A7C15; z = state; z = (z ^ (z >> 30))·0xBF58476D1CE4E5B9;
//! z = (z ^ (z >> 27))·0x94D049BB133111EB; return z ^ (z >> 31)` (wrapping `u64`). Random
//! vectors draw, in order:
//!
//! * **sampling** (`m = 2^F − 1`): for each voxel `i = 0..8` one draw `w`: `r, g, b, a` are
//!   bytes 0, 1, 2, 3 of `w`, and `k = (w >> 32) & 7` replaces `a` by 0 (`k = 0`), by 255
//!   (`k = 1`), by 1 (`k = 2`) or all four bytes by 255 (`k = 3`); for `preweighted` each color
//!   byte then becomes `premultiply(c, a) = ⌊(2·c·a + 255)/510⌋`. Then one draw `w`:
//!   `fx = w & m`, `fy = (w >> 16) & m`, `fz = (w >> 32) & m`, and `k = (w >> 48) & 7` sets all
//!   three to 0 (`k = 0`), to `m` (`k = 1`) or to `2^(F−1)` (`k = 2`).
//! * **a U8.8 sample** (used below): one draw `w`, `k = w >> 61`; `a = 0` (`k = 0`), `ONE`
//!   (`k = 1`), `256·((w >> 8) & 255)` (`k = 2`, an 8-bit level) or `(w & 0xFFFFFFFF) % 65281`;
//!   then `r, g, b`, each one draw `% (a + 1)`.
//! * **compositing**: the accumulator, then the sample (each as above).
//! * **opacity correction**: one draw `w`, `ratio = (1 + w % 65536)/4096` (exact in `f32`,
//!   in `(0, 16]`), then the sample.
//! * **downsampling**: each of the 64 voxels as a `preweighted` sampling voxel above; then one
//!   draw `w`, `k = w >> 61`: `a_raw` = 0, 8192, 13107, 16384, 32768 for `k = 0…4`, else
//!   `(w & 0xFFFF) % 32769`.

use std::fmt;
use std::path::{Path, PathBuf};

use serde_json::{json, Value};
use volsample::downsample::integer::{downsample_level_int, IntFilter4, IntOpacityBased};
use volsample::fixed_point::correction::PSI_LIMIT;
use volsample::fixed_point::{
    front_to_back, premultiply, IntCorrection, IntFilter, IntMode, IntPos, IntSample, IntSampler,
    ONE,
};
use volsample::voxel::Voxel;
use volsample::{
    AssociatedU8, Nearest, OpacityWeighted, Preweighted, Separate, StraightU8, Trilinear, Volume,
};

/// Version of the generator and file layout; bumped whenever the bytes for a given
/// `(kernel, count, seed, frac_bits)` change.
pub const GENERATOR_VERSION: u32 = 1;

/// Name of the input file in a vector directory.
pub const INPUTS_FILE: &str = "inputs.hex";
/// Name of the expected-output file in a vector directory.
pub const EXPECTED_FILE: &str = "expected.hex";
/// Name of the manifest in a vector directory.
pub const MANIFEST_FILE: &str = "manifest.json";

/// The SplitMix64 generator (see the module docs).
#[derive(Debug, Clone)]
pub struct SplitMix64 {
    state: u64,
}

impl SplitMix64 {
    /// A generator whose state is `seed`.
    pub fn new(seed: u64) -> Self {
        Self { state: seed }
    }

    /// The next 64-bit draw.
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
}

/// What an integer sampling kernel interpolates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SampleMode {
    /// `OpacityWeighted` over straight `u8` voxels.
    OpacityWeighted,
    /// `Separate` over straight `u8` voxels.
    Separate,
    /// `Preweighted` over premultiplied `u8` voxels.
    Preweighted,
}

/// The reconstruction filter of a sampling kernel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SampleFilter {
    /// Nearest neighbour (one tap, chosen with round half up).
    Nearest,
    /// Trilinear, as the sum of eight exactly weighted taps.
    Trilinear,
}

/// An integer kernel that vectors can be generated for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kernel {
    /// One sample of a 2×2×2 tap set.
    Sample(SampleMode, SampleFilter),
    /// One front-to-back compositing step.
    Composite,
    /// Table-driven opacity correction of one sample.
    Correction,
    /// One coarse voxel of integer opacity-based downsampling of `u8` associated voxels.
    Downsample,
}

impl Kernel {
    /// Every kernel, in the order `volsample vectors` lists them.
    pub const ALL: [Kernel; 9] = [
        Kernel::Sample(SampleMode::OpacityWeighted, SampleFilter::Nearest),
        Kernel::Sample(SampleMode::OpacityWeighted, SampleFilter::Trilinear),
        Kernel::Sample(SampleMode::Separate, SampleFilter::Nearest),
        Kernel::Sample(SampleMode::Separate, SampleFilter::Trilinear),
        Kernel::Sample(SampleMode::Preweighted, SampleFilter::Nearest),
        Kernel::Sample(SampleMode::Preweighted, SampleFilter::Trilinear),
        Kernel::Composite,
        Kernel::Correction,
        Kernel::Downsample,
    ];

    /// The command-line name.
    pub fn name(self) -> &'static str {
        use SampleFilter::*;
        use SampleMode::*;
        match self {
            Kernel::Sample(OpacityWeighted, Nearest) => "opacity-weighted-nearest",
            Kernel::Sample(OpacityWeighted, Trilinear) => "opacity-weighted-trilinear",
            Kernel::Sample(Separate, Nearest) => "separate-nearest",
            Kernel::Sample(Separate, Trilinear) => "separate-trilinear",
            Kernel::Sample(Preweighted, Nearest) => "preweighted-nearest",
            Kernel::Sample(Preweighted, Trilinear) => "preweighted-trilinear",
            Kernel::Composite => "composite-front-to-back",
            Kernel::Correction => "opacity-correction",
            Kernel::Downsample => "downsample-opacity-based",
        }
    }

    /// The kernel of a command-line name.
    ///
    /// # Errors
    /// [`VectorError::UnknownKernel`] for any other name.
    pub fn parse(name: &str) -> Result<Self, VectorError> {
        Self::ALL
            .into_iter()
            .find(|k| k.name() == name)
            .ok_or_else(|| VectorError::UnknownKernel(name.to_string()))
    }
}

/// What went wrong while generating, writing or reading vectors.
#[derive(Debug)]
#[non_exhaustive]
pub enum VectorError {
    /// The kernel name is not one of [`Kernel::ALL`].
    UnknownKernel(String),
    /// `count` was 0.
    ZeroCount,
    /// `frac_bits` outside `4..=12`.
    FracBits(u32),
    /// A core constructor rejected a generated input (a generator bug).
    Core(volsample::Error),
    /// The output directory or a file in it could not be created or written.
    Write {
        /// The path.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// A vector file could not be read.
    Read {
        /// The path.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// A vector file or manifest is malformed.
    Parse {
        /// The file.
        path: PathBuf,
        /// What is wrong (with the line number where there is one).
        message: String,
    },
}

impl fmt::Display for VectorError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            VectorError::UnknownKernel(k) => {
                let names: Vec<_> = Kernel::ALL.iter().map(|k| k.name()).collect();
                write!(f, "unknown kernel '{k}' (one of: {})", names.join(", "))
            }
            VectorError::ZeroCount => write!(f, "--count must be at least 1"),
            VectorError::FracBits(b) => {
                write!(f, "--frac-bits {b} is outside 4..=12")
            }
            VectorError::Core(e) => write!(f, "core kernel rejected a generated input: {e:?}"),
            VectorError::Write { path, source } => {
                write!(f, "cannot write {}: {source}", path.display())
            }
            VectorError::Read { path, source } => {
                write!(f, "cannot read {}: {source}", path.display())
            }
            VectorError::Parse { path, message } => write!(f, "{}: {message}", path.display()),
        }
    }
}

impl std::error::Error for VectorError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            VectorError::Write { source, .. } | VectorError::Read { source, .. } => Some(source),
            _ => None,
        }
    }
}

impl From<volsample::Error> for VectorError {
    fn from(e: volsample::Error) -> Self {
        VectorError::Core(e)
    }
}

/// A validated request: kernel, count, seed and fractional position bits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Spec {
    kernel: Kernel,
    count: usize,
    seed: u64,
    frac_bits: u32,
}

impl Spec {
    /// Validates a request.
    ///
    /// # Errors
    /// [`VectorError::UnknownKernel`], [`VectorError::ZeroCount`], [`VectorError::FracBits`].
    pub fn new(kernel: &str, count: usize, seed: u64, frac_bits: u32) -> Result<Self, VectorError> {
        let kernel = Kernel::parse(kernel)?;
        if count == 0 {
            return Err(VectorError::ZeroCount);
        }
        if !(4..=12).contains(&frac_bits) {
            return Err(VectorError::FracBits(frac_bits));
        }
        Ok(Self {
            kernel,
            count,
            seed,
            frac_bits,
        })
    }

    /// The kernel.
    pub fn kernel(&self) -> Kernel {
        self.kernel
    }
    /// Number of vectors.
    pub fn count(&self) -> usize {
        self.count
    }
    /// The seed.
    pub fn seed(&self) -> u64 {
        self.seed
    }
    /// Fractional position bits `F` (sampling kernels only).
    pub fn frac_bits(&self) -> u32 {
        self.frac_bits
    }
}

/// A U8.8 sample as raw `[r, g, b, a]` (`C̃` and `α`, `ONE` = opacity 1).
pub type Raw = [u16; 4];

/// The inputs of one vector.
// The 64-voxel downsampling tap set makes one variant 260 bytes; boxing it would cost more
// code than the few MB a 10,000-vector set takes on the host.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Case {
    /// A tap set: voxel bytes `[r, g, b, a]` (straight, or associated for `preweighted`) and
    /// the fractions `[fx, fy, fz]` (`F` bits each).
    Sample {
        /// Voxel `i` at `(i & 1, (i >> 1) & 1, i >> 2)`.
        voxels: [[u8; 4]; 8],
        /// Fractions in units of `2^−F` voxel.
        frac: [u32; 3],
    },
    /// One compositing step: `acc` is in front of `s`.
    Composite {
        /// The accumulator.
        acc: Raw,
        /// The new sample.
        s: Raw,
    },
    /// One opacity correction with ratio `d/d′`.
    Correction {
        /// `d/d′`.
        ratio: f32,
        /// The sample.
        s: Raw,
    },
    /// One coarse voxel of opacity-based downsampling.
    Downsample {
        /// Associated voxel bytes `[C̃r, C̃g, C̃b, α]`; tap `t = i + 4j + 16k`.
        taps: [[u8; 4]; 64],
        /// The outer filter tap `a` (Q0.16, at most `2^15`).
        a_raw: u32,
    },
}

/// The downsampled coarse voxel of a 64-voxel tap set (see the module docs).
fn downsample_kernel(taps: &[[u8; 4]; 64], a_raw: u32) -> Result<Raw, VectorError> {
    let filter = IntFilter4::from_raw(a_raw)?;
    let mut src = [AssociatedU8([0; 4]); 216];
    for (t, v) in taps.iter().enumerate() {
        let (i, j, k) = (t % 4, (t / 4) % 4, t / 16);
        if let Some(d) = src.get_mut((1 + i) + 6 * ((1 + j) + 6 * (1 + k))) {
            *d = AssociatedU8(*v);
        }
    }
    let mut dst = [AssociatedU8([0; 4]); 27];
    downsample_level_int(IntOpacityBased, filter, &src, [6, 6, 6], &mut dst)?;
    Ok(dst[1 + 3 * (1 + 3)].0.map(u16::from))
}

fn sample_from(s: IntSample) -> Raw {
    let [r, g, b] = s.c();
    [r, g, b, s.a()]
}

fn int_sample(s: Raw) -> Result<IntSample, VectorError> {
    Ok(IntSample::new([s[0], s[1], s[2]], s[3])?)
}

fn run_sampler<V: Voxel, M: IntMode<V>, Fl: IntFilter, const F: u32>(
    voxels: &[V; 8],
    mode: M,
    filter: Fl,
    frac: [u32; 3],
) -> Result<Raw, VectorError> {
    let vol = Volume::new(voxels, [2, 2, 2])?;
    let pos = IntPos::<F>::new([0; 3], frac)?;
    Ok(sample_from(IntSampler::new(vol, mode, filter).sample(pos)))
}

fn sample_kernel<const F: u32>(
    mode: SampleMode,
    filter: SampleFilter,
    voxels: &[[u8; 4]; 8],
    frac: [u32; 3],
) -> Result<Raw, VectorError> {
    let straight = voxels.map(StraightU8);
    let assoc = voxels.map(AssociatedU8);
    match (mode, filter) {
        (SampleMode::OpacityWeighted, SampleFilter::Nearest) => {
            run_sampler::<_, _, _, F>(&straight, OpacityWeighted, Nearest, frac)
        }
        (SampleMode::OpacityWeighted, SampleFilter::Trilinear) => {
            run_sampler::<_, _, _, F>(&straight, OpacityWeighted, Trilinear::new(), frac)
        }
        (SampleMode::Separate, SampleFilter::Nearest) => {
            run_sampler::<_, _, _, F>(&straight, Separate, Nearest, frac)
        }
        (SampleMode::Separate, SampleFilter::Trilinear) => {
            run_sampler::<_, _, _, F>(&straight, Separate, Trilinear::new(), frac)
        }
        (SampleMode::Preweighted, SampleFilter::Nearest) => {
            run_sampler::<_, _, _, F>(&assoc, Preweighted, Nearest, frac)
        }
        (SampleMode::Preweighted, SampleFilter::Trilinear) => {
            run_sampler::<_, _, _, F>(&assoc, Preweighted, Trilinear::new(), frac)
        }
    }
}

/// The expected output of one vector, computed by the core kernel (the golden model).
///
/// # Errors
/// [`VectorError::FracBits`] for `F` outside `4..=12`; [`VectorError::Core`] if the core
/// rejects an input (a voxel with `C̃ > α` for `preweighted`, a sample with `C̃ > α` or
/// `α > ONE`, a non-positive ratio); [`VectorError::Parse`]-free otherwise.
pub fn expected(spec: &Spec, case: &Case) -> Result<Raw, VectorError> {
    match (spec.kernel, case) {
        (Kernel::Sample(mode, filter), Case::Sample { voxels, frac }) => {
            let (m, fl) = (mode, filter);
            match spec.frac_bits {
                4 => sample_kernel::<4>(m, fl, voxels, *frac),
                5 => sample_kernel::<5>(m, fl, voxels, *frac),
                6 => sample_kernel::<6>(m, fl, voxels, *frac),
                7 => sample_kernel::<7>(m, fl, voxels, *frac),
                8 => sample_kernel::<8>(m, fl, voxels, *frac),
                9 => sample_kernel::<9>(m, fl, voxels, *frac),
                10 => sample_kernel::<10>(m, fl, voxels, *frac),
                11 => sample_kernel::<11>(m, fl, voxels, *frac),
                12 => sample_kernel::<12>(m, fl, voxels, *frac),
                b => Err(VectorError::FracBits(b)),
            }
        }
        (Kernel::Composite, Case::Composite { acc, s }) => Ok(sample_from(front_to_back(
            int_sample(*acc)?,
            int_sample(*s)?,
        ))),
        (Kernel::Correction, Case::Correction { ratio, s }) => {
            let corr = IntCorrection::new(*ratio)?;
            Ok(sample_from(corr.apply(int_sample(*s)?)))
        }
        (Kernel::Downsample, Case::Downsample { taps, a_raw }) => downsample_kernel(taps, *a_raw),
        (k, c) => Err(VectorError::Parse {
            path: PathBuf::new(),
            message: format!("case {c:?} does not belong to kernel {}", k.name()),
        }),
    }
}

/// The corner cases of a kernel, in order (see the module docs).
pub fn corner_cases(spec: &Spec) -> Vec<Case> {
    let f = spec.frac_bits;
    match spec.kernel {
        Kernel::Sample(mode, _) => {
            let m = (1u32 << f) - 1;
            let h = 1u32 << (f - 1);
            let fracs = [
                [0, 0, 0],
                [m, m, m],
                [h, h, h],
                [h - 1, h - 1, h - 1],
                [0, m, h],
                [m, h, 0],
            ];
            let equal = |v: [u8; 4]| [v; 8];
            let distinct: [[u8; 4]; 8] =
                std::array::from_fn(|i| [(i * 31) as u8, 255 - (i * 29) as u8, (i * 17) as u8, 0]);
            let with_a = |a: fn(usize) -> u8| {
                let mut v = distinct;
                for (i, x) in v.iter_mut().enumerate() {
                    x[3] = a(i);
                }
                v
            };
            let sets: [[[u8; 4]; 8]; 9] = [
                equal([200, 100, 50, 0]),    // α = 0 everywhere
                equal([255, 255, 255, 255]), // every byte saturated
                equal([255, 128, 0, 1]),     // α_F = 1
                equal([37, 201, 99, 137]),   // all eight equal, mid opacity
                equal([0, 0, 0, 0]),         // all zero
                // Wittenbrink fig. 4 along x: opaque white next to transparent red.
                std::array::from_fn(|i| {
                    if i & 1 == 0 {
                        [255, 255, 255, 255]
                    } else {
                        [255, 0, 0, 0]
                    }
                }),
                with_a(|i| if i % 2 == 0 { 0 } else { 255 }),
                with_a(|_| 1),
                with_a(|i| if i == 7 { 255 } else { 0 }),
            ];
            let mut out = Vec::new();
            for set in sets {
                let set = if mode == SampleMode::Preweighted {
                    set.map(|[r, g, b, a]| {
                        [premultiply(r, a), premultiply(g, a), premultiply(b, a), a]
                    })
                } else {
                    set
                };
                for frac in fracs {
                    out.push(Case::Sample { voxels: set, frac });
                }
            }
            out
        }
        Kernel::Composite => {
            let accs: [Raw; 7] = [
                [0; 4],
                [ONE; 4],
                [ONE / 2, ONE / 4, 0, ONE / 2],
                [ONE - 1; 4],
                [1, 0, 1, 1],
                [256, 256, 0, 256],
                [100, 200, 300, 40000],
            ];
            let samples: [Raw; 7] = [
                [0; 4],
                [ONE; 4],
                [0, 0, 0, ONE],
                [256, 0, 256, 256],
                [1, 1, 1, 1],
                [ONE / 2, ONE / 4, 0, ONE / 2],
                [ONE - 1; 4],
            ];
            accs.iter()
                .flat_map(|&acc| samples.iter().map(move |&s| Case::Composite { acc, s }))
                .collect()
        }
        Kernel::Correction => {
            let ratios = [1.0f32, 0.5, 2.0, 0.25, 4.0, 1.0 / 4096.0, 16.0, 65536.0];
            let samples: [Raw; 9] = [
                [0; 4],
                [ONE; 4],
                [256; 4],
                [0, 0, 0, 256],
                [1, 1, 1, 1],
                [ONE - 1; 4],
                [PSI_LIMIT - 1, 0, 1000, PSI_LIMIT - 1],
                [PSI_LIMIT, 0, 1000, PSI_LIMIT],
                [ONE / 2, ONE / 4, 0, ONE / 2],
            ];
            ratios
                .iter()
                .flat_map(|&ratio| samples.iter().map(move |&s| Case::Correction { ratio, s }))
                .collect()
        }
        Kernel::Downsample => {
            let filters = [0u32, 8192, 13107, 16384, 32768];
            let straight: [[[u8; 4]; 64]; 7] = [
                [[200, 100, 50, 0]; 64],  // α = 0 everywhere
                [[255; 4]; 64],           // every byte saturated
                [[255, 128, 0, 1]; 64],   // α_F = 1
                [[37, 201, 99, 137]; 64], // all equal, mid opacity
                std::array::from_fn(|t| if t % 2 == 0 { [255; 4] } else { [255, 0, 0, 0] }),
                // One opaque voxel on an inner tap, one on an outer (corner) tap.
                std::array::from_fn(|t| {
                    if t == 21 || t == 63 {
                        [255, 64, 0, 255]
                    } else {
                        [0; 4]
                    }
                }),
                std::array::from_fn(|t| {
                    [
                        (t * 4) as u8,
                        255 - (t * 3) as u8,
                        (t * 7) as u8,
                        (t * 4 + 3) as u8,
                    ]
                }),
            ];
            let mut out = Vec::new();
            for set in straight {
                let taps = set.map(|[r, g, b, a]| {
                    [premultiply(r, a), premultiply(g, a), premultiply(b, a), a]
                });
                for a_raw in filters {
                    out.push(Case::Downsample { taps, a_raw });
                }
            }
            out
        }
    }
}

/// One random voxel as the sampling kernels draw it (see the module docs).
fn random_voxel(rng: &mut SplitMix64, associated: bool) -> [u8; 4] {
    let w = rng.next_u64();
    let mut b = [w as u8, (w >> 8) as u8, (w >> 16) as u8, (w >> 24) as u8];
    match (w >> 32) & 7 {
        0 => b[3] = 0,
        1 => b[3] = 255,
        2 => b[3] = 1,
        3 => b = [255; 4],
        _ => {}
    }
    if associated {
        for k in 0..3 {
            b[k] = premultiply(b[k], b[3]);
        }
    }
    b
}

fn random_sample(rng: &mut SplitMix64) -> Raw {
    let w = rng.next_u64();
    let a = match w >> 61 {
        0 => 0,
        1 => u64::from(ONE),
        2 => 256 * ((w >> 8) & 255),
        _ => (w & 0xFFFF_FFFF) % (u64::from(ONE) + 1),
    };
    let mut c = [0u16; 4];
    for x in c.iter_mut().take(3) {
        *x = (rng.next_u64() % (a + 1)) as u16;
    }
    c[3] = a as u16;
    c
}

fn random_case(spec: &Spec, rng: &mut SplitMix64) -> Case {
    match spec.kernel {
        Kernel::Sample(mode, _) => {
            let mut voxels = [[0u8; 4]; 8];
            for v in voxels.iter_mut() {
                *v = random_voxel(rng, mode == SampleMode::Preweighted);
            }
            let m = (1u64 << spec.frac_bits) - 1;
            let w = rng.next_u64();
            let mut frac = [w & m, (w >> 16) & m, (w >> 32) & m].map(|x| x as u32);
            match (w >> 48) & 7 {
                0 => frac = [0; 3],
                1 => frac = [m as u32; 3],
                2 => frac = [1 << (spec.frac_bits - 1); 3],
                _ => {}
            }
            Case::Sample { voxels, frac }
        }
        Kernel::Composite => {
            let acc = random_sample(rng);
            let s = random_sample(rng);
            Case::Composite { acc, s }
        }
        Kernel::Correction => {
            let k = 1 + rng.next_u64() % 65536;
            let ratio = k as f32 / 4096.0;
            let s = random_sample(rng);
            Case::Correction { ratio, s }
        }
        Kernel::Downsample => {
            let mut taps = [[0u8; 4]; 64];
            for v in taps.iter_mut() {
                *v = random_voxel(rng, true);
            }
            let w = rng.next_u64();
            let a_raw = match w >> 61 {
                0 => 0,
                1 => 8192,
                2 => 13107,
                3 => 16384,
                4 => 32768,
                _ => ((w & 0xFFFF) % 32769) as u32,
            };
            Case::Downsample { taps, a_raw }
        }
    }
}

/// The `count` input cases of a request: corner cases first, then random ones.
pub fn generate(spec: &Spec) -> Vec<Case> {
    let mut cases = corner_cases(spec);
    cases.truncate(spec.count);
    let mut rng = SplitMix64::new(spec.seed);
    while cases.len() < spec.count {
        cases.push(random_case(spec, &mut rng));
    }
    cases
}

/// Number of corner cases of a request (at most its count).
pub fn corner_count(spec: &Spec) -> usize {
    corner_cases(spec).len().min(spec.count)
}

/// One field of a packed word.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Field {
    /// Name (`v3_a`, `fx`, `acc_r`, …).
    pub name: String,
    /// Offset of the least significant bit (bit 0 is the word's least significant bit).
    pub offset: u32,
    /// Width in bits.
    pub width: u32,
    /// Fractional bits of the value.
    pub frac_bits: u32,
    /// Format and meaning.
    pub meaning: String,
}

/// The fields of a word, packed from bit 0 upwards in order.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Layout {
    /// The fields, lowest offset first.
    pub fields: Vec<Field>,
}

impl Layout {
    fn push(&mut self, name: String, width: u32, frac_bits: u32, meaning: &str) {
        let offset = self.width();
        self.fields.push(Field {
            name,
            offset,
            width,
            frac_bits,
            meaning: meaning.to_string(),
        });
    }

    /// Total width in bits.
    pub fn width(&self) -> u32 {
        self.fields.last().map_or(0, |f| f.offset + f.width)
    }

    /// Hex digits per line (`⌈width/4⌉`).
    pub fn hex_digits(&self) -> usize {
        self.width().div_ceil(4) as usize
    }

    /// Packs one value per field (each masked to its width) into a word.
    pub fn pack(&self, values: &[u64]) -> Word {
        let mut w = Word::zero(self.width());
        for (f, &v) in self.fields.iter().zip(values) {
            w.set(f.offset, f.width, v);
        }
        w
    }

    /// The value of each field of a word.
    pub fn unpack(&self, w: &Word) -> Vec<u64> {
        self.fields
            .iter()
            .map(|f| w.get(f.offset, f.width))
            .collect()
    }
}

fn push_u88(l: &mut Layout, prefix: &str) {
    for ch in ["r", "g", "b"] {
        l.push(
            format!("{prefix}{ch}"),
            16,
            8,
            "U8.8 associated color C̃ (raw/256 u8 levels; ≤ α)",
        );
    }
    l.push(
        format!("{prefix}a"),
        16,
        8,
        "U8.8 opacity α (ONE = 65280 is opaque)",
    );
}

/// The layout of an input word.
pub fn input_layout(spec: &Spec) -> Layout {
    let mut l = Layout::default();
    match spec.kernel {
        Kernel::Sample(mode, _) => {
            let color = if mode == SampleMode::Preweighted {
                "u8 premultiplied color C̃ (≤ α)"
            } else {
                "u8 straight color C"
            };
            for i in 0..8 {
                for ch in ["r", "g", "b"] {
                    l.push(format!("v{i}_{ch}"), 8, 0, color);
                }
                l.push(format!("v{i}_a"), 8, 0, "u8 opacity α (255 is opaque)");
            }
            for ax in ["fx", "fy", "fz"] {
                l.push(
                    ax.to_string(),
                    spec.frac_bits,
                    spec.frac_bits,
                    "fraction of the position within the tap set, raw/2^F voxel",
                );
            }
        }
        Kernel::Composite => {
            push_u88(&mut l, "acc_");
            push_u88(&mut l, "s_");
        }
        Kernel::Correction => {
            push_u88(&mut l, "s_");
            l.push(
                "ratio_raw".into(),
                64,
                32,
                "IntRatio: ⌊(d/d′)·2^32 + ½⌋ (round half up)",
            );
            l.push(
                "ratio_f32".into(),
                32,
                0,
                "the ratio d/d′ as IEEE-754 f32 bits (informational; ratio_raw is derived from it)",
            );
        }
        Kernel::Downsample => {
            for t in 0..64 {
                for ch in ["r", "g", "b"] {
                    l.push(format!("t{t}_{ch}"), 8, 0, "u8 premultiplied color C̃ (≤ α)");
                }
                l.push(format!("t{t}_a"), 8, 0, "u8 opacity α (255 is opaque)");
            }
            l.push(
                "a_raw".into(),
                16,
                16,
                "outer filter tap a (Q0.16, ≤ 2^15); taps (a, 2^15 − a, 2^15 − a, a)",
            );
        }
    }
    l
}

/// The layout of an output word: a U8.8 sample, or for `downsample-opacity-based` a `u8`
/// associated voxel.
pub fn output_layout(spec: &Spec) -> Layout {
    let mut l = Layout::default();
    if spec.kernel == Kernel::Downsample {
        for ch in ["r", "g", "b"] {
            l.push(ch.to_string(), 8, 0, "u8 premultiplied color C̃′ (≤ α′)");
        }
        l.push("a".into(), 8, 0, "u8 opacity α′ (255 is opaque)");
    } else {
        push_u88(&mut l, "");
    }
    l
}

fn input_values(case: &Case) -> Result<Vec<u64>, VectorError> {
    Ok(match case {
        Case::Sample { voxels, frac } => voxels
            .iter()
            .flatten()
            .map(|&b| u64::from(b))
            .chain(frac.iter().map(|&f| u64::from(f)))
            .collect(),
        Case::Composite { acc, s } => acc.iter().chain(s).map(|&x| u64::from(x)).collect(),
        Case::Correction { ratio, s } => {
            let r = volsample::fixed_point::IntRatio::new(*ratio)?.raw();
            let mut v: Vec<u64> = s.iter().map(|&x| u64::from(x)).collect();
            v.push(r);
            v.push(u64::from(ratio.to_bits()));
            v
        }
        Case::Downsample { taps, a_raw } => taps
            .iter()
            .flatten()
            .map(|&b| u64::from(b))
            .chain([u64::from(*a_raw)])
            .collect(),
    })
}

fn case_from_values(kernel: Kernel, v: &[u64]) -> Option<Case> {
    let raw4 = |s: &[u64]| -> Option<Raw> {
        Some([
            u16::try_from(*s.first()?).ok()?,
            u16::try_from(*s.get(1)?).ok()?,
            u16::try_from(*s.get(2)?).ok()?,
            u16::try_from(*s.get(3)?).ok()?,
        ])
    };
    match kernel {
        Kernel::Sample(..) => {
            let mut voxels = [[0u8; 4]; 8];
            for (i, b) in voxels.iter_mut().flatten().enumerate() {
                *b = u8::try_from(*v.get(i)?).ok()?;
            }
            let frac = [
                u32::try_from(*v.get(32)?).ok()?,
                u32::try_from(*v.get(33)?).ok()?,
                u32::try_from(*v.get(34)?).ok()?,
            ];
            Some(Case::Sample { voxels, frac })
        }
        Kernel::Composite => Some(Case::Composite {
            acc: raw4(v.get(0..4)?)?,
            s: raw4(v.get(4..8)?)?,
        }),
        Kernel::Correction => Some(Case::Correction {
            s: raw4(v.get(0..4)?)?,
            ratio: f32::from_bits(u32::try_from(*v.get(5)?).ok()?),
        }),
        Kernel::Downsample => {
            let mut taps = [[0u8; 4]; 64];
            for (i, b) in taps.iter_mut().flatten().enumerate() {
                *b = u8::try_from(*v.get(i)?).ok()?;
            }
            Some(Case::Downsample {
                taps,
                a_raw: u32::try_from(*v.get(256)?).ok()?,
            })
        }
    }
}

/// A word of any width, as little-endian 64-bit limbs.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Word {
    limbs: Vec<u64>,
}

impl Word {
    /// A zero word of `width` bits.
    pub fn zero(width: u32) -> Self {
        Self {
            limbs: vec![0; width.div_ceil(64).max(1) as usize],
        }
    }

    /// Sets bits `offset..offset + width` (`width ≤ 64`) to `value` (masked).
    pub fn set(&mut self, offset: u32, width: u32, value: u64) {
        for b in 0..width.min(64) {
            let bit = (value >> b) & 1;
            let pos = offset + b;
            if let Some(l) = self.limbs.get_mut((pos / 64) as usize) {
                *l = (*l & !(1 << (pos % 64))) | (bit << (pos % 64));
            }
        }
    }

    /// Bits `offset..offset + width` (`width ≤ 64`).
    pub fn get(&self, offset: u32, width: u32) -> u64 {
        (0..width.min(64)).fold(0, |acc, b| {
            let pos = offset + b;
            let bit = self
                .limbs
                .get((pos / 64) as usize)
                .map_or(0, |l| (l >> (pos % 64)) & 1);
            acc | (bit << b)
        })
    }

    /// `digits` lowercase hex digits, most significant first.
    pub fn to_hex(&self, digits: usize) -> String {
        (0..digits)
            .rev()
            .map(|d| {
                let nib = self.get(d as u32 * 4, 4) as u32;
                char::from_digit(nib, 16).unwrap_or('0')
            })
            .collect()
    }

    /// Parses exactly `digits` hex digits into a word of `width` bits; `None` if the text is
    /// not such a word or sets a bit at or above `width`.
    pub fn from_hex(text: &str, digits: usize, width: u32) -> Option<Self> {
        if text.len() != digits {
            return None;
        }
        let mut w = Word::zero(digits as u32 * 4);
        for (d, c) in text.chars().rev().enumerate() {
            w.set(d as u32 * 4, 4, u64::from(c.to_digit(16)?));
        }
        let top = digits as u32 * 4;
        if (width..top).any(|b| w.get(b, 1) != 0) {
            return None;
        }
        w.limbs.truncate(width.div_ceil(64).max(1) as usize);
        Some(w)
    }
}

/// The text of a `.hex` file: one word per line.
pub fn hex_text(layout: &Layout, words: &[Word]) -> String {
    let d = layout.hex_digits();
    let mut s = String::with_capacity(words.len() * (d + 1));
    for w in words {
        s.push_str(&w.to_hex(d));
        s.push('\n');
    }
    s
}

/// Reads a `.hex` file written with `layout` (blank lines and `//` comments skipped).
///
/// # Errors
/// [`VectorError::Read`] if it cannot be read; [`VectorError::Parse`] for a line that is not one
/// word of the layout's width.
pub fn read_hex(path: &Path, layout: &Layout) -> Result<Vec<Word>, VectorError> {
    let text = std::fs::read_to_string(path).map_err(|source| VectorError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    let mut words = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let line = line.split("//").next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let w = Word::from_hex(line, layout.hex_digits(), layout.width()).ok_or_else(|| {
            VectorError::Parse {
                path: path.to_path_buf(),
                message: format!(
                    "line {}: expected {} hex digits of a {}-bit word, found '{line}'",
                    n + 1,
                    layout.hex_digits(),
                    layout.width()
                ),
            }
        })?;
        words.push(w);
    }
    Ok(words)
}

fn layout_json(l: &Layout, file: &str) -> Value {
    json!({
        "file": file,
        "word_bits": l.width(),
        "hex_digits": l.hex_digits(),
        "packing": "fields from bit 0 (least significant) upwards; one word per line, most significant hex digit first",
        "fields": l.fields.iter().map(|f| json!({
            "name": f.name,
            "offset": f.offset,
            "width": f.width,
            "frac_bits": f.frac_bits,
            "signed": false,
            "meaning": f.meaning,
        })).collect::<Vec<_>>(),
    })
}

fn rounding_json(spec: &Spec) -> Value {
    let s = 3 * spec.frac_bits;
    match spec.kernel {
        Kernel::Sample(mode, filter) => {
            let weights = match filter {
                SampleFilter::Nearest => json!({
                    "rule": "round half up",
                    "formula": "nearest voxel per axis: ⌊(index·2^F + f)/2^F + ½⌋, i.e. corner bit = (f ≥ 2^(F−1)); weight 1, shift s = 0",
                }),
                SampleFilter::Trilinear => json!({
                    "rule": "exact",
                    "formula": format!("w_i = px·py·pz with p = 2^F − f for the low corner and p = f for the high one (corner i at (i&1, (i>>1)&1, i>>2)); Σ w_i = 2^s, s = 3F = {s}"),
                }),
            };
            let outputs = match mode {
                SampleMode::OpacityWeighted => json!([
                    {"output": "a", "rule": "round half up", "formula": "S_α = Σ w_i·α_i; a = ⌊256·S_α/2^s + ½⌋"},
                    {"output": "r, g, b", "rule": "round half up", "formula": "S_c = Σ (w_i·α_i)·C_i; c = ⌊256·S_c/(255·2^s) + ½⌋"},
                ]),
                SampleMode::Separate => json!([
                    {"output": "a", "rule": "round half up", "formula": "a = ⌊256·Σ w_i·α_i/2^s + ½⌋"},
                    {"output": "(straight C, internal)", "rule": "round half up", "formula": "C = ⌊256·Σ w_i·C_i/2^s + ½⌋"},
                    {"output": "r, g, b", "rule": "round half up", "formula": "c = ⌊a·C/65280 + ½⌋ = (a·C + 32640) div 65280"},
                ]),
                SampleMode::Preweighted => json!([
                    {"output": "a", "rule": "round half up", "formula": "a = ⌊256·Σ w_i·α_i/2^s + ½⌋"},
                    {"output": "r, g, b", "rule": "round half up", "formula": "c = ⌊256·Σ w_i·min(C̃_i, α_i)/2^s + ½⌋"},
                ]),
            };
            json!({"weights": weights, "outputs": outputs})
        }
        Kernel::Composite => json!({"outputs": [
            {"output": "r, g, b, a", "rule": "round half up",
             "formula": "T = 65280 − acc_a; x = acc_x + ⌊T·s_x/65280 + ½⌋ = acc_x + (T·s_x + 32640) div 65280"},
        ]}),
        Kernel::Downsample => json!({"outputs": [
            {"output": "(filter sums, internal)", "rule": "exact",
             "formula": "S_x = Σ w_i·w_j·w_k·x_t over the 64 taps (x = min(C̃, α) per color, α), w = (a, 2^15 − a, 2^15 − a, a), Σ = 2^48 per unit"},
            {"output": "(guarded means, internal)", "rule": "round half up",
             "formula": "ᾱ_g = ⌊S_α/2^40 + ½⌋, C̄_g = min(⌊S_c/2^40 + ½⌋, ᾱ_g) (8 guard bits)"},
            {"output": "a", "rule": "round half up",
             "formula": "G = 2·256·255 − ᾱ_g; α′ = ⌊ᾱ_g·G/(2^16·255) + ½⌋ (α′ = 1 − (1 − ᾱ)²)"},
            {"output": "r, g, b", "rule": "round half up", "formula": "C̃′ = ⌊C̄_g·G/(2^16·255) + ½⌋"},
        ]}),
        Kernel::Correction => json!({"outputs": [
            {"output": "a", "rule": "round half up, truncate, saturate",
             "formula": "α_d = 1 − e^(−r·L), L = −ln(1 − α) from the ψ (α < 2^15) or ln m tables; y = r·L to 28 fractional bits (round half up, saturate at 16); α_d = ⌊65280·y·φ(y) + ½⌋ (y < 1) or ⌊65280·(1 − e^(−y)) + ½⌋ (1 ≤ y < 16) or 65280; α = 0 → 0, α = 65280 → 65280. Exact arithmetic: volsample::fixed_point::correction module docs"},
            {"output": "r, g, b", "rule": "round half up", "formula": "c = ⌊C̃·α_d/α + ½⌋ (0 when α = 0)"},
        ]}),
    }
}

fn generator_json(spec: &Spec) -> Value {
    let draws = match spec.kernel {
        Kernel::Sample(SampleMode::Preweighted, _) => "per voxel i=0..8: w=next(); r,g,b,a = bytes 0..3 of w; k=(w>>32)&7: 0→a=0, 1→a=255, 2→a=1, 3→r=g=b=a=255; then each color byte c→⌊(2·c·a+255)/510⌋ (premultiply, round half up). Then w=next(); m=2^F−1; fx=w&m, fy=(w>>16)&m, fz=(w>>32)&m; k=(w>>48)&7: 0→all 0, 1→all m, 2→all 2^(F−1)",
        Kernel::Sample(..) => "per voxel i=0..8: w=next(); r,g,b,a = bytes 0..3 of w; k=(w>>32)&7: 0→a=0, 1→a=255, 2→a=1, 3→r=g=b=a=255. Then w=next(); m=2^F−1; fx=w&m, fy=(w>>16)&m, fz=(w>>32)&m; k=(w>>48)&7: 0→all 0, 1→all m, 2→all 2^(F−1)",
        Kernel::Composite => "acc, then s, each a U8.8 sample: w=next(); k=w>>61: 0→a=0, 1→a=65280, 2→a=256·((w>>8)&255), else a=(w&0xFFFFFFFF) mod 65281; then r,g,b each next() mod (a+1)",
        Kernel::Downsample => "per tap t=0..64 as a preweighted sampling voxel: w=next(); r,g,b,a = bytes 0..3 of w; k=(w>>32)&7: 0→a=0, 1→a=255, 2→a=1, 3→r=g=b=a=255; each color byte c→⌊(2·c·a+255)/510⌋. Then w=next(); k=w>>61: a_raw = 0, 8192, 13107, 16384, 32768 for k=0..4, else (w&0xFFFF) mod 32769",
        Kernel::Correction => "w=next(); ratio=(1 + w mod 65536)/4096 (exact f32); then s as a U8.8 sample: w=next(); k=w>>61: 0→a=0, 1→a=65280, 2→a=256·((w>>8)&255), else a=(w&0xFFFFFFFF) mod 65281; then r,g,b each next() mod (a+1)",
    };
    json!({
        "name": "volsample vectors",
        "version": GENERATOR_VERSION,
        "prng": "SplitMix64: state += 0x9E3779B97F4A7C15; z = state; z = (z ^ (z >> 30))·0xBF58476D1CE4E5B9; z = (z ^ (z >> 27))·0x94D049BB133111EB; next() = z ^ (z >> 31) (wrapping u64)",
        "seeding": "state = seed before the first draw; corner cases come first and draw nothing",
        "random_draws": draws,
    })
}

/// The manifest of a request.
pub fn manifest(spec: &Spec) -> Value {
    let what = match spec.kernel {
        Kernel::Sample(..) => "one sample of a 2×2×2 tap set: the voxels v0..v7 of a 2×2×2 volume (voxel i at (i&1, (i>>1)&1, i>>2)) sampled at IntPos::<F>::new([0,0,0], [fx,fy,fz])",
        Kernel::Composite => "one front-to-back step: volsample::fixed_point::front_to_back(acc, s), acc in front",
        Kernel::Downsample => "one coarse voxel of volsample::downsample::integer::downsample_level_int(IntOpacityBased, IntFilter4::from_raw(a_raw), …) over AssociatedU8: taps t = i + 4j + 16k are fine voxels (2X−1+i, 2Y−1+j, 2Z−1+k); computed as coarse voxel (1,1,1) of a 6×6×6 volume (no edge clamping)",
        Kernel::Correction => "IntCorrection::new(ratio_f32).apply(s): α_d = 1 − (1 − α)^r, C̃_d = C̃·α_d/α, table driven; tables in table_*.hex",
    };
    let mut m = json!({
        "kernel": spec.kernel.name(),
        "description": what,
        "count": spec.count,
        "corner_cases": corner_count(spec),
        "seed": spec.seed,
        "frac_bits": spec.frac_bits,
        "frac_bits_note": "F, the fractional position bits of the sampling kernels (each field also states its own frac_bits)",
        "one": ONE,
        "generator": generator_json(spec),
        "rounding_rules": {
            "round half up": "⌊x + ½⌋ of the exact quotient (the paper's Int(x + 0.5))",
            "truncate": "⌊x⌋",
            "saturate": "clamp to the largest value of the format",
        },
        "rounding": rounding_json(spec),
        "inputs": layout_json(&input_layout(spec), INPUTS_FILE),
        "expected": layout_json(&output_layout(spec), EXPECTED_FILE),
    });
    if spec.kernel == Kernel::Correction {
        m["tables"] = json!(correction_tables()
            .iter()
            .map(|t| json!({"file": t.file, "entries": t.values.len(), "word_bits": t.bits, "hex_digits": t.bits.div_ceil(4), "meaning": t.meaning}))
            .collect::<Vec<_>>());
    }
    m
}

/// One lookup table of the opacity correction, as written to `table_*.hex`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TableFile {
    /// File name.
    pub file: &'static str,
    /// Entry width in bits.
    pub bits: u32,
    /// The entries.
    pub values: Vec<u64>,
    /// Definition.
    pub meaning: &'static str,
}

/// The correction tables (independent of the ratio).
pub fn correction_tables() -> Vec<TableFile> {
    // Any valid ratio: the tables do not depend on it.
    let Ok(c) = IntCorrection::new(1.0) else {
        return Vec::new();
    };
    let t = c.exp_tables();
    vec![
        TableFile {
            file: "table_psi.hex",
            bits: 32,
            values: c.psi_table().iter().map(|&x| u64::from(x)).collect(),
            meaning: "G[j] = ⌊2^47·ψ(128·j/65280)/65280 + ½⌋, ψ(α) = −ln(1 − α)/α, j = 0..256",
        },
        TableFile {
            file: "table_ln_m.hex",
            bits: 32,
            values: c.ln_table().iter().map(|&x| u64::from(x)).collect(),
            meaning: "Λ[j] = ⌊2^32·ln(1 + j/256) + ½⌋, j = 0..256",
        },
        TableFile {
            file: "table_ln_top.hex",
            bits: 44,
            values: c.ln_top().to_vec(),
            meaning: "K[e] = ⌊2^39·ln(65280/2^e) + ½⌋, e = 0..14",
        },
        TableFile {
            file: "table_phi.hex",
            bits: 32,
            values: t.phi().iter().map(|&x| u64::from(x)).collect(),
            meaning: "⌊2^31·φ(j/256) + ½⌋, φ(x) = (1 − e^(−x))/x, j = 0..256",
        },
        TableFile {
            file: "table_exp.hex",
            bits: 32,
            values: t.exp().iter().map(|&x| u64::from(x)).collect(),
            meaning: "⌊2^31·e^(−j/256) + ½⌋, j = 0..256",
        },
        TableFile {
            file: "table_exp_int.hex",
            bits: 32,
            values: t.exp_int().iter().map(|&x| u64::from(x)).collect(),
            meaning: "⌊2^32·e^(−n) + ½⌋, n = 1..15 (index n − 1)",
        },
    ]
}

/// A generated vector set.
#[derive(Debug, Clone, PartialEq)]
pub struct VectorSet {
    /// The request.
    pub spec: Spec,
    /// The inputs.
    pub cases: Vec<Case>,
    /// The expected outputs (from the core kernels).
    pub expected: Vec<Raw>,
}

/// Generates the vectors of a request and their expected outputs.
///
/// # Errors
/// [`VectorError::Core`] if a core constructor rejects a generated input (a generator bug).
pub fn build(spec: &Spec) -> Result<VectorSet, VectorError> {
    let cases = generate(spec);
    let expected = cases
        .iter()
        .map(|c| expected(spec, c))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(VectorSet {
        spec: *spec,
        cases,
        expected,
    })
}

fn write_file(path: PathBuf, text: &str) -> Result<(), VectorError> {
    std::fs::write(&path, text).map_err(|source| VectorError::Write { path, source })
}

/// Writes a vector set into `dir` (created if missing): `inputs.hex`, `expected.hex`,
/// `manifest.json` and, for the correction, its tables.
///
/// # Errors
/// [`VectorError::Write`] naming the path that could not be created or written.
pub fn write(set: &VectorSet, dir: &Path) -> Result<(), VectorError> {
    std::fs::create_dir_all(dir).map_err(|source| VectorError::Write {
        path: dir.to_path_buf(),
        source,
    })?;
    let il = input_layout(&set.spec);
    let inputs = set
        .cases
        .iter()
        .map(|c| Ok(il.pack(&input_values(c)?)))
        .collect::<Result<Vec<_>, VectorError>>()?;
    let ol = output_layout(&set.spec);
    let outputs: Vec<Word> = set
        .expected
        .iter()
        .map(|e| ol.pack(&e.map(u64::from)))
        .collect();
    write_file(dir.join(INPUTS_FILE), &hex_text(&il, &inputs))?;
    write_file(dir.join(EXPECTED_FILE), &hex_text(&ol, &outputs))?;
    if set.spec.kernel == Kernel::Correction {
        for t in correction_tables() {
            let l = Layout {
                fields: vec![Field {
                    name: "entry".into(),
                    offset: 0,
                    width: t.bits,
                    frac_bits: 0,
                    meaning: String::new(),
                }],
            };
            let words: Vec<Word> = t.values.iter().map(|&v| l.pack(&[v])).collect();
            write_file(dir.join(t.file), &hex_text(&l, &words))?;
        }
    }
    let mut text = serde_json::to_string_pretty(&manifest(&set.spec)).unwrap_or_default();
    text.push('\n');
    write_file(dir.join(MANIFEST_FILE), &text)
}

fn parse_err(path: &Path, message: String) -> VectorError {
    VectorError::Parse {
        path: path.to_path_buf(),
        message,
    }
}

/// Reads a vector directory back: the request from `manifest.json`, the cases from
/// `inputs.hex` and the expected outputs from `expected.hex`.
///
/// # Errors
/// [`VectorError::Read`] or [`VectorError::Parse`] for a missing or malformed file, or one
/// whose word count differs from the manifest's count.
pub fn read(dir: &Path) -> Result<VectorSet, VectorError> {
    let mpath = dir.join(MANIFEST_FILE);
    let text = std::fs::read_to_string(&mpath).map_err(|source| VectorError::Read {
        path: mpath.clone(),
        source,
    })?;
    let m: Value = serde_json::from_str(&text).map_err(|e| parse_err(&mpath, e.to_string()))?;
    let kernel = m["kernel"]
        .as_str()
        .ok_or_else(|| parse_err(&mpath, "no \"kernel\"".into()))?;
    let count = m["count"]
        .as_u64()
        .ok_or_else(|| parse_err(&mpath, "no \"count\"".into()))?;
    let seed = m["seed"]
        .as_u64()
        .ok_or_else(|| parse_err(&mpath, "no \"seed\"".into()))?;
    let frac_bits = m["frac_bits"]
        .as_u64()
        .and_then(|b| u32::try_from(b).ok())
        .ok_or_else(|| parse_err(&mpath, "no \"frac_bits\"".into()))?;
    let spec = Spec::new(kernel, count as usize, seed, frac_bits)?;
    let il = input_layout(&spec);
    let ipath = dir.join(INPUTS_FILE);
    let cases = read_hex(&ipath, &il)?
        .iter()
        .enumerate()
        .map(|(n, w)| {
            case_from_values(spec.kernel, &il.unpack(w))
                .ok_or_else(|| parse_err(&ipath, format!("word {n} does not decode")))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let ol = output_layout(&spec);
    let epath = dir.join(EXPECTED_FILE);
    let expected: Vec<Raw> = read_hex(&epath, &ol)?
        .iter()
        .map(|w| {
            let v = ol.unpack(w);
            std::array::from_fn(|k| v.get(k).copied().unwrap_or(0) as u16)
        })
        .collect();
    for (path, n) in [(&ipath, cases.len()), (&epath, expected.len())] {
        if n != spec.count {
            return Err(parse_err(
                path,
                format!("{n} words, the manifest says {}", spec.count),
            ));
        }
    }
    Ok(VectorSet {
        spec,
        cases,
        expected,
    })
}

/// `volsample vectors`: validates the arguments, generates, writes and reports.
///
/// # Errors
/// A message for a bad argument or a file that cannot be written.
pub fn run(
    kernel: &str,
    count: usize,
    seed: u64,
    frac_bits: u32,
    out: &Path,
) -> Result<String, VectorError> {
    let spec = Spec::new(kernel, count, seed, frac_bits)?;
    let set = build(&spec)?;
    write(&set, out)?;
    Ok(format!(
        "{}: {} vectors ({} corner cases, then random; seed {}, F = {}) -> {}/{{{INPUTS_FILE}, {EXPECTED_FILE}, {MANIFEST_FILE}}}",
        spec.kernel.name(),
        spec.count,
        corner_count(&spec),
        spec.seed,
        spec.frac_bits,
        out.display()
    ))
}
