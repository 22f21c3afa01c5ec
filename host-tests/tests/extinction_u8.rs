//! `ExtinctionWeightedU8` (issue 9: extinction sampling at the memory cost of 8-bit straight
//! storage) against `ExtinctionWeighted` over the same volume converted to `ExtinctionF32`:
//! bit-identical samples and rays, every filter, both orders, termination, background and
//! empty-space skipping; its `TauTable` against f64 and its bad inputs.

use proptest::prelude::*;
use volsample::composite::Order;
use volsample::mode::{ExtinctionWeightedU8, TauTable};
use volsample::skip::Occupancy;
use volsample::voxel::{unorm8, MAX_OPTICAL_DEPTH};
use volsample::{
    BackToFront, Error, ExtinctionF32, ExtinctionWeighted, Filter, FrontToBack, Nearest, Ray,
    RayMarcher, Sample, Step, StraightF32, StraightU8, Threshold, Trilinear, TriquadraticBSpline,
    Volume,
};
use volsample_host::tolerance as tol;

fn same(a: &Sample, b: &Sample) -> bool {
    a.a.to_bits() == b.a.to_bits() && a.c.map(f32::to_bits) == b.c.map(f32::to_bits)
}

fn converted(v: &[StraightU8], d_ref: f32) -> Vec<ExtinctionF32> {
    v.iter()
        .map(|v| {
            let [r, g, b, a] = v.0.map(unorm8);
            ExtinctionF32::from_straight(StraightF32 { c: [r, g, b], a }, d_ref)
        })
        .collect()
}

/// Every sample position and ray of `rays` through the u8 marcher and the converted one.
fn check<F: Filter, O: Order + Copy>(
    u8s: &[StraightU8],
    dims: [usize; 3],
    d_ref: f32,
    step: Step,
    order: O,
    positions: &[[f32; 3]],
    rays: &[Ray],
) -> Result<(), TestCaseError> {
    let table = TauTable::new(d_ref).unwrap();
    let ext = converted(u8s, d_ref);
    let v8 = Volume::new(u8s, dims).unwrap();
    let ve = Volume::new(&ext, dims).unwrap();
    let bg = Sample {
        c: [0.2, 0.1, 0.0],
        a: 0.4,
    };
    let a = RayMarcher::new(
        v8,
        ExtinctionWeightedU8::new(&table),
        F::default(),
        order,
        step,
    )
    .unwrap()
    .with_background(bg)
    .unwrap();
    let b = RayMarcher::new(ve, ExtinctionWeighted, F::default(), order, step)
        .unwrap()
        .with_background(bg)
        .unwrap();
    for p in positions {
        let (x, y) = (a.sample(*p), b.sample(*p));
        prop_assert!(same(&x, &y), "sample at {p:?}: {x:?} vs {y:?}");
    }
    for r in rays {
        let (x, y) = (a.cast_counted(r), b.cast_counted(r));
        prop_assert!(same(&x.0, &y.0) && x.1 == y.1, "ray {r:?}: {x:?} vs {y:?}");
    }
    // Empty-space skipping reads the same emptiness (τ = 0) either way.
    let mut grid = vec![0u8; Occupancy::buffer_len(dims, 1)];
    let skip = a.with_skipping(&mut grid, 1).unwrap();
    for r in rays {
        let (x, y) = (skip.cast_counted(r), b.cast_counted(r));
        prop_assert!(same(&x.0, &y.0), "skipping, ray {r:?}: {x:?} vs {y:?}");
    }
    Ok(())
}

fn volume_strategy() -> impl Strategy<Value = ([usize; 3], Vec<StraightU8>)> {
    ([1usize..6, 1..6, 1..6]).prop_flat_map(|dims| {
        let n = dims.iter().product::<usize>();
        let voxel = prop_oneof![
            any::<[u8; 4]>().prop_map(StraightU8),
            any::<[u8; 3]>().prop_map(|[r, g, b]| StraightU8([r, g, b, 0])),
            any::<[u8; 3]>().prop_map(|[r, g, b]| StraightU8([r, g, b, 255])),
            any::<[u8; 3]>().prop_map(|[r, g, b]| StraightU8([r, g, b, 1])),
        ];
        (Just(dims), proptest::collection::vec(voxel, n))
    })
}

fn ray_strategy() -> impl Strategy<Value = Ray> {
    (
        [-2.0f32..8.0, -2.0..8.0, -3.0..-1.0],
        [-1.0f32..1.0, -1.0..1.0, 0.1..1.0],
    )
        .prop_map(|(o, d)| Ray::new(o, d).unwrap())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn u8_extinction_is_bit_identical_to_the_converted_volume(
        (dims, u8s) in volume_strategy(),
        d_ref in prop_oneof![Just(1.0f32), Just(0.5), 0.01f32..4.0, Just(1e-6), Just(1e6)],
        d in prop_oneof![Just(0.5f32), 0.05f32..3.0],
        a_stop in prop_oneof![Just(1.0f32), 0.05f32..1.0],
        positions in proptest::collection::vec([-1.0f32..6.0, -1.0..6.0, -1.0..6.0], 16),
        rays in proptest::collection::vec(ray_strategy(), 8),
    ) {
        let step = Step::new(d).unwrap();
        let stop = FrontToBack(Threshold::new(a_stop).unwrap());
        let ftb = FrontToBack::new();
        check::<Trilinear, _>(&u8s, dims, d_ref, step, stop, &positions, &rays)?;
        check::<Trilinear<volsample::Tree>, _>(&u8s, dims, d_ref, step, ftb, &positions, &rays)?;
        check::<Nearest, _>(&u8s, dims, d_ref, step, stop, &positions, &rays)?;
        check::<TriquadraticBSpline, _>(&u8s, dims, d_ref, step, ftb, &positions, &rays)?;
        check::<Trilinear, _>(&u8s, dims, d_ref, step, BackToFront, &positions, &rays)?;
    }
}

/// Every entry against `−ln(1 − n/255)/d′` in f64, capped at the optical depth
/// `from_straight` caps at, within `FROM_STRAIGHT_TAU_REL` (the bound `τ` inherits from
/// `ExtinctionF32::from_straight`).
#[test]
fn tau_table_entries_hold_the_from_straight_bound() {
    let mut worst = 0.0f64;
    for d_ref in [1.0f32, 0.5, 0.3, 7.0, 1e-3] {
        let t = TauTable::new(d_ref).unwrap();
        assert_eq!(t.d_ref(), d_ref);
        assert_eq!(t.tau(0), 0.0);
        for n in 0..=255u8 {
            let a = f64::from(unorm8(n));
            let depth = (-(-a).ln_1p()).min(f64::from(MAX_OPTICAL_DEPTH));
            let want = depth / f64::from(d_ref);
            let got = f64::from(t.tau(n));
            let rel = if want == 0.0 {
                got
            } else {
                (got - want).abs() / want
            };
            worst = worst.max(rel / tol::FROM_STRAIGHT_TAU_REL);
            assert!(
                rel <= tol::FROM_STRAIGHT_TAU_REL,
                "n = {n}, d′ = {d_ref}: {got} vs {want}"
            );
        }
        // Increasing in the byte: more opacity, more extinction.
        assert!((1..=255u8).all(|n| t.tau(n) > t.tau(n - 1)), "d′ = {d_ref}");
    }
    println!("TauTable worst relative error: {worst:.3} of FROM_STRAIGHT_TAU_REL");
}

/// `TauTable::extinction` of every voxel byte pair `(c, α)` against
/// `ExtinctionF32::from_straight` of the same voxel read as `n/255`, bit for bit, for several
/// `d′`: the per-voxel identity behind the sampling identity above, exhaustively. (It also
/// holds the table's `C^τ = τ·C` to the `min(τ)` of `from_straight` without computing it: the
/// product of `τ` and a value in `[0, 1]` rounds to at most `τ`.)
#[test]
fn tau_table_extinction_equals_from_straight_for_every_byte_pair() {
    for d_ref in [1.0f32, 0.5, 0.3, 7.0, 1e-3, f32::MIN_POSITIVE] {
        let t = TauTable::new(d_ref).unwrap();
        for a in 0..=255u8 {
            for c in 0..=255u8 {
                let v = StraightU8([c, 255 - c, c / 2, a]);
                let [r, g, b, a8] = v.0.map(unorm8);
                let want = ExtinctionF32::from_straight(
                    StraightF32 {
                        c: [r, g, b],
                        a: a8,
                    },
                    d_ref,
                );
                let got = t.extinction(v);
                let bits = |e: ExtinctionF32| e.c_tau.map(f32::to_bits);
                assert!(
                    bits(got) == bits(want) && got.tau.to_bits() == want.tau.to_bits(),
                    "d′ = {d_ref}, voxel {v:?}: {got:?} vs {want:?}"
                );
            }
        }
    }
}

#[test]
fn tau_table_rejects_bad_reference_distances() {
    for d in [
        0.0f32,
        -0.0,
        -1.0,
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
    ] {
        assert_eq!(
            TauTable::new(d),
            Err(Error::InvalidReferenceDistance),
            "d′ = {d}"
        );
    }
    assert!(TauTable::new(f32::MIN_POSITIVE).is_ok());
    assert!(TauTable::new(f32::MAX).is_ok());
}
