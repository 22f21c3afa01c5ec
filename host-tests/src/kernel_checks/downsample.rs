//! `downsample`: float and integer downsampling levels and chains against the f64 reference
//! and the integer model.

use arbitrary::Arbitrary;
use volsample::downsample::integer::{
    build_chain_int, downsample_level_int, IntExtinctionBased, IntFilter4, IntMethod,
    IntOpacityBased,
};
use volsample::downsample::{
    build_chain, chain_len, downsample_level, level_count, level_dims, level_offset,
    ExtinctionBased, Filter4, OpacityBased,
};
use volsample::fixed_point::{ExtinctionFx, IntSample, ONE};
use volsample::{AssociatedF32, AssociatedU8, ExtinctionF32, Volume};

use super::{filled, raw};
use crate::int_model::downsample as dm;
use crate::reference::downsample as rd;
use crate::reference::{RefAssoc, RefExtinction};
use crate::tolerance::downsample as tol;

/// Input of the `downsample` check.
#[derive(Debug, Clone, PartialEq, Eq, Default, Arbitrary)]
pub struct DownsampleInput {
    /// Dimensions, each `1 + x mod 9`.
    pub dims: [u8; 3],
    /// The float filter's `a` as `f32` bits; when `Filter4::new` refuses it (it must then be
    /// outside `[0, ½]` or not finite), `a = (bits mod 32769)/65536` instead.
    pub a_bits: u32,
    /// The integer filter's raw `a` (`mod 32769`) when odd; when even, the float filter's
    /// `a` quantised (`IntFilter4::from_filter`).
    pub a_raw: u16,
    /// Largest `τ` of the float extinction input: `[1, 8, 64][x mod 3]`.
    pub tau_sel: u8,
    /// Largest optical depth of the integer extinction input: `255 << (x mod 19)` raw.
    pub depth_shift: u8,
    /// Voxel bytes `[c0, c1, c2, α]` (past them a fixed pattern, `kernel_checks::fill`): float
    /// associated voxels
    /// (`α = 0, 1, x·10⁻⁷` for `x ≤ 8`, else `x/255`; `C̃ = (c/255)·α`), float extinction
    /// voxels (`τ = (α/255)·τ_max`, `C^τ = (c/255)·τ`) and the integer formats (`C̃ ≤ α`).
    pub voxels: Vec<[u8; 4]>,
}

fn assoc_f32(v: [u8; 4]) -> AssociatedF32 {
    let a = match v[3] {
        0 => 0.0,
        255 => 1.0,
        x @ 1..=8 => f32::from(x) * 1e-7,
        x => f32::from(x) / 255.0,
    };
    AssociatedF32 {
        c: [v[0], v[1], v[2]].map(|c| f32::from(c) / 255.0 * a),
        a,
    }
}

fn ext_f32(v: [u8; 4], tau_max: f32) -> ExtinctionF32 {
    let tau = f32::from(v[3]) / 255.0 * tau_max;
    ExtinctionF32 {
        c_tau: [v[0], v[1], v[2]].map(|c| f32::from(c) / 255.0 * tau),
        tau,
    }
}

fn ref_assoc(v: &AssociatedF32) -> RefAssoc {
    RefAssoc::new(v.c.map(f64::from), f64::from(v.a))
}

fn ref_ext(v: &ExtinctionF32) -> RefExtinction {
    RefExtinction {
        tau: f64::from(v.tau),
        color_tau: v.c_tau.map(f64::from),
    }
}

/// The float `a` of the input, checking that `Filter4::new` refuses only invalid values.
fn float_filter(bits: u32) -> Result<(Filter4, f32), String> {
    let a = f32::from_bits(bits);
    match Filter4::new(a) {
        Ok(f) => {
            if !(a.is_finite() && (0.0..=0.5).contains(&a)) || f.a() != a {
                return Err(format!("Filter4::new accepted a = {a:e} as {f:?}"));
            }
            Ok((f, a))
        }
        Err(_) if a.is_finite() && (0.0..=0.5).contains(&a) => {
            Err(format!("Filter4::new refused a = {a:e}"))
        }
        Err(_) => {
            let a = (bits % 32769) as f32 / 65536.0;
            Filter4::new(a)
                .map(|f| (f, a))
                .map_err(|e| format!("Filter4::new({a}): {e}"))
        }
    }
}

/// The float chain of one method against the f64 reference chain; level 1 also by
/// `downsample_level`, bit-identical to the chain's.
fn float_chains(
    dims: [usize; 3],
    bytes: &[[u8; 4]],
    filter: Filter4,
    tau_max: f32,
) -> Result<u64, String> {
    let mut compared = 0u64;
    let a = f64::from(filter.a());
    let what = |l: usize| format!("{dims:?} a = {a:e} level {l}");
    // Opacity-based.
    let fine: Vec<AssociatedF32> = bytes.iter().map(|&v| assoc_f32(v)).collect();
    let vol = Volume::new(&fine, dims).map_err(|e| e.to_string())?;
    let mut out = vec![AssociatedF32::default(); chain_len(dims)];
    let chain = build_chain(OpacityBased, filter, vol, &mut out).map_err(|e| e.to_string())?;
    let want = rd::chain(
        dims,
        &fine.iter().map(ref_assoc).collect::<Vec<_>>(),
        a,
        rd::downsample_opacity,
    );
    if chain.len() != want.len() || chain.len() as u32 != level_count(dims) {
        return Err(format!(
            "{dims:?}: {} levels, reference {}",
            chain.len(),
            want.len()
        ));
    }
    for (l, (rdims, rv)) in want.iter().enumerate().skip(1) {
        let lvl = chain
            .level(l as u32)
            .ok_or_else(|| format!("{}: missing", what(l)))?
            .volume();
        if lvl.dims() != *rdims {
            return Err(format!("{}: dims {:?} != {rdims:?}", what(l), lvl.dims()));
        }
        let bound = tol::opacity_chain(l as u32);
        for (i, (v, r)) in lvl.data().iter().zip(rv).enumerate() {
            let valid = v.a.is_finite()
                && (0.0..=1.0).contains(&v.a)
                && v.c.iter().all(|&c| c.is_finite() && c >= 0.0 && c <= v.a);
            if !valid {
                return Err(format!("{} voxel {i}: invalid {v:?}", what(l)));
            }
            compared += 1;
            let err = ref_assoc(v).max_abs_diff(*r);
            if err.is_nan() || err > bound {
                return Err(format!(
                    "{} voxel {i} opacity-based: {v:?} vs {r:?}: err {err:e} > {bound:e}",
                    what(l)
                ));
            }
        }
    }
    if want.len() > 1 {
        let mut one = vec![AssociatedF32::default(); want[1].1.len()];
        let lvl =
            downsample_level(OpacityBased, filter, &vol, &mut one).map_err(|e| e.to_string())?;
        let from_chain = chain.level(1).map(|c| c.volume().data().to_vec());
        if Some(lvl.data().to_vec()) != from_chain {
            return Err(format!(
                "{dims:?}: downsample_level != chain level 1 (opacity)"
            ));
        }
    }
    // Extinction-based.
    let fine: Vec<ExtinctionF32> = bytes.iter().map(|&v| ext_f32(v, tau_max)).collect();
    let vol = Volume::new(&fine, dims).map_err(|e| e.to_string())?;
    let mut out = vec![ExtinctionF32::default(); chain_len(dims)];
    let chain = build_chain(ExtinctionBased, filter, vol, &mut out).map_err(|e| e.to_string())?;
    let want = rd::chain(
        dims,
        &fine.iter().map(ref_ext).collect::<Vec<_>>(),
        a,
        rd::downsample_extinction,
    );
    let tau_level0 = fine.iter().fold(0.0f64, |m, v| m.max(f64::from(v.tau)));
    for (l, (_, rv)) in want.iter().enumerate().skip(1) {
        let lvl = chain
            .level(l as u32)
            .ok_or_else(|| format!("{}: missing", what(l)))?
            .volume();
        let bound = tol::extinction_chain(l as u32, tau_level0);
        for (i, (v, r)) in lvl.data().iter().zip(rv).enumerate() {
            let valid = v.tau.is_finite()
                && v.tau >= 0.0
                && v.c_tau
                    .iter()
                    .all(|&c| c.is_finite() && c >= 0.0 && c <= v.tau);
            if !valid {
                return Err(format!("{} voxel {i}: invalid {v:?}", what(l)));
            }
            compared += 1;
            let err = v
                .c_tau
                .iter()
                .zip(r.color_tau)
                .fold((f64::from(v.tau) - r.tau).abs(), |m, (c, rc)| {
                    m.max((f64::from(*c) - rc).abs())
                });
            if err.is_nan() || err > bound {
                return Err(format!(
                    "{} voxel {i} extinction-based: {v:?} vs {r:?}: err {err:e} > {bound:e}",
                    what(l)
                ));
            }
        }
    }
    if want.len() > 1 {
        let mut one = vec![ExtinctionF32::default(); want[1].1.len()];
        let lvl =
            downsample_level(ExtinctionBased, filter, &vol, &mut one).map_err(|e| e.to_string())?;
        let from_chain = chain.level(1).map(|c| c.volume().data().to_vec());
        if Some(lvl.data().to_vec()) != from_chain {
            return Err(format!(
                "{dims:?}: downsample_level != chain level 1 (extinction)"
            ));
        }
    }
    Ok(compared)
}

/// One integer format: to and from the model's channels `[c0, c1, c2, α or D]`.
struct IntFormat<V> {
    name: &'static str,
    to: fn([u64; 4]) -> V,
    raw: fn(&V) -> [u64; 4],
    /// Full scale (opacity-based) or `None` (extinction-based).
    full: Option<u64>,
}

fn u8_to(v: [u64; 4]) -> AssociatedU8 {
    AssociatedU8(v.map(|x| x.min(255) as u8))
}
fn u8_raw(v: &AssociatedU8) -> [u64; 4] {
    v.0.map(u64::from)
}
fn u88_to(v: [u64; 4]) -> IntSample {
    let a = v[3].min(ONE.into()) as u16;
    let c = [v[0], v[1], v[2]].map(|c| c.min(a.into()) as u16);
    IntSample::new(c, a).unwrap_or(IntSample::TRANSPARENT)
}
fn u88_raw(v: &IntSample) -> [u64; 4] {
    raw(v).map(u64::from)
}
fn fx_to(v: [u64; 4]) -> ExtinctionFx {
    let t = |x: u64| x.min(u64::from(u32::MAX)) as u32;
    ExtinctionFx {
        tau: t(v[3]),
        c_tau: [t(v[0]), t(v[1]), t(v[2])],
    }
}
fn fx_raw(v: &ExtinctionFx) -> [u64; 4] {
    let [r, g, b] = v.c_tau;
    [r, g, b, v.tau].map(u64::from)
}

/// The integer chain of one format against the model chain: bit for bit, in range with
/// `C̃ ≤ α`, and within the per-level bound of the exact method on the level before (not
/// for saturated extinction values); level 1 also by `downsample_level_int`.
fn int_chain<V: Copy + PartialEq + std::fmt::Debug, M: IntMethod<V>>(
    method: M,
    fmt: &IntFormat<V>,
    filter: IntFilter4,
    dims: [usize; 3],
    base: &[[u64; 4]],
) -> Result<u64, String> {
    let mut compared = 0u64;
    let vox: Vec<V> = base.iter().map(|&v| (fmt.to)(v)).collect();
    let mut out = vec![(fmt.to)([0; 4]); chain_len(dims)];
    let count = build_chain_int(method, filter, &vox, dims, &mut out)
        .map_err(|e| format!("{}: {e}", fmt.name))?;
    let a_q = filter.a_raw();
    let want = dm::chain(dims, base, |d, v| match fmt.full {
        Some(full) => dm::opacity_level(d, v, a_q, full),
        None => dm::extinction_level(d, v, a_q),
    });
    if count != level_count(dims) || want.len() as u32 + 1 != count {
        return Err(format!(
            "{}: {count} levels, model {}",
            fmt.name,
            want.len() + 1
        ));
    }
    let (bound, cap) = match fmt.full {
        Some(full) => (tol::INT_OPACITY_LEVEL_LSB, full),
        None => (tol::INT_EXTINCTION_LEVEL_LSB, dm::MAX_DEPTH_RAW),
    };
    for (l, (d, mv)) in (1u32..).zip(want.iter()) {
        if *d != level_dims(dims, l) {
            return Err(format!("{} level {l}: model dims {d:?}", fmt.name));
        }
        let off = level_offset(dims, l);
        let got = out
            .get(off..off + mv.len())
            .ok_or_else(|| format!("{} level {l}: chain too short", fmt.name))?;
        for (i, (g, m)) in got.iter().zip(mv).enumerate() {
            let g = (fmt.raw)(g);
            compared += 1;
            let what = || format!("{} {dims:?} a_q = {a_q} level {l} voxel {i}", fmt.name);
            if g != m.raw {
                return Err(format!("{}: kernel {g:?} != model {:?}", what(), m.raw));
            }
            if g[3] > cap || g[..3].iter().any(|&c| c > g[3]) {
                return Err(format!("{}: out of range {g:?}", what()));
            }
            for (&r, &e) in g.iter().zip(m.exact.iter()) {
                if fmt.full.is_none() && r == cap {
                    continue;
                }
                let err = (r as f64 - e).abs();
                if err.is_nan() || err > bound {
                    return Err(format!("{}: {r} vs exact {e}: err {err} > {bound}", what()));
                }
            }
        }
    }
    if let Some((_, first)) = want.first() {
        let mut one = vec![(fmt.to)([0; 4]); first.len()];
        downsample_level_int(method, filter, &vox, dims, &mut one)
            .map_err(|e| format!("{}: {e}", fmt.name))?;
        if out.get(level_offset(dims, 1)..level_offset(dims, 1) + one.len()) != Some(&one[..]) {
            return Err(format!(
                "{} {dims:?}: downsample_level_int != chain level 1",
                fmt.name
            ));
        }
    }
    Ok(compared)
}

/// `downsample`: on the input's volume and filter, the float opacity- and extinction-based
/// chains (and one level) are valid and within `tolerance::downsample`'s chain bounds of the
/// f64 reference; `Filter4::new` accepts exactly the `a` in `[0, ½]`; the integer chains
/// (`AssociatedU8`, U8.8, `ExtinctionFx`) agree bit for bit with the integer model, stay in
/// range with `C̃ ≤ α` and within the per-level bounds of the exact method. Returns the
/// number of coarse voxels compared.
///
/// # Errors
/// The first broken bound or disagreement, with the values.
pub fn downsample(inp: &DownsampleInput) -> Result<u64, String> {
    let dims = inp.dims.map(|x| 1 + usize::from(x % 9));
    let bytes = filled(&inp.voxels, dims[0] * dims[1] * dims[2]);
    let (filter, _) = float_filter(inp.a_bits)?;
    let tau_max = [1.0, 8.0, 64.0][usize::from(inp.tau_sel % 3)];
    let mut compared = float_chains(dims, &bytes, filter, tau_max)?;

    let int_filter = if inp.a_raw % 2 == 1 {
        IntFilter4::from_raw(u32::from(inp.a_raw) % 32769)
            .map_err(|e| format!("IntFilter4::from_raw({}): {e}", inp.a_raw % 32769))?
    } else {
        let q = IntFilter4::from_filter(filter);
        if q.a_raw() != dm::quantise_a(f64::from(filter.a())) {
            return Err(format!(
                "IntFilter4::from_filter({:e}) = {} != model {}",
                filter.a(),
                q.a_raw(),
                dm::quantise_a(f64::from(filter.a()))
            ));
        }
        q
    };
    let assoc8: Vec<[u64; 4]> = bytes
        .iter()
        .map(|v| {
            let a = u64::from(v[3]);
            [
                u64::from(v[0]).min(a),
                u64::from(v[1]).min(a),
                u64::from(v[2]).min(a),
                a,
            ]
        })
        .collect();
    compared += int_chain(
        IntOpacityBased,
        &IntFormat {
            name: "AssociatedU8",
            to: u8_to,
            raw: u8_raw,
            full: Some(255),
        },
        int_filter,
        dims,
        &assoc8,
    )?;
    // U8.8: each byte spread over the 16 bits (`x·256 + x`, at most ONE for α).
    let one = u64::from(ONE);
    let assoc16: Vec<[u64; 4]> = assoc8
        .iter()
        .map(|v| {
            let a = (v[3] * 257).min(one);
            [
                (v[0] * 257).min(a),
                (v[1] * 257).min(a),
                (v[2] * 257).min(a),
                a,
            ]
        })
        .collect();
    compared += int_chain(
        IntOpacityBased,
        &IntFormat {
            name: "IntSample",
            to: u88_to,
            raw: u88_raw,
            full: Some(one),
        },
        int_filter,
        dims,
        &assoc16,
    )?;
    // U7.20 optical depths up to `255 << shift` (`2^26` at most, below saturation at level 0).
    let shift = u32::from(inp.depth_shift % 19);
    let depth: Vec<[u64; 4]> = bytes
        .iter()
        .map(|v| {
            let d = u64::from(v[3]) << shift;
            [
                u64::from(v[0]) * d / 255,
                u64::from(v[1]) * d / 255,
                u64::from(v[2]) * d / 255,
                d,
            ]
        })
        .collect();
    compared += int_chain(
        IntExtinctionBased,
        &IntFormat {
            name: "ExtinctionFx",
            to: fx_to,
            raw: fx_raw,
            full: None,
        },
        int_filter,
        dims,
        &depth,
    )?;
    Ok(compared)
}
