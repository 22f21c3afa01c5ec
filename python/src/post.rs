//! Post-classification: scalar volumes `(z, y, x)` and the core's `TransferFunction`
//! (`PostClassified`: interpolate the scalar, then classify, `C̃ = α·C`).

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2, PyReadonlyArray1, PyReadonlyArray3, PyUntypedArrayMethods};
use pyo3::prelude::*;
use volsample::{ControlPoint, Error, PostClassified, Sample};

use crate::{core_err, value_err, FilterName, Params};
use crate::{render_kernel, sample_kernel, CameraKind, RenderOpts};
use volsample::{Nearest, Trilinear, TriquadraticBSpline};

/// The most control points a Python `TransferFunction` holds (the core's capacity `N`).
pub(crate) const TF_CAPACITY: usize = 256;

/// A piecewise-linear transfer function (the core's `TransferFunction`): scalar `s` to
/// straight color and opacity, linear between control points, the end values outside them.
#[pyclass(frozen, module = "volsample")]
#[derive(Clone, Debug)]
pub(crate) struct TransferFunction {
    pub(crate) tf: volsample::TransferFunction<TF_CAPACITY>,
}

#[pymethods]
impl TransferFunction {
    /// Control points `(s, r, g, b, a)`, `s` strictly increasing, colors and opacities in
    /// `[0, 1]` (opacity for the reference distance); at most 256.
    #[new]
    fn new(points: &Bound<'_, PyAny>) -> PyResult<Self> {
        let rows: Vec<Vec<f32>> = points
            .extract()
            .map_err(|_| value_err("points must be a sequence of (s, r, g, b, a) rows"))?;
        let mut cps = Vec::with_capacity(rows.len());
        for r in &rows {
            let &[s, red, g, b, a] = r.as_slice() else {
                return Err(value_err(
                    "points must be a sequence of (s, r, g, b, a) rows",
                ));
            };
            cps.push(ControlPoint {
                s,
                c: [red, g, b],
                a,
            });
        }
        let tf = volsample::TransferFunction::new(&cps).map_err(core_err)?;
        Ok(Self { tf })
    }

    /// The control points as a `(n, 5)` `float32` array of `(s, r, g, b, a)`.
    #[getter]
    fn points<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f32>>> {
        let flat: Vec<f32> = self
            .tf
            .points()
            .iter()
            .flat_map(|p| [p.s, p.c[0], p.c[1], p.c[2], p.a])
            .collect();
        let n = flat.len() / 5;
        Array2::from_shape_vec((n, 5), flat)
            .map(|a| a.into_pyarray(py))
            .map_err(|e| value_err(format!("internal shape error: {e}")))
    }

    /// Straight color and opacity `(n, 4)` `float32` at the scalars `s` (`(n,)` `float32`).
    fn eval<'py>(
        &self,
        py: Python<'py>,
        s: PyReadonlyArray1<'py, f32>,
    ) -> PyResult<Bound<'py, PyArray2<f32>>> {
        let s: Vec<f32> = s.as_array().iter().copied().collect();
        let tf = &self.tf;
        let out: Vec<[f32; 4]> = py.allow_threads(|| {
            s.iter()
                .map(|&x| {
                    let (c, a) = tf.eval(x);
                    [c[0], c[1], c[2], a]
                })
                .collect()
        });
        Ok(crate::to_array2(out)?.into_pyarray(py))
    }

    fn __len__(&self) -> usize {
        self.tf.points().len()
    }

    fn __repr__(&self) -> String {
        format!("TransferFunction({} points)", self.tf.points().len())
    }
}

/// A scalar volume's voxels, in the core's scalar voxel types.
pub(crate) enum Scalars {
    U8(Vec<u8>),
    U16(Vec<u16>),
    F32(Vec<f32>),
}

fn read_scalars_of<T: numpy::Element + Copy>(
    obj: &Bound<'_, PyAny>,
) -> Option<(Vec<T>, [usize; 3])> {
    let a = obj.extract::<PyReadonlyArray3<'_, T>>().ok()?;
    let s = a.shape();
    let dims = [s[2], s[1], s[0]];
    let v = a.as_array();
    Some((v.as_standard_layout().iter().copied().collect(), dims))
}

/// Reads a `(z, y, x)` `uint8`, `uint16` or `float32` scalar volume and its `[x, y, z]` dims.
pub(crate) fn read_scalars(obj: &Bound<'_, PyAny>) -> PyResult<(Scalars, [usize; 3])> {
    read_scalars_for(obj, "mode 'post_classified'")
}

/// [`read_scalars`] for `who` (named in the error).
pub(crate) fn read_scalars_for(
    obj: &Bound<'_, PyAny>,
    who: &str,
) -> PyResult<(Scalars, [usize; 3])> {
    if let Some((d, dims)) = read_scalars_of::<u8>(obj) {
        return Ok((Scalars::U8(d), dims));
    }
    if let Some((d, dims)) = read_scalars_of::<u16>(obj) {
        return Ok((Scalars::U16(d), dims));
    }
    if let Some((d, dims)) = read_scalars_of::<f32>(obj) {
        return Ok((Scalars::F32(d), dims));
    }
    Err(value_err(format!(
        "{who} reads a scalar volume: a numpy array of shape (z, y, x) and dtype uint8, uint16 or float32"
    )))
}

/// Runs `$k(data, PostClassified::new(tf), filter, args…)` for the scalar type at hand.
macro_rules! run_post {
    ($scalars:expr, $tf:expr, $filter:expr, $k:ident ( $($arg:expr),* )) => {{
        let m = PostClassified::new($tf);
        match $scalars {
            Scalars::U8(d) => with_filter!($filter, f => $k(d, m, f, $($arg),*)),
            Scalars::U16(d) => with_filter!($filter, f => $k(d, m, f, $($arg),*)),
            Scalars::F32(d) => with_filter!($filter, f => $k(d, m, f, $($arg),*)),
        }
    }};
}

/// `sample(…, mode="post_classified", tf=…)`: `(n, 4)` associated samples.
pub(crate) fn sample_post(
    py: Python<'_>,
    volume: &Bound<'_, PyAny>,
    pos: &[[f32; 3]],
    tf: &TransferFunction,
    filter: FilterName,
    step: f32,
    reference_distance: f32,
) -> PyResult<Vec<[f32; 4]>> {
    let (scalars, dims) = read_scalars(volume)?;
    let p = Params {
        dims,
        step,
        d_ref: reference_distance,
    };
    let tf = &tf.tf;
    let out: Result<_, Error> =
        py.allow_threads(|| run_post!(&scalars, tf, filter, sample_kernel(p, pos)));
    out.map_err(core_err)
}

/// `render(…, mode="post_classified", tf=…)`: the image's pixels, row-major.
#[allow(clippy::too_many_arguments)]
pub(crate) fn render_post(
    py: Python<'_>,
    volume: &Bound<'_, PyAny>,
    tf: &TransferFunction,
    filter: FilterName,
    (step, reference_distance): (f32, f32),
    cam: CameraKind,
    size: (usize, usize),
    threads: usize,
    o: RenderOpts,
    img: &mut [Sample],
) -> PyResult<()> {
    let (scalars, dims) = read_scalars(volume)?;
    let p = Params {
        dims,
        step,
        d_ref: reference_distance,
    };
    let tf = &tf.tf;
    let out: Result<_, Error> = py.allow_threads(|| {
        run_post!(
            &scalars,
            tf,
            filter,
            render_kernel(p, cam, size, threads, o, img)
        )
    });
    out.map_err(core_err)
}
