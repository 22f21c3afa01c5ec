//! The two ways of looking up `τ` (`Taus`) and the choice between them (`fast_gathers`).

use super::*;

/// Both ways of looking up `τ` ([`Taus`]: one gather, or eight scalar loads) read every
/// opacity byte as `TauTable::extinction` does, in every lane; and the one-ray march and the
/// packets of `ExtinctionWeightedU8` come out the same bits with either, as the portable
/// one-ray march (whichever way this CPU's token picks, the tests of the marchers run only
/// that one).
#[test]
#[cfg_attr(
    all(miri, not(all(target_feature = "avx2", target_feature = "fma"))),
    ignore = "Miri: no AVX2 (Avx2::detect answers the compiled target features there)"
)]
fn both_tau_lookups_read_the_table() {
    let Some(cpu) = Avx2::detect() else {
        return; // no AVX2 here: nothing to check (`tests/isa.rs` checks the detection)
    };
    // SAFETY: `detect` found AVX2 and FMA on this CPU.
    assert_eq!(unsafe { tau_lookup_check(cpu) }, Ok(()));
}

#[target_feature(enable = "avx2,fma")]
fn tau_lookup_check(cpu: Avx2) -> Result<(), crate::Error> {
    use crate::mode::{ExtinctionWeightedU8, TauOfAlpha8, TauTable};
    use crate::{FrontToBack, Isa, RayMarcher, Step, Trilinear};
    let table = TauTable::new(0.7)?;
    let mut next = xorshift(0x9E37_79B9_7F4A_7C15);
    let ways = [cpu.gathers(), !cpu.gathers()].map(|gathers| Avx2 { gathers });
    for n in 0..=255u32 {
        let words: [i32; LANES] = core::array::from_fn(|l| {
            let alpha = (n + 29 * l as u32) & 0xff;
            ((alpha << 24) | (next() as u32 & 0x00ff_ffff)) as i32
        });
        for way in ways {
            let taus = Taus {
                table: table.taus(),
                gather: way.gathers(),
            };
            // SAFETY: this function's AVX2 and FMA.
            let got = unsafe { TauOfAlpha8::channels(indices(words), taus) }.map(|v| array(v));
            for (l, word) in words.into_iter().enumerate() {
                let e = table.extinction(StraightU8(word.to_le_bytes()));
                let want = [e.c_tau[0], e.c_tau[1], e.c_tau[2], e.tau];
                for (c, (g, w)) in got.iter().zip(want).enumerate() {
                    let g = g.get(l).copied().unwrap_or(f32::NAN);
                    assert_eq!(
                        g.to_bits(),
                        w.to_bits(),
                        "word {word:#x}, channel {c}, {way:?}"
                    );
                }
            }
        }
    }
    // A 9³ volume of random bytes, rays through it in several directions.
    let voxels: [StraightU8; 729] =
        core::array::from_fn(|_| StraightU8((next() as u32).to_le_bytes()));
    let (vol, step) = (crate::Volume::new(&voxels, [9; 3])?, Step::new(0.35)?);
    let mode = ExtinctionWeightedU8::new(&table);
    let m = RayMarcher::new(vol, mode, Trilinear::new(), FrontToBack::new(), step)?;
    let m = m.with_isa(Isa::BASELINE);
    let mut rays = [crate::Ray::new([0.0; 3], [0.0, 0.0, 1.0])?; LANES];
    for (l, r) in rays.iter_mut().enumerate() {
        let dir = [0.3 + 0.1 * l as f32, 0.5 - 0.2 * l as f32, 1.0];
        *r = crate::Ray::new([0.2 + 0.9 * l as f32, 1.1, -0.5], dir)?;
    }
    let stage = Stage {
        d: 0.35,
        a_stop: f32::INFINITY,
        taus: table.taus(),
        corr: crate::opacity::Uncorrected,
    };
    for way in ways {
        let ranges = rays.each_ref().each(|r| m.sample_range(r));
        let samples = Samples {
            ranges,
            first: 0,
            total: 0,
        };
        let out = march8::<StraightU8, ExtinctionWeightedU8<'_>>(way, &vol, &rays, &samples, stage);
        for (ray, got) in rays.iter().zip(out) {
            let (range, want) = (m.sample_range(ray), m.cast(ray));
            let one = Samples::window(range, 0..range.1);
            let (alone, count) =
                march_one::<StraightU8, ExtinctionWeightedU8<'_>>(way, &vol, ray, &one, stage);
            assert_eq!(count, range.1, "{way:?}");
            for s in [got, alone] {
                assert_eq!(s.a.to_bits(), want.a.to_bits(), "{way:?}");
                assert_eq!(s.c.map(f32::to_bits), want.c.map(f32::to_bits), "{way:?}");
            }
        }
        assert!(
            rays.iter().any(|r| m.cast(r).a > 0.05),
            "the rays see something"
        );
    }
    Ok(())
}

/// `fast_gathers` from CPUID's leaves 0 and 1: Intel family 6 outside the models affected by
/// Gather Data Sampling, nothing else. EAX of leaf 1 as the Intel SDM lays it out (stepping in
/// bits 0–3, model 4–7, family 8–11, extended model 16–19); the vendor strings spelled out.
#[test]
fn gathers_are_fast_only_on_intel_outside_gather_data_sampling() {
    let vendor = |name: &[u8; 12]| {
        let word = |k: usize| {
            let b = |i: usize| u32::from(name.get(k + i).copied().unwrap_or(0));
            b(0) | (b(1) << 8) | (b(2) << 16) | (b(3) << 24)
        };
        CpuidResult {
            eax: 0x20,
            ebx: word(0),
            edx: word(4),
            ecx: word(8),
        }
    };
    let eax = |family: u32, model: u32| {
        let (ext_family, family) = if family > 15 {
            (family - 15, 15)
        } else {
            (0, family)
        };
        (ext_family << 20) | ((model >> 4) << 16) | (family << 8) | ((model & 0xf) << 4) | 2
    };
    let leaf1 = |family, model| CpuidResult {
        eax: eax(family, model),
        ebx: 0,
        ecx: 0,
        edx: 0,
    };
    let (intel, amd) = (vendor(b"GenuineIntel"), vendor(b"AuthenticAMD"));
    // Emerald Rapids (the project's Xeon: family 6, model 207), Sapphire Rapids, Alder Lake.
    for model in [0xCF, 0x8F, 0x97] {
        assert!(
            fast_gathers(intel, leaf1(6, model)),
            "Intel model {model:#x}"
        );
    }
    // Skylake-SP, Ice Lake-SP, Tiger Lake: Gather Data Sampling.
    for model in [0x55, 0x6A, 0x8C] {
        assert!(
            !fast_gathers(intel, leaf1(6, model)),
            "Intel model {model:#x}"
        );
    }
    // AMD Zen 3 (family 25, model 1: the project's EPYC) and Zen 4; another family of Intel's.
    assert!(!fast_gathers(amd, leaf1(25, 0x01)));
    assert!(!fast_gathers(amd, leaf1(25, 0x11)));
    assert!(!fast_gathers(intel, leaf1(15, 0x06)));
    // This CPU: the token's answer is `fast_gathers` of its own CPUID (which Miri cannot run).
    if let (false, Some(cpu)) = (cfg!(miri), Avx2::detect()) {
        assert_eq!(cpu.gathers(), fast_gathers(__cpuid(0), __cpuid(1)));
    }
}
