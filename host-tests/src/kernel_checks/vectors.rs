//! The `vectors` fuzz target: any request `volsample vectors` accepts (every kernel, `count`,
//! `seed`, `F`, table size) is generated, written to a scratch directory, and read back two
//! ways: by [`vectors::read`] (the code's own layouts) and field by field through the
//! manifest's field tables (what a test bench does with `$readmemh` and the manifest). Both
//! must give back the generated inputs and the core kernel's outputs, and every decoded case
//! run through the kernel again ([`vectors::expected_counted`]) must give the decoded output,
//! sample count included.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use arbitrary::Arbitrary;
use serde_json::Value;

use crate::vectors::{self, Kernel, Spec, VectorSet, TABLE_SIZES};

/// The most vectors one fuzz input asks for (corner cases first, then random ones).
pub const MAX_FUZZ_COUNT: usize = 48;

/// One `vectors` request, reduced into what the API accepts.
#[derive(Debug, Default, Clone, Arbitrary)]
pub struct VectorsInput {
    /// Index into [`Kernel::ALL`].
    pub kernel: u8,
    /// `1 + count % MAX_FUZZ_COUNT` vectors.
    pub count: u8,
    /// The generator's seed.
    pub seed: u64,
    /// `F = 4 + frac % 9`.
    pub frac: u8,
    /// Index into [`TABLE_SIZES`] (extinction kernels only).
    pub table: u8,
}

/// A scratch directory, removed when dropped.
struct Scratch(PathBuf);

impl Scratch {
    fn new() -> Self {
        static NEXT: AtomicU64 = AtomicU64::new(0);
        let n = NEXT.fetch_add(1, Ordering::Relaxed);
        Self(
            std::env::temp_dir().join(format!("volsample-fuzz-vectors-{}-{n}", std::process::id())),
        )
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Runs the check.
///
/// # Errors
/// Which file, vector and field disagreed, or the error of a request the API should accept.
pub fn vectors(i: &VectorsInput) -> Result<(), String> {
    let kernel = Kernel::ALL[usize::from(i.kernel) % Kernel::ALL.len()];
    let count = 1 + usize::from(i.count) % MAX_FUZZ_COUNT;
    let f = 4 + u32::from(i.frac) % 9;
    let name = kernel.name();
    let mut spec = Spec::new(name, count, i.seed, f).map_err(|e| format!("{name}: {e}"))?;
    if kernel.has_table_size() {
        let n = TABLE_SIZES[usize::from(i.table) % TABLE_SIZES.len()];
        spec = spec
            .with_table_size(n)
            .map_err(|e| format!("{name}: {e}"))?;
    }
    let set = vectors::build(&spec).map_err(|e| format!("{name}: build: {e}"))?;
    let dir = Scratch::new();
    vectors::write(&set, &dir.0).map_err(|e| format!("{name}: write: {e}"))?;
    let back = vectors::read(&dir.0).map_err(|e| format!("{name}: read: {e}"))?;
    let what = format!("{name} (count {count}, seed {}, F = {f})", i.seed);
    if back != set {
        return Err(format!(
            "{what}: the files read back differ from the set written"
        ));
    }
    through_manifest(&set, &dir.0).map_err(|e| format!("{what}: {e}"))?;
    for (k, case) in back.cases.iter().enumerate() {
        let (out, n) =
            vectors::expected_counted(&spec, case).map_err(|e| format!("{what}: {e}"))?;
        if out != back.expected[k] || n != back.samples_taken.get(k).copied() {
            return Err(format!(
                "{what}: vector {k} ({case:?}): the kernel gives {out:?} ({n:?} samples), the file {:?} ({:?})",
                back.expected[k],
                back.samples_taken.get(k)
            ));
        }
    }
    Ok(())
}

/// Every line of `inputs.hex` and `expected.hex` has the manifest's `hex_digits`, and decoded
/// field by field at the offsets and widths the manifest lists (raw bits; a two's complement
/// field as its bits) equals the generated case's field values and the kernel's outputs.
fn through_manifest(set: &VectorSet, dir: &Path) -> Result<(), String> {
    let read =
        |file: &str| std::fs::read_to_string(dir.join(file)).map_err(|e| format!("{file}: {e}"));
    let m: Value = serde_json::from_str(&read(vectors::MANIFEST_FILE)?)
        .map_err(|e| format!("manifest: {e}"))?;
    let counted = matches!(set.spec.kernel(), Kernel::RayMarch(_));
    let outputs: Vec<Vec<u64>> = set
        .expected
        .iter()
        .enumerate()
        .map(|(k, e)| {
            let mut v: Vec<u64> = e.iter().map(|&x| u64::from(x)).collect();
            if counted {
                v.extend(set.samples_taken.get(k).map(|&n| u64::from(n)));
            }
            v
        })
        .collect();
    let inputs = set
        .cases
        .iter()
        .map(vectors::case_values)
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| e.to_string())?;
    for (key, file, values) in [
        ("inputs", vectors::INPUTS_FILE, inputs),
        ("expected", vectors::EXPECTED_FILE, outputs),
    ] {
        let fields = m[key]["fields"]
            .as_array()
            .ok_or_else(|| format!("manifest: no {key}.fields"))?;
        let text = read(file)?;
        let lines: Vec<&str> = text.lines().collect();
        if lines.len() != values.len() {
            return Err(format!(
                "{file}: {} lines for {} vectors",
                lines.len(),
                values.len()
            ));
        }
        // (name, offset, width) of each field, as the manifest lists them.
        let fields: Vec<(String, usize, usize)> = fields
            .iter()
            .map(|f| {
                let num = |key: &str| f[key].as_u64().and_then(|x| usize::try_from(x).ok());
                match (f["name"].as_str(), num("offset"), num("width")) {
                    (Some(n), Some(o), Some(w)) if w <= 64 => Ok((n.to_string(), o, w)),
                    _ => Err(format!(
                        "manifest: {key}: a field without name, offset or width: {f}"
                    )),
                }
            })
            .collect::<Result<_, _>>()?;
        for (k, (line, want)) in lines.iter().zip(&values).enumerate() {
            if fields.len() != want.len() {
                return Err(format!(
                    "{file}: the manifest lists {} fields, the word has {}",
                    fields.len(),
                    want.len()
                ));
            }
            let digits = hex_digits(line).ok_or_else(|| format!("{file} line {k} is not hex"))?;
            if Some(digits.len() as u64) != m[key]["hex_digits"].as_u64() {
                return Err(format!(
                    "{file} line {k}: {} hex digits, the manifest says {}",
                    digits.len(),
                    m[key]["hex_digits"]
                ));
            }
            for ((name, offset, width), &w) in fields.iter().zip(want) {
                let got = field_bits(&digits, *offset, *width)
                    .ok_or_else(|| format!("{file} line {k}: field {name} lies past the word"))?;
                let mask = if *width >= 64 {
                    u64::MAX
                } else {
                    (1u64 << width) - 1
                };
                if got != w & mask {
                    return Err(format!(
                        "{file} line {k}: field {name} is {got:#x} by the manifest, {w:#x} generated"
                    ));
                }
            }
        }
    }
    Ok(())
}

/// The hex digits of a line, least significant first; `None` unless every character is one.
fn hex_digits(line: &str) -> Option<Vec<u8>> {
    line.chars()
        .rev()
        .map(|c| c.to_digit(16).and_then(|d| u8::try_from(d).ok()))
        .collect()
}

/// The raw bits of one field (`offset`, `width ≤ 64`) of a word given by its hex digits (least
/// significant first), bit 0 the least significant; `None` if the field lies past the word.
fn field_bits(digits: &[u8], offset: usize, width: usize) -> Option<u64> {
    if width > 64 || (offset + width).div_ceil(4) > digits.len() {
        return None;
    }
    let bit = |b: usize| u64::from((digits[b / 4] >> (b % 4)) & 1);
    Some((0..width).fold(0u64, |acc, b| acc | bit(offset + b) << b))
}
