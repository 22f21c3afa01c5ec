//! The fixed kernel suite of the volsample firmware check (issue 6).
//!
//! The same source runs on Cortex-M under QEMU (`volsample-firmware`, bin `suite`) and on the
//! host (`volsample-fw-host`); each prints one line per result, every value as the hex bit
//! pattern of its `f32` (`to_bits`) or integer, and `run.sh` requires the outputs to be
//! identical byte for byte. The inputs are built in: a small volume from a fixed integer
//! generator, converted to every voxel format, fixed and generated positions, rays, cameras.
//!
//! Line format: `<case>[.<variant>]/<index> <hex> <hex> …`; big sweeps print one
//! `…/digest n=<count> <fnv64>` line instead of their values (the digest covers every value
//! bit for bit). The last line is `# suite lines=<L> values=<N> fnv64=<hash of all values>`.
//!
//! # Adding a kernel
//! Write a `fn(&mut Emitter<'_>, &Inputs)` that calls the kernel on the inputs and emits its
//! results, and add it with a unique name to [`CASES`]; both sides pick it up. New kernel
//! families (e.g. downsampling, which is not in the core yet) go in their own module here.
#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_docs)]

mod float;
mod int;

use core::fmt::{self, Write as _};

use volsample::{
    AssociatedF32, AssociatedU8, ControlPoint, Error, ExtinctionF32, Sample, StraightF32,
    StraightU8, TransferFunction,
};

/// Where the suite's lines go: semihosting stdout on the target, stdout on the host.
pub trait Out {
    /// Writes one line (without its newline).
    fn line(&mut self, s: &str);
}

/// Longest line the suite prints.
const LINE: usize = 512;

/// FNV-1a, 64 bit, over the little-endian bytes of each 32-bit word.
#[derive(Debug, Clone, Copy)]
struct Fnv(u64);

impl Fnv {
    const fn new() -> Self {
        Self(0xcbf2_9ce4_8422_2325)
    }
    fn word(&mut self, w: u32) {
        for b in w.to_le_bytes() {
            self.0 = (self.0 ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
        }
    }
}

/// Formats results as hex lines and counts them.
pub struct Emitter<'o> {
    out: &'o mut dyn Out,
    lines: u32,
    values: u32,
    all: Fnv,
    overflow: bool,
}

impl<'o> Emitter<'o> {
    /// An emitter writing to `out`.
    pub fn new(out: &'o mut dyn Out) -> Self {
        Self {
            out,
            lines: 0,
            values: 0,
            all: Fnv::new(),
            overflow: false,
        }
    }

    fn flush(&mut self, s: &heapless::String<LINE>, ok: bool) {
        self.overflow |= !ok;
        self.lines += 1;
        self.out.line(s);
    }

    /// One line: `name/idx` and each word in hex.
    pub fn words(
        &mut self,
        name: fmt::Arguments<'_>,
        idx: usize,
        words: impl IntoIterator<Item = u32>,
    ) {
        let mut s = heapless::String::<LINE>::new();
        let mut ok = write!(s, "{name}/{idx}").is_ok();
        for w in words {
            self.values += 1;
            self.all.word(w);
            ok &= write!(s, " {w:08x}").is_ok();
        }
        self.flush(&s, ok);
    }

    /// One line of `f32` bit patterns.
    pub fn f32s(&mut self, name: fmt::Arguments<'_>, idx: usize, v: &[f32]) {
        self.words(name, idx, v.iter().map(|x| x.to_bits()));
    }

    /// One line holding a sample: `C̃` then `α`.
    pub fn sample(&mut self, name: fmt::Arguments<'_>, idx: usize, s: Sample) {
        let [r, g, b] = s.c;
        self.f32s(name, idx, &[r, g, b, s.a]);
    }

    /// One line for a big sweep: the value count and the FNV-1a-64 of every value.
    pub fn digest(&mut self, name: fmt::Arguments<'_>, words: impl IntoIterator<Item = u32>) {
        let mut h = Fnv::new();
        let mut n = 0u32;
        for w in words {
            n += 1;
            h.word(w);
            self.all.word(w);
        }
        self.values += n;
        let mut s = heapless::String::<LINE>::new();
        let ok = write!(s, "{name}/digest n={n} {:016x}", h.0).is_ok();
        self.flush(&s, ok);
    }

    /// One line for a constructor that refused its input.
    pub fn error(&mut self, name: fmt::Arguments<'_>, idx: usize, e: Error) {
        let mut s = heapless::String::<LINE>::new();
        let ok = write!(s, "{name}/{idx} err {e:?}").is_ok();
        self.flush(&s, ok);
    }

    /// Values emitted so far.
    pub fn values(&self) -> u32 {
        self.values
    }
}

/// Volume dimensions of the built-in inputs.
pub const DIMS: [usize; 3] = [4, 3, 3];
/// Voxel count.
pub const N: usize = DIMS[0] * DIMS[1] * DIMS[2];

/// A fixed linear congruential generator (Numerical Recipes constants): the same numbers
/// everywhere, integer arithmetic only.
#[derive(Debug, Clone, Copy)]
pub struct Lcg(u32);

impl Lcg {
    /// Seeded generator.
    pub const fn new(seed: u32) -> Self {
        Self(seed)
    }
    /// Next 32-bit value.
    pub fn next_u32(&mut self) -> u32 {
        self.0 = self.0.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        self.0
    }
    /// Next byte (the high bits).
    pub fn next_u8(&mut self) -> u8 {
        (self.next_u32() >> 24) as u8
    }
    /// Next `f32` in `[lo, hi)` with 16 random bits (exact arithmetic up to the final scale).
    pub fn next_f32(&mut self, lo: f32, hi: f32) -> f32 {
        let u = (self.next_u32() >> 16) as f32 / 65536.0;
        lo + u * (hi - lo)
    }
}

/// The built-in inputs, every voxel format of the same volume.
#[derive(Debug, Clone)]
pub struct Inputs {
    /// Straight RGBA bytes.
    pub su8: [StraightU8; N],
    /// The same, as `f32`.
    pub sf32: [StraightF32; N],
    /// Premultiplied (Drebin) bytes, rounded half up.
    pub au8: [AssociatedU8; N],
    /// Associated `f32`.
    pub af32: [AssociatedF32; N],
    /// Extinction form for `d′ = 1`.
    pub ext: [ExtinctionF32; N],
    /// `u8` scalars (the opacity byte).
    pub s8: [u8; N],
    /// `u16` scalars.
    pub s16: [u16; N],
    /// A transfer function over `0..=255` (also applied to the `u16` scalars, which then
    /// mostly clamp at its end: on purpose).
    pub tf: TransferFunction<4>,
}

impl Inputs {
    /// Builds the inputs. Voxels 0 and 1 are Wittenbrink's fig. 4 pair (opaque white next to
    /// transparent red); voxel 2 is nearly transparent blue (the premultiplied-storage limit);
    /// the rest come from the generator, a quarter of them opaque and a quarter transparent.
    ///
    /// # Errors
    /// None for the fixed control points; the `Result` keeps the suite panic-free.
    pub fn new() -> Result<Self, Error> {
        let mut g = Lcg::new(0x5eed_0006);
        let mut su8 = [StraightU8([0; 4]); N];
        for (i, v) in su8.iter_mut().enumerate() {
            let [r, gr, b] = [g.next_u8(), g.next_u8(), g.next_u8()];
            let a = match g.next_u8() >> 6 {
                0 => 0,
                1 => 255,
                _ => g.next_u8(),
            };
            *v = match i {
                0 => StraightU8([255, 255, 255, 255]),
                1 => StraightU8([255, 0, 0, 0]),
                2 => StraightU8([0, 0, 255, 1]),
                _ => StraightU8([r, gr, b, a]),
            };
        }
        let sf32 = su8.map(|StraightU8([r, g, b, a])| StraightF32 {
            c: [r, g, b].map(volsample::voxel::unorm8),
            a: volsample::voxel::unorm8(a),
        });
        let tf = TransferFunction::new(&[
            ControlPoint {
                s: 0.0,
                c: [0.0, 0.0, 0.0],
                a: 0.0,
            },
            ControlPoint {
                s: 40.0,
                c: [1.0, 0.25, 0.0],
                a: 0.1,
            },
            ControlPoint {
                s: 160.0,
                c: [0.5, 0.75, 1.0],
                a: 0.6,
            },
            ControlPoint {
                s: 255.0,
                c: [1.0, 1.0, 1.0],
                a: 1.0,
            },
        ])?;
        Ok(Self {
            su8,
            sf32,
            au8: su8.map(volsample::fixed_point::premultiply_voxel),
            af32: sf32.map(AssociatedF32::from_straight),
            ext: sf32.map(|v| ExtinctionF32::from_straight(v, 1.0)),
            s8: su8.map(|v| v.0[3]),
            s16: su8.map(|v| (u16::from(v.0[0]) << 8) | u16::from(v.0[3])),
            tf,
        })
    }
}

/// A named case of the suite.
pub type Case = fn(&mut Emitter<'_>, &Inputs);

/// Every case, in output order. Add new kernels here.
pub const CASES: &[(&str, Case)] = &[
    ("unorm8", float::unorm8),
    ("weights", float::weights),
    ("phi", float::phi),
    ("correct", float::correct),
    ("integrate_step", float::integrate_step),
    ("composite", float::composite),
    ("tf", float::tf),
    ("clip", float::clip),
    ("sample", float::sample),
    ("cast", float::cast),
    ("render", float::render),
    ("int.rounding", int::rounding),
    ("int.pos", int::pos),
    ("int.weights", int::weights),
    ("int.sample", int::sample),
    ("int.correction", int::correction),
    ("int.composite", int::composite),
    ("int.premul", int::premul),
    ("int.ray", int::ray),
    ("int.extinction", int::extinction),
    ("int.marcher", int::marcher),
];

/// What a run printed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Summary {
    /// Lines printed (the summary line not included).
    pub lines: u32,
    /// Values compared (each `f32` or integer result once).
    pub values: u32,
    /// A line did not fit the line buffer (a suite bug: the run must fail).
    pub overflow: bool,
}

/// Runs every case of [`CASES`] and prints the summary line.
pub fn run(out: &mut dyn Out) -> Summary {
    let mut e = Emitter::new(out);
    match Inputs::new() {
        Ok(inputs) => {
            for (_, case) in CASES {
                case(&mut e, &inputs);
            }
        }
        Err(err) => e.error(format_args!("inputs"), 0, err),
    }
    let summary = Summary {
        lines: e.lines,
        values: e.values,
        overflow: e.overflow,
    };
    let mut s = heapless::String::<LINE>::new();
    let ok = write!(
        s,
        "# suite lines={} values={} fnv64={:016x}{}",
        e.lines,
        e.values,
        e.all.0,
        if e.overflow { " OVERFLOW" } else { "" }
    )
    .is_ok();
    e.out.line(if ok { &s } else { "# suite OVERFLOW" });
    summary
}
