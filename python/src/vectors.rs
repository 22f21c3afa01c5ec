//! The HDL reference vectors: `vectors` writes a vector set exactly as the CLI's
//! `volsample vectors` does (the same `volsample_host::vectors::Spec` and `run_spec`, so the
//! files are the CLI's byte for byte), `read_vectors` reads one back as field values.

use std::path::PathBuf;

use numpy::ndarray::Array2;
use numpy::IntoPyArray;
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use volsample_host::vectors::{
    case_values, input_layout, output_layout, read, run_spec, Spec, VectorError, VectorSet,
    MANIFEST_FILE,
};

/// A file that cannot be written or read is an `OSError`; everything else (an unknown kernel,
/// a zero count, a malformed file, …) a `ValueError`, each with the library's message.
fn vectors_err(e: VectorError) -> PyErr {
    match e {
        VectorError::Write { .. } | VectorError::Read { .. } => PyOSError::new_err(e.to_string()),
        _ => PyValueError::new_err(e.to_string()),
    }
}

/// `json.loads(text)`.
fn json_loads<'py>(py: Python<'py>, text: &str) -> PyResult<Bound<'py, PyAny>> {
    py.import("json")?.call_method1("loads", (text,))
}

/// Generates the reference vectors of an integer kernel into `out` (created if missing):
/// `inputs.hex`, `expected.hex`, `manifest.json` and the kernel's `table_*.hex`, byte for
/// byte what `volsample vectors --kernel … --count … --seed … --frac-bits …
/// [--table-size …] --out …` writes. Returns the manifest as a dict.
#[pyfunction]
#[pyo3(signature = (kernel, out, count = 10_000, seed = 1, frac_bits = 8, table_size = None))]
pub(crate) fn vectors<'py>(
    py: Python<'py>,
    kernel: &str,
    out: PathBuf,
    count: usize,
    seed: u64,
    frac_bits: u32,
    table_size: Option<usize>,
) -> PyResult<Bound<'py, PyAny>> {
    // As the CLI: validate the request, then generate and write.
    let spec = Spec::new(kernel, count, seed, frac_bits)
        .and_then(|s| match table_size {
            Some(n) => s.with_table_size(n),
            None => Ok(s),
        })
        .map_err(vectors_err)?;
    py.allow_threads(|| run_spec(&spec, &out))
        .map_err(vectors_err)?;
    json_loads(py, &volsample_host::vectors::manifest(&spec).to_string())
}

/// The field values of each word, one row per vector (two's complement fields as their bits).
fn rows(values: Rows, fields: usize) -> PyResult<Array2<u64>> {
    let n = values.len();
    let flat: Vec<u64> = values.into_iter().flatten().collect();
    Array2::from_shape_vec((n, fields), flat)
        .map_err(|e| PyValueError::new_err(format!("internal shape error: {e}")))
}

/// The low `width` bits.
fn mask(width: u32) -> u64 {
    if width >= 64 {
        u64::MAX
    } else {
        (1 << width) - 1
    }
}

/// One row of field values per vector.
type Rows = Vec<Vec<u64>>;

/// The inputs and expected outputs of a read set as field values.
fn field_values(set: &VectorSet) -> Result<(Rows, Rows), VectorError> {
    // `case_values` gives a two's complement field sign-extended to 64 bits: keep the field's
    // own bits, as the word holds them.
    let widths: Vec<u32> = input_layout(&set.spec)
        .fields
        .iter()
        .map(|f| f.width)
        .collect();
    let inputs = set
        .cases
        .iter()
        .map(|c| {
            let v = case_values(c)?;
            Ok(v.iter().zip(&widths).map(|(&x, &w)| x & mask(w)).collect())
        })
        .collect::<Result<Vec<_>, VectorError>>()?;
    let expected = set
        .expected
        .iter()
        .enumerate()
        .map(|(i, e)| {
            let mut v: Vec<u64> = e.iter().map(|&x| u64::from(x)).collect();
            if let Some(&n) = set.samples_taken.get(i) {
                v.push(u64::from(n));
            }
            v
        })
        .collect();
    Ok((inputs, expected))
}

/// Reads a vector directory back (`volsample_host::vectors::read`: the manifest, then every
/// word of `inputs.hex` and `expected.hex` checked against its layout and count): a dict with
/// `manifest` (the parsed `manifest.json`), `inputs` and `expected` (`(count, fields)`
/// `uint64` arrays of field values, a two's complement field as its own `width` bits) and
/// `input_fields` / `expected_fields` (the field names, in column order).
#[pyfunction]
pub(crate) fn read_vectors<'py>(py: Python<'py>, dir: PathBuf) -> PyResult<Bound<'py, PyDict>> {
    let (set, inputs, expected) = py
        .allow_threads(|| {
            let set = read(&dir)?;
            let (i, e) = field_values(&set)?;
            Ok((set, i, e))
        })
        .map_err(vectors_err)?;
    let (il, ol) = (input_layout(&set.spec), output_layout(&set.spec));
    let names = |l: &volsample_host::vectors::Layout| {
        l.fields.iter().map(|f| f.name.clone()).collect::<Vec<_>>()
    };
    let text = std::fs::read_to_string(dir.join(MANIFEST_FILE))
        .map_err(|e| PyOSError::new_err(format!("{}: {e}", dir.join(MANIFEST_FILE).display())))?;
    let d = PyDict::new(py);
    d.set_item("manifest", json_loads(py, &text)?)?;
    d.set_item("inputs", rows(inputs, il.fields.len())?.into_pyarray(py))?;
    d.set_item(
        "expected",
        rows(expected, ol.fields.len())?.into_pyarray(py),
    )?;
    d.set_item("input_fields", names(&il))?;
    d.set_item("expected_fields", names(&ol))?;
    Ok(d)
}
