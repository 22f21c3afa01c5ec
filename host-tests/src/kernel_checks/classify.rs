//! `classify`: the classification and shading pre-passes against the f64 reference.

use arbitrary::Arbitrary;
use volsample::{ControlPoint, Volume};

use crate::tolerance;

/// Input of the `classify` check.
#[derive(Debug, Clone, PartialEq, Eq, Default, Arbitrary)]
pub struct ClassifyInput {
    /// Dimensions `1 + x mod 4`, `1 + y mod 4`, `1 + z mod 3`.
    pub dims: [u8; 3],
    /// Scalars as `f32` bits (a non-finite one is read as its low 16 bits, `− 32768`),
    /// repeated to fill the volume.
    pub field: Vec<u32>,
    /// Levoy's classifier `f_v`, `α_v`, `r` as `f32` bits; refused ones (the check verifies
    /// that `Isosurface::new` refuses exactly those) replaced by the first scalar, `½`, `1`.
    pub iso: [u32; 3],
    /// The light: direction and `k_a`, `k_d` as `f32` bits; refused ones replaced by
    /// `[0, 0, 1]`, `¼`, `¾`.
    pub light: [u32; 5],
    /// Control points `[s, r, g, b, a]`: `s` as `f32` bits (a non-finite one as above), the
    /// others `(x mod 65536)/65535`; sorted, equal `s` dropped, at most 4 (one point when
    /// empty).
    pub tf: Vec<[u32; 5]>,
}

fn finite_or_small(bits: u32) -> f32 {
    let x = f32::from_bits(bits);
    if x.is_finite() {
        x
    } else {
        f32::from((bits & 0xffff) as u16) - 32768.0
    }
}

fn unit16(bits: u32) -> f32 {
    f32::from((bits & 0xffff) as u16) / 65535.0
}

/// The bound of `TransferFunction::eval` at `s`: `TF_EVAL_BASE + L·TF_EVAL_PER_SLOPE·m`, `L`
/// the slope of the segment holding `s` and `m` the largest of `|s|` and its ends.
fn tf_bound(points: &[ControlPoint], s: f32) -> f64 {
    match points.windows(2).find(|p| p[0].s <= s && s < p[1].s) {
        None => tolerance::TF_EVAL_BASE,
        Some(p) => {
            let width = f64::from(p[1].s) - f64::from(p[0].s);
            let dv = p[1]
                .c
                .iter()
                .zip(p[0].c.iter())
                .map(|(a, b)| f64::from((a - b).abs()))
                .fold(f64::from((p[1].a - p[0].a).abs()), f64::max);
            let m = f64::from(s.abs().max(p[0].s.abs()).max(p[1].s.abs()));
            tolerance::TF_EVAL_BASE + dv / width * tolerance::TF_EVAL_PER_SLOPE * m
        }
    }
}

/// `classify`: Levoy's classifier gives `α ∈ [0, 1]` within `CLASSIFY_ISOSURFACE_ABS` of the
/// reference and leaves the color; shading gives channels in `[0, 1]` within `shade_abs` of
/// `C·min(1, k_a + k_d·|n·L|)` with the exact central-difference normal and leaves `α`; the
/// transfer-function pass is within its `TF_EVAL` bound of the reference; the constructors
/// refuse exactly the invalid parameters. Returns the number of voxel values compared.
///
/// # Errors
/// The first bound exceeded or wrong refusal, with the values.
pub fn classify(inp: &ClassifyInput) -> Result<u64, String> {
    use crate::reference::{
        central_gradient, levoy_opacities, shade_factor, RefControlPoint, RefIsosurface,
        RefScalarVolume, RefTransferFunction,
    };
    use crate::tolerance::hard_cases as hc;
    use volsample::classify::{classify_isosurface, classify_transfer, Isosurface};
    use volsample::shade::{shade_in_place, Light};
    use volsample::{StraightF32, TransferFunction};

    let dims = [
        1 + usize::from(inp.dims[0] % 4),
        1 + usize::from(inp.dims[1] % 4),
        1 + usize::from(inp.dims[2] % 3),
    ];
    let n = dims[0] * dims[1] * dims[2];
    let field: Vec<f32> = if inp.field.is_empty() {
        vec![0.0; n]
    } else {
        inp.field
            .iter()
            .cycle()
            .take(n)
            .map(|&b| finite_or_small(b))
            .collect()
    };
    let vol = Volume::new(&field, dims).map_err(|e| e.to_string())?;
    let rvol = RefScalarVolume::new(dims, field.iter().map(|&x| f64::from(x)).collect(), 1.0);
    let mut compared = 0u64;

    // Levoy's classifier.
    let [f_v, alpha_v, r] = inp.iso.map(f32::from_bits);
    let valid = f_v.is_finite() && (0.0..=1.0).contains(&alpha_v) && r.is_finite() && r > 0.0;
    let iso = match (Isosurface::new(f_v, alpha_v, r), valid) {
        (Ok(iso), true) => (iso, [f_v, alpha_v, r]),
        (Err(_), false) => {
            let p = [field[0], 0.5, 1.0];
            let iso = Isosurface::new(p[0], p[1], p[2]).map_err(|e| e.to_string())?;
            (iso, p)
        }
        (got, _) => {
            return Err(format!(
                "Isosurface::new({f_v:e}, {alpha_v:e}, {r:e}) = {got:?}, valid: {valid}"
            ))
        }
    };
    let (iso, [f_v, alpha_v, r]) = iso;
    let color = [1.0, 0.25, 0.0];
    let mut out = vec![StraightF32::default(); n];
    classify_isosurface(&vol, &iso, color, &mut out).map_err(|e| e.to_string())?;
    let want = levoy_opacities(
        &rvol,
        RefIsosurface {
            f_v: f64::from(f_v),
            alpha_v: f64::from(alpha_v),
            r: f64::from(r),
        },
    );
    for (i, (got, want)) in out.iter().zip(want).enumerate() {
        compared += 1;
        let err = (f64::from(got.a) - want).abs();
        if got.c != color
            || !(got.a.is_finite() && (0.0..=1.0).contains(&got.a))
            || err.is_nan()
            || err > hc::CLASSIFY_ISOSURFACE_ABS
        {
            return Err(format!(
                "Levoy {dims:?} voxel {i} f_v={f_v:e} α_v={alpha_v:e} r={r:e}: {got:?}, \
                 want α {want}: err {err:e} > {:e} (field {field:?})",
                hc::CLASSIFY_ISOSURFACE_ABS
            ));
        }
    }

    // Shading.
    let [dx, dy, dz, ka, kd] = inp.light.map(f32::from_bits);
    let dir = [dx, dy, dz];
    let valid = dir.iter().all(|d| d.is_finite())
        && dir.iter().any(|&d| d != 0.0)
        && ka.is_finite()
        && kd.is_finite()
        && ka >= 0.0
        && kd >= 0.0;
    let (light, dir, ka, kd) = match (Light::new(dir, ka, kd), valid) {
        (Ok(l), true) => (l, dir, ka, kd),
        (Err(_), false) => {
            let d = [0.0, 0.0, 1.0];
            (
                Light::new(d, 0.25, 0.75).map_err(|e| e.to_string())?,
                d,
                0.25,
                0.75,
            )
        }
        (got, _) => {
            return Err(format!(
                "Light::new({dir:?}, {ka:e}, {kd:e}) = {got:?}, valid: {valid}"
            ))
        }
    };
    let colors: Vec<[f32; 3]> = (0..n)
        .map(|i| {
            let b = inp.field.get(i).copied().unwrap_or(0);
            [unit16(b), unit16(b >> 8), unit16(b >> 16)]
        })
        .collect();
    let mut rgba: Vec<StraightF32> = colors.iter().map(|&c| StraightF32 { c, a: 0.5 }).collect();
    shade_in_place(&vol, &light, &mut rgba).map_err(|e| e.to_string())?;
    let bound = hc::shade_abs(f64::from(ka), f64::from(kd));
    for (i, (got, c0)) in rgba.iter().zip(&colors).enumerate() {
        let p = [
            i % dims[0],
            (i / dims[0]) % dims[1],
            i / (dims[0] * dims[1]),
        ];
        let k = shade_factor(central_gradient(dims, &rvol.scalars, p), dir, ka, kd);
        for (ch, (&c, &c0)) in got.c.iter().zip(c0).enumerate() {
            compared += 1;
            let want = (f64::from(c0) * k).clamp(0.0, 1.0);
            let err = (f64::from(c) - want).abs();
            if got.a != 0.5
                || !(c.is_finite() && (0.0..=1.0).contains(&c))
                || err.is_nan()
                || err > bound
            {
                return Err(format!(
                    "shade {dims:?} {p:?} ch{ch} dir={dir:?} k_a={ka:e} k_d={kd:e}: {got:?} \
                     vs {want}: err {err:e} > {bound:e} (field {field:?})"
                ));
            }
        }
    }

    // Transfer function.
    let mut pts: Vec<ControlPoint> = inp
        .tf
        .iter()
        .map(|p| ControlPoint {
            s: finite_or_small(p[0]),
            c: [unit16(p[1]), unit16(p[2]), unit16(p[3])],
            a: unit16(p[4]),
        })
        .collect();
    pts.sort_by(|a, b| a.s.total_cmp(&b.s));
    pts.dedup_by(|a, b| a.s <= b.s);
    pts.truncate(4);
    if pts.is_empty() {
        pts.push(ControlPoint {
            s: 0.0,
            c: [1.0, 0.5, 0.0],
            a: 0.5,
        });
    }
    let tf = TransferFunction::<4>::new(&pts)
        .map_err(|e| format!("TransferFunction::new refused {pts:?}: {e}"))?;
    let rtf = RefTransferFunction::new(
        pts.iter()
            .map(|p| RefControlPoint::new(f64::from(p.s), p.c.map(f64::from), f64::from(p.a)))
            .collect(),
    );
    let mut out = vec![StraightF32::default(); n];
    classify_transfer(&vol, &tf, &mut out).map_err(|e| e.to_string())?;
    for (&s, got) in field.iter().zip(&out) {
        compared += 1;
        let want = rtf.eval(f64::from(s));
        let in_range = got
            .c
            .iter()
            .chain(std::iter::once(&got.a))
            .all(|v| v.is_finite() && (0.0..=1.0).contains(v));
        let err = (0..3)
            .map(|k| (f64::from(got.c[k]) - want.color[k]).abs())
            .fold((f64::from(got.a) - want.alpha).abs(), f64::max);
        let bound = tf_bound(&pts, s);
        if !in_range || err.is_nan() || err > bound {
            return Err(format!(
                "transfer function {pts:?} at s = {s:e}: {got:?} vs {want:?}: err {err:e} > {bound:e}"
            ));
        }
    }
    Ok(compared)
}
