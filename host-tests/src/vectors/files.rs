//! Vector sets on disk: the manifest, writing, reading back, and the `volsample vectors`
//! command.

use std::path::{Path, PathBuf};

use serde_json::{json, Value};
use volsample::fixed_point::ONE;

use super::words::{hex_text, layout_json, read_hex, Layout, Word};
use super::{
    case_from_values, composite, corner_count, correction, downsample, expected_all, extinction,
    generate, input_layout, input_values, output_layout, ray_march, sampling, Case, Kernel, Raw,
    Spec, VectorError, EXPECTED_FILE, GENERATOR_VERSION, INPUTS_FILE, MANIFEST_FILE,
};

fn rounding_json(spec: &Spec) -> Value {
    let f = spec.frac_bits;
    match spec.kernel {
        Kernel::Sample(mode, filter) => sampling::rounding_json(mode, filter, f),
        Kernel::Composite => composite::rounding_json(),
        Kernel::Downsample => downsample::rounding_json(),
        Kernel::Correction => correction::rounding_json(),
        Kernel::Extinction(filter) => extinction::rounding_json(filter, f, spec.table_size),
        Kernel::RayMarch(filter) => ray_march::rounding_json(filter, f),
    }
}

fn generator_json(spec: &Spec) -> Value {
    let draws = match spec.kernel {
        Kernel::Sample(mode, _) => sampling::generator_draws(mode),
        Kernel::Composite => composite::GENERATOR_DRAWS,
        Kernel::Downsample => downsample::GENERATOR_DRAWS,
        Kernel::Correction => correction::GENERATOR_DRAWS,
        Kernel::Extinction(_) => extinction::GENERATOR_DRAWS,
        Kernel::RayMarch(_) => ray_march::GENERATOR_DRAWS,
    };
    json!({
        "name": "volsample vectors",
        "version": GENERATOR_VERSION,
        "prng": "SplitMix64: state += 0x9E3779B97F4A7C15; z = state; z = (z ^ (z >> 30))·0xBF58476D1CE4E5B9; z = (z ^ (z >> 27))·0x94D049BB133111EB; next() = z ^ (z >> 31) (wrapping u64)",
        "seeding": "state = seed before the first draw; corner cases come first and draw nothing",
        "random_draws": draws,
    })
}

/// The lookup tables a kernel reads, written beside the vectors (none for most kernels).
fn tables(spec: &Spec) -> Result<Vec<TableFile>, VectorError> {
    match spec.kernel {
        Kernel::Correction | Kernel::RayMarch(_) => Ok(super::correction_tables()),
        Kernel::Extinction(_) => super::extinction_tables(spec.table_size),
        _ => Ok(Vec::new()),
    }
}

/// The manifest of a request.
pub fn manifest(spec: &Spec) -> Value {
    let what = match spec.kernel {
        Kernel::Sample(..) => sampling::DESCRIPTION,
        Kernel::Composite => composite::DESCRIPTION,
        Kernel::Downsample => downsample::DESCRIPTION,
        Kernel::Correction => correction::DESCRIPTION,
        Kernel::Extinction(_) => extinction::DESCRIPTION,
        Kernel::RayMarch(_) => ray_march::DESCRIPTION,
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
    if spec.kernel.has_table_size() {
        m["table_size"] = json!(spec.table_size);
        m["tables_note"] = json!("the entries as volsample::fixed_point::ExtinctionTables::<table_size>::new() builds them (f64 with libm, one round half up per entry); load the table_*.hex files for bit-exact results");
    }
    let tables = tables(spec).unwrap_or_default();
    if !tables.is_empty() {
        m["tables"] = json!(tables
            .iter()
            .map(|t| json!({"file": t.file, "entries": t.values.len(), "word_bits": t.bits, "hex_digits": t.bits.div_ceil(4), "meaning": t.meaning}))
            .collect::<Vec<_>>());
    }
    m
}

/// One lookup table, as written to `table_*.hex`.
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

/// A generated vector set.
#[derive(Debug, Clone, PartialEq)]
pub struct VectorSet {
    /// The request.
    pub spec: Spec,
    /// The inputs.
    pub cases: Vec<Case>,
    /// The expected outputs (from the core kernels).
    pub expected: Vec<Raw>,
    /// For the `ray-march-*` kernels the number of samples each ray composited (from the
    /// core); empty for the other kernels.
    pub samples_taken: Vec<u32>,
}

/// Generates the vectors of a request and their expected outputs.
///
/// # Errors
/// [`VectorError::Core`] if a core constructor rejects a generated input (a generator bug).
pub fn build(spec: &Spec) -> Result<VectorSet, VectorError> {
    let cases = generate(spec);
    let outputs = expected_all(spec, &cases)?;
    Ok(VectorSet {
        spec: *spec,
        expected: outputs.iter().map(|o| o.0).collect(),
        samples_taken: outputs.iter().filter_map(|o| o.1).collect(),
        cases,
    })
}

fn write_file(path: PathBuf, text: &str) -> Result<(), VectorError> {
    std::fs::write(&path, text).map_err(|source| VectorError::Write { path, source })
}

/// Writes a vector set into `dir` (created if missing): `inputs.hex`, `expected.hex`,
/// `manifest.json` and the kernel's tables, if any.
///
/// # Errors
/// [`VectorError::Write`] naming the path that could not be created or written;
/// [`VectorError::InvalidCase`] if a ray-march set lacks its sample counts.
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
    let counted = matches!(set.spec.kernel, Kernel::RayMarch(_));
    if counted && set.samples_taken.len() != set.expected.len() {
        return Err(VectorError::InvalidCase(format!(
            "{} expected samples but {} sample counts",
            set.expected.len(),
            set.samples_taken.len()
        )));
    }
    let outputs: Vec<Word> = set
        .expected
        .iter()
        .enumerate()
        .map(|(i, e)| {
            let mut v = e.map(u64::from).to_vec();
            if let Some(&n) = set.samples_taken.get(i).filter(|_| counted) {
                v.push(u64::from(n));
            }
            ol.pack(&v)
        })
        .collect();
    write_file(dir.join(INPUTS_FILE), &hex_text(&il, &inputs))?;
    write_file(dir.join(EXPECTED_FILE), &hex_text(&ol, &outputs))?;
    for t in tables(&set.spec)? {
        let l = Layout::single("entry", t.bits);
        let words: Vec<Word> = t.values.iter().map(|&v| l.pack(&[v])).collect();
        write_file(dir.join(t.file), &hex_text(&l, &words))?;
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
/// `inputs.hex` and the expected outputs (and ray-march sample counts) from `expected.hex`.
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
    let mut spec = Spec::new(kernel, count as usize, seed, frac_bits)?;
    if spec.kernel.has_table_size() {
        let n = m["table_size"]
            .as_u64()
            .and_then(|n| usize::try_from(n).ok())
            .ok_or_else(|| parse_err(&mpath, "no \"table_size\"".into()))?;
        spec = spec.with_table_size(n)?;
    }
    let il = input_layout(&spec);
    let ipath = dir.join(INPUTS_FILE);
    let cases = read_hex(&ipath, &il)?
        .iter()
        .enumerate()
        .map(|(n, w)| {
            case_from_values(&spec, &il.unpack(w))
                .ok_or_else(|| parse_err(&ipath, format!("word {n} does not decode")))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let ol = output_layout(&spec);
    let epath = dir.join(EXPECTED_FILE);
    let words: Vec<Vec<u64>> = read_hex(&epath, &ol)?
        .iter()
        .map(|w| ol.unpack(w))
        .collect();
    let expected: Vec<Raw> = words
        .iter()
        .map(|v| std::array::from_fn(|k| v.get(k).copied().unwrap_or(0) as u16))
        .collect();
    let samples_taken = if matches!(spec.kernel, Kernel::RayMarch(_)) {
        words
            .iter()
            .map(|v| v.get(4).copied().unwrap_or(0) as u32)
            .collect()
    } else {
        Vec::new()
    };
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
        samples_taken,
    })
}

/// `volsample vectors` for a validated request: generates, writes and reports.
///
/// # Errors
/// A message for a file that cannot be written.
pub fn run_spec(spec: &Spec, out: &Path) -> Result<String, VectorError> {
    let set = build(spec)?;
    write(&set, out)?;
    let tables = if spec.kernel.has_table_size() {
        format!(", table size {}", spec.table_size)
    } else {
        String::new()
    };
    Ok(format!(
        "{}: {} vectors ({} corner cases, then random; seed {}, F = {}{tables}) -> {}/{{{INPUTS_FILE}, {EXPECTED_FILE}, {MANIFEST_FILE}}}",
        spec.kernel.name(),
        spec.count,
        corner_count(spec),
        spec.seed,
        spec.frac_bits,
        out.display()
    ))
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
    run_spec(&Spec::new(kernel, count, seed, frac_bits)?, out)
}
