//! Check functions shared by the fuzz targets (`fuzz/`) and the stable tests that replay the
//! checked-in corpus: each takes an input (decoded from bytes with `arbitrary`, exactly as the
//! fuzz target decodes it) and returns `Err` with a description when a stated bound or
//! invariant of an integer kernel is broken.

use arbitrary::{Arbitrary, Unstructured};
use std::sync::OnceLock;
use volsample::fixed_point::{
    composite_front_to_back, premultiply, premultiply_voxel, unpremultiply, ExtinctionFx,
    ExtinctionTables, IntExtinction, IntMode, IntPos, IntRatio, IntSample, IntSampler, IntStop,
    ONE,
};
use volsample::mode::Mode;
use volsample::sample::Interp;
use volsample::{
    AssociatedU8, ExtinctionWeighted, Nearest, OpacityWeighted, Preweighted, Separate, StraightU8,
    Trilinear, Volume,
};

use crate::int_model::{
    self, composite as cm, extinction as em, premul as pm, sample as sm, Modelled,
};
use crate::tolerance::integer as tol;

/// The fuzz targets, by name (`fuzz/fuzz_targets/<name>.rs`, corpus in `fuzz/corpus/<name>/`);
/// the kernel-family ones ([`kernel_checks::TARGETS`](crate::kernel_checks::TARGETS)) are run
/// by [`kernel_checks::run`](crate::kernel_checks::run).
pub const TARGETS: [&str; 10] = [
    "premul_storage",
    "int_vs_float",
    "composite",
    "extinction",
    "marcher_packets",
    "int_marcher",
    "downsample",
    "filters",
    "classify",
    "vectors",
];

/// Decodes `data` as the fuzz target `target` does and runs its check.
///
/// # Errors
/// The check's description of a broken bound, or an unknown target name.
pub fn run(target: &str, data: &[u8]) -> Result<(), String> {
    match target {
        "premul_storage" => decode(data).and_then(|i| premul_storage(&i)),
        "int_vs_float" => decode(data).and_then(|i| int_vs_float(&i)),
        "composite" => decode(data).and_then(|i| composite(&i)),
        "extinction" => decode(data).and_then(|i| extinction(&i)),
        #[cfg(feature = "marcher-checks")]
        "marcher_packets" => decode(data).and_then(|i| crate::marcher_checks::marcher_packets(&i)),
        #[cfg(not(feature = "marcher-checks"))]
        "marcher_packets" => {
            Err("marcher_packets: built without the feature marcher-checks".into())
        }
        t if crate::kernel_checks::TARGETS.contains(&t) => crate::kernel_checks::run(t, data),
        _ => Err(format!("unknown fuzz target {target}")),
    }
}

/// Input that does not decode is not a failure (libFuzzer skips it the same way).
fn decode<'a, T: Arbitrary<'a> + Default>(data: &'a [u8]) -> Result<T, String> {
    Ok(T::arbitrary_take_rest(Unstructured::new(data)).unwrap_or_default())
}

/// Runs `$body` with the const `F` (4..=12) chosen by `$sel`.
macro_rules! with_frac_bits {
    ($sel:expr, $f:ident => $body:expr) => {
        match 4 + u32::from($sel) % 9 {
            4 => {
                const $f: u32 = 4;
                $body
            }
            5 => {
                const $f: u32 = 5;
                $body
            }
            6 => {
                const $f: u32 = 6;
                $body
            }
            7 => {
                const $f: u32 = 7;
                $body
            }
            8 => {
                const $f: u32 = 8;
                $body
            }
            9 => {
                const $f: u32 = 9;
                $body
            }
            10 => {
                const $f: u32 = 10;
                $body
            }
            11 => {
                const $f: u32 = 11;
                $body
            }
            _ => {
                const $f: u32 = 12;
                $body
            }
        }
    };
}

/// Which integer kernel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Arbitrary)]
pub enum IntKernel {
    /// `OpacityWeighted` on straight `u8`.
    #[default]
    OpacityWeighted,
    /// `Separate` on straight `u8`.
    Separate,
    /// `Preweighted` on premultiplied `u8` (the voxel bytes, with `C̃` clamped to `α`).
    Preweighted,
}

/// One sample of a 2×2×2 cell: the 8 voxels (corner `i` at `(i & 1, (i >> 1) & 1, i >> 2)`),
/// the fractions (reduced modulo `2^F`), `F = 4 + frac_bits_sel mod 9`, and the filter.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Arbitrary)]
pub struct CellInput {
    /// The 8 voxels `[r, g, b, a]`.
    pub voxels: [[u8; 4]; 8],
    /// Raw fractions (only the low `F` bits are used).
    pub frac: [u32; 3],
    /// Selects `F`.
    pub frac_bits_sel: u8,
    /// Trilinear (`true`) or nearest.
    pub trilinear: bool,
    /// The kernel.
    pub kernel: IntKernel,
}

impl CellInput {
    /// `F` for this input.
    pub fn frac_bits(&self) -> u32 {
        4 + u32::from(self.frac_bits_sel) % 9
    }

    /// The voxels as valid associated bytes (`C̃` clamped to `α`).
    pub fn associated(&self) -> [AssociatedU8; 8] {
        self.voxels
            .map(|[r, g, b, a]| AssociatedU8([r.min(a), g.min(a), b.min(a), a]))
    }
}

/// The kernel's sample through the public sampler, at `F` bits.
fn kernel_sample<const F: u32>(inp: &CellInput) -> Result<IntSample, String> {
    let m = (1u32 << F) - 1;
    let pos = IntPos::<F>::from_raw(inp.frac.map(|f| f & m));
    let straight = inp.voxels.map(StraightU8);
    let assoc = inp.associated();
    fn run<V: volsample::voxel::Voxel, M: IntMode<V>, const F: u32>(
        data: &[V],
        mode: M,
        trilinear: bool,
        pos: IntPos<F>,
    ) -> Result<IntSample, String> {
        let vol = Volume::new(data, [2, 2, 2]).map_err(|e| e.to_string())?;
        Ok(if trilinear {
            IntSampler::new(vol, mode, Trilinear::new()).sample(pos)
        } else {
            IntSampler::new(vol, mode, Nearest).sample(pos)
        })
    }
    match inp.kernel {
        IntKernel::OpacityWeighted => run(&straight, OpacityWeighted, inp.trilinear, pos),
        IntKernel::Separate => run(&straight, Separate, inp.trilinear, pos),
        IntKernel::Preweighted => run(&assoc, Preweighted, inp.trilinear, pos),
    }
}

/// The taps and real weights the model uses for this input.
fn model_taps(inp: &CellInput) -> (Vec<[u8; 4]>, Vec<f64>) {
    let f = inp.frac_bits();
    let m = (1u32 << f) - 1;
    let frac = inp.frac.map(|x| x & m);
    if inp.trilinear {
        (
            inp.voxels.to_vec(),
            int_model::trilinear_weights(f, frac).to_vec(),
        )
    } else {
        let half = 1u32 << (f - 1);
        let idx = frac.map(|x| usize::from(x >= half));
        let i = idx[0] + 2 * (idx[1] + 2 * idx[2]);
        (vec![inp.voxels[i]], vec![1.0])
    }
}

/// The model of the input's kernel.
pub fn model(inp: &CellInput) -> Modelled {
    let (taps, w) = model_taps(inp);
    match inp.kernel {
        IntKernel::OpacityWeighted => sm::opacity_weighted(&taps, &w),
        IntKernel::Separate => sm::separate(&taps, &w),
        IntKernel::Preweighted => sm::preweighted(&taps, &w),
    }
}

/// The kernel's sample for this input (dispatching on `F`).
///
/// # Errors
/// If the volume cannot be built (never, for 8 voxels).
pub fn sample(inp: &CellInput) -> Result<IntSample, String> {
    with_frac_bits!(inp.frac_bits_sel, F => kernel_sample::<F>(inp))
}

/// The stated bound of a kernel on `(C̃, α)`, in U8.8 LSB.
pub fn kernel_bound(k: IntKernel) -> (f64, f64) {
    match k {
        IntKernel::OpacityWeighted => {
            (tol::OPACITY_WEIGHTED_INT_LSB, tol::OPACITY_WEIGHTED_INT_LSB)
        }
        IntKernel::Separate => (tol::SEPARATE_INT_LSB, tol::SEPARATE_INT_A_LSB),
        IntKernel::Preweighted => (tol::PREWEIGHTED_INT_LSB, tol::PREWEIGHTED_INT_LSB),
    }
}

/// The `f32` float kernel of the same method on the same bytes and weights, in U8.8 units.
pub fn float_kernel(inp: &CellInput) -> ([f64; 3], f64) {
    let f = inp.frac_bits();
    let m = (1u32 << f) - 1;
    let s = (1u32 << f) as f32;
    let fr = inp.frac.map(|x| (x & m) as f32 / s);
    let straight = inp.voxels.map(StraightU8);
    let assoc = inp.associated();
    fn go<V: volsample::voxel::Voxel, M: Mode<V>>(
        mode: M,
        taps: &[V; 8],
        fr: [f32; 3],
        trilinear: bool,
    ) -> volsample::Sample {
        let i: Interp<f32> = if trilinear {
            mode.weighted(taps, &volsample::filter::trilinear_weights(fr))
        } else {
            let idx = fr.map(|x| usize::from(x >= 0.5));
            let t = taps[idx[0] + 2 * (idx[1] + 2 * idx[2])];
            mode.weighted(&[t], &[1.0f32])
        };
        mode.finish(i, 1.0)
    }
    let smp = match inp.kernel {
        IntKernel::OpacityWeighted => go(OpacityWeighted, &straight, fr, inp.trilinear),
        IntKernel::Separate => go(Separate, &straight, fr, inp.trilinear),
        IntKernel::Preweighted => go(Preweighted, &assoc, fr, inp.trilinear),
    };
    let u = |x: f32| f64::from(x) * int_model::ONE;
    (smp.c.map(u), u(smp.a))
}

fn invariant(s: &IntSample, what: &str) -> Result<(), String> {
    let [r, g, b] = s.c();
    if s.a() > ONE || r > s.a() || g > s.a() || b > s.a() {
        return Err(format!("{what}: C̃ ≤ α ≤ ONE broken: {s:?}"));
    }
    Ok(())
}

fn within(what: &str, got: f64, want: f64, bound: f64) -> Result<(), String> {
    let e = (got - want).abs();
    if e.is_nan() || e > bound {
        Err(format!(
            "{what}: {got} vs {want}: error {e} > bound {bound}"
        ))
    } else {
        Ok(())
    }
}

/// `int_vs_float`: the kernel agrees bit for bit with its f64 model, keeps `C̃ ≤ α`, and is
/// within its stated bound of the exact result and (plus slack) of the `f32` float kernel.
///
/// # Errors
/// Which of these failed, with the values.
pub fn int_vs_float(inp: &CellInput) -> Result<(), String> {
    let got = sample(inp)?;
    invariant(&got, "kernel")?;
    let m = model(inp);
    if (got.c(), got.a()) != (m.c, m.a) {
        return Err(format!("kernel {got:?} != model {m:?} for {inp:?}"));
    }
    let (bc, ba) = kernel_bound(inp.kernel);
    within("α vs exact", f64::from(got.a()), m.exact_a, ba)?;
    for k in 0..3 {
        within("C̃ vs exact", f64::from(got.c()[k]), m.exact_c[k], bc)?;
    }
    let (fc, fa) = float_kernel(inp);
    let slack = tol::FLOAT_KERNEL_SLACK_LSB;
    within("α vs f32 kernel", f64::from(got.a()), fa, ba + slack)?;
    for (g, f) in got.c().iter().zip(fc) {
        within("C̃ vs f32 kernel", f64::from(*g), f, bc + slack)?;
    }
    Ok(())
}

/// `premul_storage`: straight voxels stored premultiplied in `u8` and interpolated
/// (`Preweighted`) stay within the §7 limit of the exact `OpacityWeighted` sample, while
/// `OpacityWeighted` from the straight bytes stays within its own ½ LSB; the straight color
/// recovered from each sample is within the bound its `C̃` error implies; every
/// premultiply/unpremultiply of the voxels is within its bound.
///
/// # Errors
/// Which bound was exceeded, with the values.
pub fn premul_storage(inp: &CellInput) -> Result<(), String> {
    let ow_in = CellInput {
        kernel: IntKernel::OpacityWeighted,
        ..*inp
    };
    let stored = inp.voxels.map(|v| premultiply_voxel(StraightU8(v)).0);
    let pw_in = CellInput {
        kernel: IntKernel::Preweighted,
        voxels: stored,
        ..*inp
    };
    let exact = model(&ow_in);
    let ow = sample(&ow_in)?;
    let pw = sample(&pw_in)?;
    invariant(&ow, "OpacityWeighted")?;
    invariant(&pw, "Preweighted")?;
    for k in 0..3 {
        within(
            "OW C̃",
            f64::from(ow.c()[k]),
            exact.exact_c[k],
            tol::OPACITY_WEIGHTED_INT_LSB,
        )?;
        within(
            "PW C̃ (premultiplied storage)",
            f64::from(pw.c()[k]),
            exact.exact_c[k],
            tol::PREMUL_STORAGE_LSB,
        )?;
    }
    within(
        "PW α",
        f64::from(pw.a()),
        exact.exact_a,
        tol::PREWEIGHTED_INT_LSB,
    )?;
    if exact.exact_a > 0.0 {
        let straight = exact.exact_c.map(|c| 255.0 * c / exact.exact_a);
        for (s, name, cb) in [
            (ow, "OW", tol::OPACITY_WEIGHTED_INT_LSB),
            (pw, "PW", tol::PREMUL_STORAGE_LSB),
        ] {
            if s.a() == 0 {
                continue;
            }
            for (c, want) in s.c().iter().zip(straight) {
                let rec = 255.0 * f64::from(*c) / f64::from(s.a());
                within(
                    &format!("{name} recovered straight color"),
                    rec,
                    want,
                    tol::recovered_color_bound(cb, s.a()) + 1e-9,
                )?;
            }
        }
    }
    for v in inp.voxels {
        let a = v[3];
        for &c in &v[..3] {
            let p = premultiply(c, a);
            within(
                "premultiply",
                f64::from(p),
                f64::from(c) * f64::from(a) / 255.0,
                tol::PREMULTIPLY_LEVELS,
            )?;
            if a > 0 {
                within(
                    "§7 recovery",
                    255.0 * f64::from(p) / f64::from(a),
                    f64::from(c),
                    tol::PREMUL_RECOVERY_HALF * 255.0 / f64::from(a),
                )?;
                let u = unpremultiply(p, a);
                if u != pm::unpremultiply(p, a) {
                    return Err(format!("unpremultiply({p}, {a}) = {u} != model"));
                }
                within(
                    "unpremultiply",
                    f64::from(u),
                    f64::from(c),
                    (tol::PREMUL_RECOVERY_HALF * 255.0 / f64::from(a) + 0.5).floor(),
                )?;
            }
        }
    }
    Ok(())
}

/// Input of the `composite` check: raw sample values (made valid by reduction: `α mod
/// (ONE + 1)`, each `C̃ mod (α + 1)`) and an early-termination threshold.
#[derive(Debug, Clone, PartialEq, Eq, Default, Arbitrary)]
pub struct CompositeInput {
    /// Raw `[r, g, b, a]` per sample, front first.
    pub samples: Vec<[u16; 4]>,
    /// Raw threshold (reduced into `1..=ONE`).
    pub a_stop: u16,
}

impl CompositeInput {
    /// The valid samples (at most 4096).
    pub fn valid_samples(&self) -> Vec<IntSample> {
        self.samples
            .iter()
            .take(4096)
            .map(|&[r, g, b, a]| {
                let a = a % (ONE + 1);
                let c = [r, g, b].map(|c| c % (a + 1));
                IntSample::new(c, a).expect("reduced into the valid range")
            })
            .collect()
    }

    /// The threshold in `1..=ONE`.
    pub fn stop(&self) -> u16 {
        1 + self.a_stop % ONE
    }
}

fn raw(s: &IntSample) -> cm::Raw {
    let [r, g, b] = s.c();
    [r, g, b, s.a()]
}

/// `composite`: the integer front-to-back compositor matches its model bit for bit; the
/// accumulated opacity is monotone and `≤ ONE` and `C ≤ A` after every step; the result is
/// within `n/2` (`A`) and `n` (`C`) LSB of the exact front-to-back and back-to-front
/// composites; early termination loses at most `ONE − A_stop` plus the rounding of the
/// samples it skips.
///
/// # Errors
/// Which property failed, with the values.
pub fn composite(inp: &CompositeInput) -> Result<(), String> {
    let samples = inp.valid_samples();
    let raws: Vec<cm::Raw> = samples.iter().map(raw).collect();
    let mut acc = IntSample::TRANSPARENT;
    for s in &samples {
        let next = volsample::fixed_point::front_to_back(acc, *s);
        invariant(&next, "composite step")?;
        if next.a() < acc.a() || next.c().iter().zip(acc.c()).any(|(n, o)| *n < o) {
            return Err(format!("not monotone: {acc:?} -> {next:?}"));
        }
        acc = next;
    }
    let (full, n) = composite_front_to_back(samples.iter().copied(), IntStop::NEVER);
    let (model_full, _) = cm::front_to_back(&raws, ONE);
    if raw(&full) != model_full {
        return Err(format!("compositor {full:?} != model {model_full:?}"));
    }
    if n < samples.len() && full.a() < ONE {
        return Err(format!("stopped early at {n} with A = {} < ONE", full.a()));
    }
    let nf = n as f64;
    let f2b = cm::exact_front_to_back(&raws[..n]);
    let b2f = cm::exact_back_to_front(&raws[..n]);
    for k in 0..4 {
        let b = if k == 3 {
            tol::COMPOSITE_INT_A_LSB_PER_STEP * nf
        } else {
            tol::COMPOSITE_INT_C_LSB_PER_STEP * nf
        };
        within(
            "vs exact front to back",
            f64::from(raw(&full)[k]),
            f2b[k],
            b + 1e-6,
        )?;
        within(
            "vs exact back to front",
            f64::from(raw(&full)[k]),
            b2f[k],
            b + 1e-6,
        )?;
    }
    let stop = IntStop::new(inp.stop()).map_err(|e| e.to_string())?;
    let (early, m) = composite_front_to_back(samples.iter().copied(), stop);
    let (model_early, model_m) = cm::front_to_back(&raws, inp.stop());
    if raw(&early) != model_early || m != model_m {
        return Err(format!(
            "early {early:?}/{m} != model {model_early:?}/{model_m}"
        ));
    }
    let lost = f64::from(ONE - inp.stop()) + (samples.len() - m) as f64;
    for k in 0..4 {
        let d = f64::from(raw(&full)[k]) - f64::from(raw(&early)[k]);
        if d < 0.0 || d > lost {
            return Err(format!(
                "early termination lost {d} LSB in channel {k} > {lost} (A_stop {})",
                inp.stop()
            ));
        }
    }
    Ok(())
}

/// Input of the `extinction` check: raw `f32` bits of `τ` (any value: 0, subnormal, huge, ∞,
/// NaN) and of the step `d`, and straight color bytes; then a cell for the integer kernel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Arbitrary)]
pub struct ExtinctionInput {
    /// `τ` as `f32` bits.
    pub tau_bits: u32,
    /// `d` as `f32` bits (made finite and positive by taking `|d|` and skipping 0, NaN, ∞).
    pub d_bits: u32,
    /// Straight color bytes.
    pub color: [u8; 3],
    /// The integer kernel's cell (its ratio is `d/d′` with `d′ = 1`).
    pub int: ExtinctionCell,
}

/// Table sizes the `extinction` check exercises (`table_sel mod 4`).
pub const EXTINCTION_TABLE_SIZES: [usize; 4] = [17, 65, 257, 1025];

/// One integer `ExtinctionWeighted` sample of a 2×2×2 cell.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Arbitrary)]
pub struct ExtinctionCell {
    /// Straight voxels `[r, g, b, a]`, converted with `ExtinctionFx::from_straight_u8`.
    pub voxels: [[u8; 4]; 8],
    /// Raw `[τ, C^τ_r, C^τ_g, C^τ_b]` for voxels 0 and 1, used instead of the conversion when
    /// `τ ≠ 0` (reduced into range: `τ mod (MAX_DEPTH_RAW + 1)`, each `C^τ mod (τ + 1)`).
    pub raw: [[u32; 4]; 2],
    /// Raw fractions (only the low `F` bits are used).
    pub frac: [u32; 3],
    /// Selects `F = 4 + sel mod 9`.
    pub frac_bits_sel: u8,
    /// Trilinear (`true`) or nearest.
    pub trilinear: bool,
    /// Selects the table size from [`EXTINCTION_TABLE_SIZES`].
    pub table_sel: u8,
}

impl ExtinctionCell {
    /// `F` for this input.
    pub fn frac_bits(&self) -> u32 {
        4 + u32::from(self.frac_bits_sel) % 9
    }

    /// The table size.
    pub fn table_size(&self) -> usize {
        EXTINCTION_TABLE_SIZES[usize::from(self.table_sel % 4)]
    }

    /// The stored voxels, and whether all of them came from the straight bytes.
    pub fn stored(&self) -> ([ExtinctionFx; 8], bool) {
        let mut converted = true;
        let mut out = self
            .voxels
            .map(|v| ExtinctionFx::from_straight_u8(StraightU8(v)));
        for (o, r) in out.iter_mut().zip(self.raw) {
            if r[0] != 0 {
                let tau = r[0] % (em::MAX_DEPTH_RAW + 1);
                *o = ExtinctionFx {
                    tau,
                    c_tau: [r[1] % (tau + 1), r[2] % (tau + 1), r[3] % (tau + 1)],
                };
                converted = false;
            }
        }
        (out, converted)
    }

    /// The taps the sample reads and their real and integer weights (shift `3F`, or 0 for
    /// nearest), with the index of each tap in the cell.
    pub fn taps(&self) -> (Vec<usize>, Vec<f64>, Vec<u128>, u32) {
        let f = self.frac_bits();
        let m = (1u32 << f) - 1;
        let frac = self.frac.map(|x| x & m);
        if self.trilinear {
            (
                (0..8).collect(),
                int_model::trilinear_weights(f, frac).to_vec(),
                em::int_weights(f, frac).to_vec(),
                3 * f,
            )
        } else {
            let half = 1u32 << (f - 1);
            let idx = frac.map(|x| usize::from(x >= half));
            (
                vec![idx[0] + 2 * (idx[1] + 2 * idx[2])],
                vec![1.0],
                vec![1],
                0,
            )
        }
    }
}

macro_rules! cached_tables {
    ($($name:ident: $n:literal),*) => {
        $(
            fn $name() -> &'static ExtinctionTables<$n> {
                static T: OnceLock<ExtinctionTables<$n>> = OnceLock::new();
                T.get_or_init(ExtinctionTables::new)
            }
        )*
    };
}
cached_tables!(tables_17: 17, tables_65: 65, tables_257: 257, tables_1025: 1025);

/// The model's tables for each size in [`EXTINCTION_TABLE_SIZES`], built once.
pub fn model_tables(n: usize) -> &'static em::Tables {
    static T: OnceLock<Vec<em::Tables>> = OnceLock::new();
    let all = T.get_or_init(|| {
        EXTINCTION_TABLE_SIZES
            .iter()
            .map(|&n| em::tables(n))
            .collect()
    });
    let i = EXTINCTION_TABLE_SIZES
        .iter()
        .position(|&m| m == n)
        .expect("a checked size");
    &all[i]
}

fn extinction_kernel<const F: u32, const N: usize>(
    cell: &ExtinctionCell,
    data: &[ExtinctionFx; 8],
    tables: &ExtinctionTables<N>,
    ratio: f32,
) -> Result<IntSample, String> {
    let m = (1u32 << F) - 1;
    let pos = IntPos::<F>::from_raw(cell.frac.map(|f| f & m));
    let vol = Volume::new(&data[..], [2, 2, 2]).map_err(|e| e.to_string())?;
    let mode = IntExtinction::new(tables, ratio).map_err(|e| e.to_string())?;
    Ok(if cell.trilinear {
        IntSampler::new(vol, mode, Trilinear::new()).sample(pos)
    } else {
        IntSampler::new(vol, mode, Nearest).sample(pos)
    })
}

/// The integer `ExtinctionWeighted` sample of `cell` at ratio `ratio` (dispatching on `F`
/// and the table size).
///
/// # Errors
/// If the ratio is not valid for the integer kernel.
pub fn extinction_sample(cell: &ExtinctionCell, ratio: f32) -> Result<IntSample, String> {
    let (data, _) = cell.stored();
    with_frac_bits!(cell.frac_bits_sel, F => match cell.table_size() {
        17 => extinction_kernel::<F, 17>(cell, &data, tables_17(), ratio),
        65 => extinction_kernel::<F, 65>(cell, &data, tables_65(), ratio),
        257 => extinction_kernel::<F, 257>(cell, &data, tables_257(), ratio),
        _ => extinction_kernel::<F, 1025>(cell, &data, tables_1025(), ratio),
    })
}

/// Errors of one integer extinction sample, in U8.8 LSB: against the exact method on the
/// stored voxels (`C̃`, `α`), and against the `f64` reference on the straight voxels when
/// every voxel came from them.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ExtinctionErrors {
    /// Worst `C̃` error against the exact method.
    pub c: f64,
    /// `α` error against the exact method.
    pub a: f64,
    /// Worst `C̃` and `α` error against the reference (`None` with raw voxels).
    pub reference: Option<(f64, f64)>,
}

/// `extinction` (integer part): the kernel agrees bit for bit with its model, keeps
/// `C̃ ≤ α ≤ ONE`, and is within its stated bounds of the exact method on the stored voxels
/// and (plus the storage term) of the `f64` reference on the straight voxels.
///
/// # Errors
/// Which of these failed, with the values.
pub fn extinction_int(cell: &ExtinctionCell, ratio: f32) -> Result<ExtinctionErrors, String> {
    if IntRatio::new(ratio).is_err() {
        return Ok(ExtinctionErrors::default());
    }
    let got = extinction_sample(cell, ratio)?;
    invariant(&got, "extinction kernel")?;
    let (data, converted) = cell.stored();
    for (d, v) in data.iter().zip(cell.voxels) {
        if converted && (d.tau, d.c_tau) != em::from_u8(v) {
            return Err(format!(
                "conversion of {v:?}: {d:?} != model {:?}",
                em::from_u8(v)
            ));
        }
    }
    let (idx, w, wi, shift) = cell.taps();
    let taps: Vec<(u32, [u32; 3])> = idx.iter().map(|&i| (data[i].tau, data[i].c_tau)).collect();
    let n = cell.table_size();
    let r_raw = em::ratio_raw(ratio);
    let (mc, ma) = em::kernel(&taps, &wi, shift, r_raw, model_tables(n));
    if (got.c(), got.a()) != (mc, ma) {
        return Err(format!(
            "kernel {got:?} != model {mc:?}/{ma} for {cell:?}, r = {ratio:e}"
        ));
    }
    let r = f64::from(ratio);
    let (ec, ea) = em::exact(&taps, &w, r);
    let (bc, ba) = (tol::extinction_int_c_lsb(n), tol::extinction_int_a_lsb(n));
    let mut errs = ExtinctionErrors {
        a: (f64::from(got.a()) - ea).abs(),
        ..Default::default()
    };
    within("extinction α vs exact", f64::from(got.a()), ea, ba)?;
    for (g, e) in got.c().iter().zip(ec) {
        errs.c = errs.c.max((f64::from(*g) - e).abs());
        within("extinction C̃ vs exact", f64::from(*g), e, bc)?;
    }
    if converted {
        let straight: Vec<[u8; 4]> = idx.iter().map(|&i| cell.voxels[i]).collect();
        let (rc, ra) = em::reference(&straight, &w, r);
        let (sa, sc) = tol::extinction_int_storage_lsb(r);
        let ea = (f64::from(got.a()) - ra).abs();
        within("extinction α vs reference", f64::from(got.a()), ra, ba + sa)?;
        let mut ec = 0.0f64;
        for (g, e) in got.c().iter().zip(rc) {
            ec = ec.max((f64::from(*g) - e).abs());
            within("extinction C̃ vs reference", f64::from(*g), e, bc + sc)?;
        }
        errs.reference = Some((ec, ea));
    }
    Ok(errs)
}

/// `extinction`: for every `τ ≥ 0` (including subnormal, huge and ∞; NaN and negatives are
/// read as 0) and every finite `d > 0`, one step of the float extinction kernel gives finite
/// values with `0 ≤ C̃ ≤ α ≤ 1`; and the integer kernel on the input's cell at ratio `d`
/// passes [`extinction_int`].
///
/// # Errors
/// The non-finite or out-of-range output.
pub fn extinction(inp: &ExtinctionInput) -> Result<(), String> {
    let tau = f32::from_bits(inp.tau_bits);
    let d = f32::from_bits(inp.d_bits).abs();
    if !(d.is_finite() && d > 0.0) {
        return Ok(());
    }
    let c = inp.color.map(|c| f32::from(c) / 255.0);
    let c_tau = c.map(|c| {
        if c == 0.0 || tau.is_nan() {
            0.0
        } else {
            (tau * c).min(tau)
        }
    });
    let s = <ExtinctionWeighted as Mode<volsample::ExtinctionF32>>::finish(
        &ExtinctionWeighted,
        Interp { c: c_tau, a: tau },
        d,
    );
    if !s.is_valid() {
        return Err(format!("τ = {tau:e}, d = {d:e}: invalid sample {s:?}"));
    }
    extinction_int(&inp.int, d).map(|_| ())
}
