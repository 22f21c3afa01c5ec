//! Reference vectors for hardware test benches: `volsample vectors` (issue 7).
//!
//! Each vector set is a directory with
//!
//! * `inputs.hex` and `expected.hex`: one fixed-width word per line, lowercase hex, most
//!   significant digit first, no prefix or separators, readable by Verilog `$readmemh` into a
//!   `reg [W-1:0] mem [0:N-1]`;
//! * `manifest.json`: the kernel, every field's name, bit offset (0 = least significant bit of
//!   the word), width, signedness, fractional bits and meaning, the rounding rules (the names
//!   the core uses: **round half up**, **truncate**, **saturate**), the count, the seed and the
//!   generator version;
//! * the lookup tables a kernel reads, each as its own `table_*.hex` (one entry per line,
//!   entry `j` on line `j`) with its generation rule in the manifest's `tables`: the opacity
//!   correction's tables for `opacity-correction` and the `ray-march-*` kernels (they do not
//!   depend on the ratio), the `φ`/`e^(−x)` tables of size `table_size` for the
//!   `extinction-weighted-*` kernels.
//!
//! Expected outputs come from the `volsample::fixed_point` kernels themselves (the golden
//! model); `host-tests/tests/vectors.rs` cross-checks them against the `f64`/`u128` models in
//! [`int_model`](crate::int_model).
//!
//! # Kernels
//!
//! | name | core kernel | input word |
//! |---|---|---|
//! | `opacity-weighted-{nearest,trilinear}` | `IntSampler<StraightU8, OpacityWeighted, _>` | 8 straight voxels + `F`-bit fractions |
//! | `separate-{nearest,trilinear}` | `IntSampler<StraightU8, Separate, _>` | 8 straight voxels + fractions |
//! | `preweighted-{nearest,trilinear}` | `IntSampler<AssociatedU8, Preweighted, _>` | 8 associated voxels + fractions |
//! | `extinction-weighted-{nearest,trilinear}` | `IntSampler<ExtinctionFx, IntExtinction<N>, _>` | 8 U7.20 `(D·C, D)` voxels + fractions + `IntRatio` (and the `f32` ratio); tables of size `N = --table-size` |
//! | `composite-front-to-back` | `front_to_back(acc, s)` | accumulator + sample (U8.8) |
//! | `opacity-correction` | `IntCorrection::apply` | sample + `IntRatio` (and the `f32` ratio) |
//! | `downsample-opacity-based` | `downsample_level_int(IntOpacityBased, …)` over `AssociatedU8` | 64 associated voxels + Q0.16 tap `a` |
//! | `ray-march-opacity-weighted-{nearest,trilinear}` | `IntRayMarcher<StraightU8, OpacityWeighted, _>::march_positions` | 64 straight voxels (4×4×4) + integer ray (start, step, count) + ratio + `A_stop` + background; output adds the samples taken |
//!
//! A sampling vector (the opacity-based and the extinction kernels) is one tap set: the eight
//! voxels `v0…v7` of a 2×2×2 volume (voxel `i` at `(i & 1, (i >> 1) & 1, i >> 2)`, the order
//! of the core's taps and weights) sampled at `IntPos::<F>::new([0, 0, 0], [fx, fy, fz])`, so
//! every voxel is read and no edge clamping happens. Nearest reads voxel
//! `(fx ≥ 2^(F−1), fy ≥ 2^(F−1), fz ≥ 2^(F−1))` (`nearest_index`, round half up).
//!
//! An extinction voxel is `ExtinctionFx`: `D = τ·d′` (`tau`) and `D·C = C^τ·d′` (`c_tau`), raw
//! U7.20 (`raw/2^20`, at most `2^26`, i.e. optical depth 64, and each `c_tau ≤ tau`); the step
//! ratio `r = d/d′` enters as `IntRatio`, `ratio_raw = ⌊r·2^32 + ½⌋`. The tables are
//! `ExtinctionTables::<N>` (`N = 2^B + 1` nodes on `[0, 1]`, `N` one of [`TABLE_SIZES`],
//! default [`DEFAULT_TABLE_SIZE`]), written as `table_phi.hex`, `table_exp.hex` and
//! `table_exp_int.hex`.
//!
//! A downsampling vector is one coarse voxel's tap set: the 4×4×4 fine voxels `t0…t63`
//! (`t = i + 4j + 16k`, fine voxel `(2X − 1 + i, 2Y − 1 + j, 2Z − 1 + k)` of coarse voxel
//! `(X, Y, Z)`) and the filter's outer tap `a_raw` (Q0.16, taps `(a, 2^15 − a, 2^15 − a, a)`);
//! the core computes it as coarse voxel `(1, 1, 1)` of a 6×6×6 volume holding the taps at
//! `1..=4` per axis (so no edge clamping happens).
//!
//! A ray-march vector is one ray through its own 4×4×4 volume of straight `u8` voxels `v0…v63`
//! (voxel `i` at `(i & 3, (i >> 2) & 3, i >> 4)`, reference distance one voxel), given in the
//! integer position format: `n ≤ 31` sample positions `p_k = p + k·Δ` (`k = 0..n`, per axis,
//! exact; `p` unsigned and `Δ` two's complement, both with `F` fractional bits; the generator
//! keeps every `p_k` in `[0, 3·2^F]`, inside the volume). The core's
//! `IntRayMarcher::march_positions` samples each `p_k` (`OpacityWeighted`, the filter of the
//! name), corrects its opacity for the ratio `r = d/d′` when `ratio_raw ≠ 2^32`, composites
//! front to back, stops before a sample once `A ≥ a_stop` and finally composites the result
//! over the background. The output is that sample and the number of samples composited.
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
//! * **a ratio** (used below): one draw `w`, `k = w >> 61`; `1` (`k = 0`),
//!   `(1 + w mod 4096)/2^20` (`k = 1`) or `(1 + w mod 65536)/4096` (each exact in `f32`).
//! * **compositing**: the accumulator, then the sample (each as above).
//! * **opacity correction**: one draw `w`, `ratio = (1 + w % 65536)/4096` (exact in `f32`,
//!   in `(0, 16]`), then the sample.
//! * **downsampling**: each of the 64 voxels as a `preweighted` sampling voxel above; then one
//!   draw `w`, `k = w >> 61`: `a_raw` = 0, 8192, 13107, 16384, 32768 for `k = 0…4`, else
//!   `(w & 0xFFFF) % 32769`.
//! * **extinction** (`M = 2^26`): for each voxel `i = 0..8` one draw `w`, `k = w >> 62`:
//!   for `k ≤ 1` the straight voxel of `w` (as a sampling voxel above) converted with
//!   `ExtinctionFx::from_straight_u8` (`D = ⌊2^20·min(−ln(1 − α/255), 64) + ½⌋`,
//!   `D·C = ⌊(2·D·c + 255)/510⌋`); for `k = 2` a raw voxel with `tau = (w & 0xFFFFFFF) % (M + 1)`,
//!   for `k = 3` one with `tau = w & 0xFFFFF` (optical depth below 1), each `c_tau` then one
//!   draw `% (tau + 1)`. Then the fractions as for sampling, then the ratio.
//! * **ray march** (`u = 2^F`, `L = 3u`): one draw `w`, `style = w & 3`: 0 → each voxel
//!   `i = 0..64` a straight sampling voxel (one draw each); 1 → haze: each voxel one draw `w`,
//!   `r, g, b` = bytes 0..2, `a` = byte 3 `>> 3`; 2 → one straight sampling voxel copied to all
//!   64; 3 → sparse: each voxel one draw `w`, `r, g, b, a` = bytes 0..3 but `a = 0` unless
//!   `(w >> 32) & 7 = 0`. Then one draw `w`: `n = w & 31`; one draw `w` for the start,
//!   `p_c = ((w >> 20c) & 0xFFFFF) % (L + 1)` (`c = 0, 1, 2` for x, y, z), one draw likewise for
//!   the last position `q`; `Δ_c = (q_c − p_c)/(n − 1)` truncated toward zero for `n ≥ 2`,
//!   `q_c − p_c` otherwise. Then the ratio (as above); then one draw `w`: `a_stop = ONE` if
//!   `w >> 62 < 2`, else `1 + (w & 0xFFFFFFFF) % ONE`; then the background as a U8.8 sample.

use std::fmt;

use volsample::fixed_point::{IntSample, ONE};

mod composite;
mod correction;
mod downsample;
mod extinction;
mod files;
mod prng;
mod ray_march;
mod sampling;
mod words;

pub use correction::correction_tables;
pub use extinction::extinction_tables;
pub use files::{build, manifest, read, run, run_spec, write, TableFile, VectorSet};
pub use prng::SplitMix64;
pub use ray_march::{ray_positions, RAY_DIMS, RAY_MAX_SAMPLES};
pub use words::{hex_text, read_hex, Field, Layout, Word};

/// Version of the generator and file layout; bumped whenever the bytes for a given
/// `(kernel, count, seed, frac_bits, table_size)` change.
pub const GENERATOR_VERSION: u32 = 1;

/// Name of the input file in a vector directory.
pub const INPUTS_FILE: &str = "inputs.hex";
/// Name of the expected-output file in a vector directory.
pub const EXPECTED_FILE: &str = "expected.hex";
/// Name of the manifest in a vector directory.
pub const MANIFEST_FILE: &str = "manifest.json";

/// The `φ`/`e^(−x)` table sizes `N = 2^B + 1` the extinction kernels support
/// (`--table-size`).
pub const TABLE_SIZES: [usize; 6] = [5, 17, 65, 257, 1025, 4097];
/// The table size used unless `--table-size` says otherwise (2 KiB of `φ` and `e^(−x)`).
pub const DEFAULT_TABLE_SIZE: usize = 257;

/// Runs `$body` with the const `$F` set to the runtime `$f` (`4..=12`), else
/// `Err(VectorError::FracBits)`.
macro_rules! with_frac_bits {
    ($f:expr, $F:ident => $body:expr) => {
        match $f {
            4 => {
                const $F: u32 = 4;
                $body
            }
            5 => {
                const $F: u32 = 5;
                $body
            }
            6 => {
                const $F: u32 = 6;
                $body
            }
            7 => {
                const $F: u32 = 7;
                $body
            }
            8 => {
                const $F: u32 = 8;
                $body
            }
            9 => {
                const $F: u32 = 9;
                $body
            }
            10 => {
                const $F: u32 = 10;
                $body
            }
            11 => {
                const $F: u32 = 11;
                $body
            }
            12 => {
                const $F: u32 = 12;
                $body
            }
            b => Err($crate::vectors::VectorError::FracBits(b)),
        }
    };
}
pub(crate) use with_frac_bits;

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
    /// One integer `ExtinctionWeighted` sample of a 2×2×2 tap set of `ExtinctionFx` voxels.
    Extinction(SampleFilter),
    /// One ray of the integer ray marcher (`OpacityWeighted`, straight `u8` 4×4×4 volume) at
    /// integer sample positions.
    RayMarch(SampleFilter),
}

impl Kernel {
    /// Every kernel, in the order `volsample vectors` lists them.
    pub const ALL: [Kernel; 13] = [
        Kernel::Sample(SampleMode::OpacityWeighted, SampleFilter::Nearest),
        Kernel::Sample(SampleMode::OpacityWeighted, SampleFilter::Trilinear),
        Kernel::Sample(SampleMode::Separate, SampleFilter::Nearest),
        Kernel::Sample(SampleMode::Separate, SampleFilter::Trilinear),
        Kernel::Sample(SampleMode::Preweighted, SampleFilter::Nearest),
        Kernel::Sample(SampleMode::Preweighted, SampleFilter::Trilinear),
        Kernel::Composite,
        Kernel::Correction,
        Kernel::Downsample,
        Kernel::Extinction(SampleFilter::Nearest),
        Kernel::Extinction(SampleFilter::Trilinear),
        Kernel::RayMarch(SampleFilter::Nearest),
        Kernel::RayMarch(SampleFilter::Trilinear),
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
            Kernel::Extinction(Nearest) => "extinction-weighted-nearest",
            Kernel::Extinction(Trilinear) => "extinction-weighted-trilinear",
            Kernel::RayMarch(Nearest) => "ray-march-opacity-weighted-nearest",
            Kernel::RayMarch(Trilinear) => "ray-march-opacity-weighted-trilinear",
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

    /// Whether the kernel reads the `φ`/`e^(−x)` tables whose size `--table-size` sets.
    pub fn has_table_size(self) -> bool {
        matches!(self, Kernel::Extinction(_))
    }
}

/// The most vectors one request may ask for (a few GB of hex at most; `--count` past it was
/// accepted and then ran until killed).
pub const MAX_COUNT: usize = 100_000_000;

/// What went wrong while generating, writing or reading vectors.
#[derive(Debug)]
#[non_exhaustive]
pub enum VectorError {
    /// The kernel name is not one of [`Kernel::ALL`].
    UnknownKernel(String),
    /// `count` was 0.
    ZeroCount,
    /// `count` was over [`MAX_COUNT`].
    CountTooLarge(usize),
    /// `frac_bits` outside `4..=12`.
    FracBits(u32),
    /// A table size not in [`TABLE_SIZES`].
    TableSize(usize),
    /// A table size given for a kernel without extinction tables.
    TableSizeNotApplicable(Kernel),
    /// A case whose inputs the kernel cannot take (a ray position outside `u32`, …).
    InvalidCase(String),
    /// A core constructor rejected a generated input (a generator bug).
    Core(volsample::Error),
    /// The output directory or a file in it could not be created or written.
    Write {
        /// The path.
        path: std::path::PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// A vector file could not be read.
    Read {
        /// The path.
        path: std::path::PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// A vector file or manifest is malformed.
    Parse {
        /// The file.
        path: std::path::PathBuf,
        /// What is wrong (with the line number where there is one).
        message: String,
    },
}

fn list<T: fmt::Display>(items: impl IntoIterator<Item = T>) -> String {
    items
        .into_iter()
        .map(|x| x.to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

impl fmt::Display for VectorError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            VectorError::UnknownKernel(k) => {
                let names = list(Kernel::ALL.iter().map(|k| k.name()));
                write!(f, "unknown kernel '{k}' (one of: {names})")
            }
            VectorError::ZeroCount => write!(f, "--count must be at least 1"),
            VectorError::CountTooLarge(n) => {
                write!(f, "--count {n} is over the limit of {MAX_COUNT}")
            }
            VectorError::FracBits(b) => {
                write!(f, "--frac-bits {b} is outside 4..=12")
            }
            VectorError::TableSize(n) => write!(
                f,
                "--table-size {n} is not supported (one of: {})",
                list(TABLE_SIZES)
            ),
            VectorError::TableSizeNotApplicable(k) => write!(
                f,
                "--table-size applies only to the extinction-weighted-* kernels, not to {}",
                k.name()
            ),
            VectorError::InvalidCase(m) => write!(f, "invalid case: {m}"),
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

/// A validated request: kernel, count, seed, fractional position bits and (extinction
/// kernels) table size.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Spec {
    kernel: Kernel,
    count: usize,
    seed: u64,
    frac_bits: u32,
    table_size: usize,
}

impl Spec {
    /// Validates a request (table size [`DEFAULT_TABLE_SIZE`]).
    ///
    /// # Errors
    /// [`VectorError::UnknownKernel`], [`VectorError::ZeroCount`],
    /// [`VectorError::CountTooLarge`], [`VectorError::FracBits`].
    pub fn new(kernel: &str, count: usize, seed: u64, frac_bits: u32) -> Result<Self, VectorError> {
        let kernel = Kernel::parse(kernel)?;
        if count == 0 {
            return Err(VectorError::ZeroCount);
        }
        if count > MAX_COUNT {
            return Err(VectorError::CountTooLarge(count));
        }
        if !(4..=12).contains(&frac_bits) {
            return Err(VectorError::FracBits(frac_bits));
        }
        Ok(Self {
            kernel,
            count,
            seed,
            frac_bits,
            table_size: DEFAULT_TABLE_SIZE,
        })
    }

    /// The same request with `φ`/`e^(−x)` tables of `n` entries.
    ///
    /// # Errors
    /// [`VectorError::TableSizeNotApplicable`] unless the kernel has such tables
    /// ([`Kernel::has_table_size`]); [`VectorError::TableSize`] unless `n` is one of
    /// [`TABLE_SIZES`].
    pub fn with_table_size(self, n: usize) -> Result<Self, VectorError> {
        if !self.kernel.has_table_size() {
            return Err(VectorError::TableSizeNotApplicable(self.kernel));
        }
        if !TABLE_SIZES.contains(&n) {
            return Err(VectorError::TableSize(n));
        }
        Ok(Self {
            table_size: n,
            ..self
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
    /// Fractional position bits `F` (sampling and ray-march kernels only).
    pub fn frac_bits(&self) -> u32 {
        self.frac_bits
    }
    /// Entries `N` of the `φ`/`e^(−x)` tables (extinction kernels only; otherwise
    /// [`DEFAULT_TABLE_SIZE`], unused).
    pub fn table_size(&self) -> usize {
        self.table_size
    }
}

/// A U8.8 sample as raw `[r, g, b, a]` (`C̃` and `α`, `ONE` = opacity 1).
pub type Raw = [u16; 4];

/// The inputs of one vector.
// The 64-voxel tap sets make two variants about 270 bytes; boxing them would cost more code
// than the few MB a 10,000-vector set takes on the host.
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
    /// An extinction tap set sampled with step ratio `d/d′`.
    Extinction {
        /// Voxel `i` at `(i & 1, (i >> 1) & 1, i >> 2)`.
        voxels: [volsample::fixed_point::ExtinctionFx; 8],
        /// Fractions in units of `2^−F` voxel.
        frac: [u32; 3],
        /// `d/d′`.
        ratio: f32,
    },
    /// One ray at integer positions through a 4×4×4 straight `u8` volume.
    RayMarch {
        /// Straight voxel bytes `[r, g, b, a]`; voxel `i` at `(i & 3, (i >> 2) & 3, i >> 4)`.
        voxels: [[u8; 4]; 64],
        /// The first position `p` (`F` fractional bits per axis).
        start: [u32; 3],
        /// The step `Δ` between positions (`F` fractional bits per axis, signed).
        step: [i32; 3],
        /// The number of positions `n` (at most [`RAY_MAX_SAMPLES`]).
        samples: u32,
        /// `d/d′` (opacity correction when it is not 1).
        ratio: f32,
        /// `A_stop` (U8.8, `1..=ONE`).
        a_stop: u16,
        /// The background (U8.8 associated).
        background: Raw,
    },
}

fn sample_from(s: IntSample) -> Raw {
    let [r, g, b] = s.c();
    [r, g, b, s.a()]
}

fn int_sample(s: Raw) -> Result<IntSample, VectorError> {
    Ok(IntSample::new([s[0], s[1], s[2]], s[3])?)
}

fn mismatch(kernel: Kernel, case: &Case) -> VectorError {
    VectorError::InvalidCase(format!(
        "case {case:?} does not belong to kernel {}",
        kernel.name()
    ))
}

/// The expected output of one vector and, for the `ray-march-*` kernels, the number of
/// samples composited, computed by the core kernel (the golden model).
///
/// # Errors
/// [`VectorError::FracBits`] for `F` outside `4..=12`; [`VectorError::Core`] if the core
/// rejects an input (a voxel with `C̃ > α` for `preweighted` or `c_tau > tau`, a sample with
/// `C̃ > α` or `α > ONE`, a non-positive ratio, `a_stop = 0`); [`VectorError::InvalidCase`]
/// for a case of another kernel or a ray position outside `u32`.
pub fn expected_counted(spec: &Spec, case: &Case) -> Result<(Raw, Option<u32>), VectorError> {
    match spec.kernel {
        Kernel::Extinction(_) => Ok((extinction::expected(spec, case)?, None)),
        Kernel::RayMarch(filter) => {
            let (s, n) = ray_march::expected(filter, spec.frac_bits, case)?;
            Ok((s, Some(n)))
        }
        _ => Ok((expected(spec, case)?, None)),
    }
}

/// The expected output of one vector, computed by the core kernel (the golden model); for
/// the `ray-march-*` kernels the composited sample (see [`expected_counted`] for the count).
///
/// # Errors
/// As [`expected_counted`].
pub fn expected(spec: &Spec, case: &Case) -> Result<Raw, VectorError> {
    match (spec.kernel, case) {
        (Kernel::Sample(mode, filter), Case::Sample { voxels, frac }) => {
            sampling::expected(mode, filter, spec.frac_bits, voxels, *frac)
        }
        (Kernel::Composite, Case::Composite { acc, s }) => composite::expected(*acc, *s),
        (Kernel::Correction, Case::Correction { ratio, s }) => correction::expected(*ratio, *s),
        (Kernel::Downsample, Case::Downsample { taps, a_raw }) => {
            downsample::expected(taps, *a_raw)
        }
        (Kernel::Extinction(_) | Kernel::RayMarch(_), _) => {
            expected_counted(spec, case).map(|(s, _)| s)
        }
        (k, c) => Err(mismatch(k, c)),
    }
}

/// The expected outputs of many vectors (the extinction tables are built once).
fn expected_all(spec: &Spec, cases: &[Case]) -> Result<Vec<(Raw, Option<u32>)>, VectorError> {
    match spec.kernel {
        Kernel::Extinction(_) => extinction::expected_all(spec, cases),
        _ => cases.iter().map(|c| expected_counted(spec, c)).collect(),
    }
}

/// The corner cases of a kernel, in order (see the module docs).
pub fn corner_cases(spec: &Spec) -> Vec<Case> {
    let f = spec.frac_bits;
    match spec.kernel {
        Kernel::Sample(mode, _) => sampling::corner_cases(mode, f),
        Kernel::Composite => composite::corner_cases(),
        Kernel::Correction => correction::corner_cases(),
        Kernel::Downsample => downsample::corner_cases(),
        Kernel::Extinction(_) => extinction::corner_cases(f),
        Kernel::RayMarch(_) => ray_march::corner_cases(f),
    }
}

fn random_case(spec: &Spec, rng: &mut SplitMix64) -> Case {
    let f = spec.frac_bits;
    match spec.kernel {
        Kernel::Sample(mode, _) => sampling::random_case(mode, f, rng),
        Kernel::Composite => composite::random_case(rng),
        Kernel::Correction => correction::random_case(rng),
        Kernel::Downsample => downsample::random_case(rng),
        Kernel::Extinction(_) => extinction::random_case(f, rng),
        Kernel::RayMarch(_) => ray_march::random_case(f, rng),
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

/// The layout of an input word.
pub fn input_layout(spec: &Spec) -> Layout {
    let f = spec.frac_bits;
    match spec.kernel {
        Kernel::Sample(mode, _) => sampling::input_layout(mode, f),
        Kernel::Composite => composite::input_layout(),
        Kernel::Correction => correction::input_layout(),
        Kernel::Downsample => downsample::input_layout(),
        Kernel::Extinction(_) => extinction::input_layout(f),
        Kernel::RayMarch(_) => ray_march::input_layout(f),
    }
}

/// The layout of an output word: a U8.8 sample; for `downsample-opacity-based` a `u8`
/// associated voxel; for the `ray-march-*` kernels a U8.8 sample and the samples taken.
pub fn output_layout(spec: &Spec) -> Layout {
    match spec.kernel {
        Kernel::Downsample => downsample::output_layout(),
        Kernel::RayMarch(_) => ray_march::output_layout(),
        _ => {
            let mut l = Layout::default();
            words::push_u88(&mut l, "");
            l
        }
    }
}

/// The value of each input field of a case (two's complement fields as their bits), in the
/// order of [`input_layout`]'s fields.
///
/// # Errors
/// [`VectorError::InvalidCase`] for a case no layout can hold.
pub fn case_values(case: &Case) -> Result<Vec<u64>, VectorError> {
    input_values(case)
}

/// The value of each input field of a case (two's complement fields as their bits).
fn input_values(case: &Case) -> Result<Vec<u64>, VectorError> {
    Ok(match case {
        Case::Sample { voxels, frac } => sampling::input_values(voxels, *frac),
        Case::Composite { acc, s } => composite::input_values(*acc, *s),
        Case::Correction { ratio, s } => correction::input_values(*ratio, *s)?,
        Case::Downsample { taps, a_raw } => downsample::input_values(taps, *a_raw),
        Case::Extinction { .. } => extinction::input_values(case)?,
        Case::RayMarch { .. } => ray_march::input_values(case)?,
    })
}

/// The case of the input field values of `spec`'s layout (`None` if they do not decode).
fn case_from_values(spec: &Spec, v: &[u64]) -> Option<Case> {
    let f = spec.frac_bits;
    match spec.kernel {
        Kernel::Sample(..) => sampling::case_from_values(v),
        Kernel::Composite => composite::case_from_values(v),
        Kernel::Correction => correction::case_from_values(v),
        Kernel::Downsample => downsample::case_from_values(v),
        Kernel::Extinction(_) => extinction::case_from_values(v),
        Kernel::RayMarch(_) => ray_march::case_from_values(f, v),
    }
}

/// The four values `[r, g, b, a]` of a [`Raw`] sample from field values.
fn raw4(s: &[u64]) -> Option<Raw> {
    Some([
        u16::try_from(*s.first()?).ok()?,
        u16::try_from(*s.get(1)?).ok()?,
        u16::try_from(*s.get(2)?).ok()?,
        u16::try_from(*s.get(3)?).ok()?,
    ])
}

/// `ONE` as `u64`, for the generators.
const ONE_U64: u64 = ONE as u64;
