//! The papers' findings, reproduced on the report's scenes (issue "the main job").

use volsample_host::float_checks::FilterKind;
use volsample_host::pipeline::{self, Method, ModeChoice, Precision};
use volsample_host::scene::generate::{self, BLACK_AIR, RED_AIR};
use volsample_host::scene::Scene;

fn render(scene: &Scene, mode: ModeChoice) -> Vec<volsample::Sample> {
    let prepared = scene.prepare().expect("scene prepares");
    let m = Method {
        mode,
        precision: Precision::F32,
        filter: FilterKind::TrilinearSum,
    };
    pipeline::render(scene, &prepared, m)
        .expect("renders")
        .pixels
}

fn mean_intensity(img: &[volsample::Sample]) -> f64 {
    img.iter()
        .map(|p| p.c.iter().map(|&c| f64::from(c)).sum::<f64>() / 3.0)
        .sum::<f64>()
        / img.len() as f64
}

fn rms_diff(a: &[volsample::Sample], b: &[volsample::Sample]) -> f64 {
    let s: f64 = a
        .iter()
        .zip(b)
        .flat_map(|(x, y)| (0..3).map(move |k| (255.0 * f64::from(x.c[k] - y.c[k])).powi(2)))
        .sum();
    (s / (3 * a.len()) as f64).sqrt()
}

/// Separate interpolation darkens a white object in black air: black leaks into every
/// boundary sample, so the mean intensity drops (by more than one 8-bit level here).
#[test]
fn separate_darkens_white_object_in_black_air() {
    let scene = generate::ball_in_air(32, BLACK_AIR, "black");
    let sep = mean_intensity(&render(&scene, ModeChoice::Separate));
    let ow = mean_intensity(&render(&scene, ModeChoice::OpacityWeighted));
    println!("mean intensity: separate {sep:.4}, opacity-weighted {ow:.4}");
    assert!(
        ow - sep > 1.0 / 255.0,
        "separate {sep} vs opacity-weighted {ow}"
    );
}

/// Separate interpolation bleeds red from transparent red air into a white object;
/// opacity-weighted interpolation shows none (every pixel stays grey: r = g = b).
#[test]
fn separate_bleeds_red_opacity_weighted_does_not() {
    let scene = generate::ball_in_air(32, RED_AIR, "red");
    let tint =
        |img: &[volsample::Sample]| img.iter().map(|p| p.c[0] - p.c[1]).fold(0.0f32, f32::max);
    let sep = tint(&render(&scene, ModeChoice::Separate));
    let ow = tint(&render(&scene, ModeChoice::OpacityWeighted));
    println!("largest red tint r - g: separate {sep:.4}, opacity-weighted {ow:e}");
    assert!(sep > 0.1, "separate shows no bleeding: {sep}");
    assert!(ow <= 1e-6, "opacity-weighted bleeds: {ow}");
}

/// The RMS difference between Separate and OpacityWeighted is larger for an aliased face than
/// for one antialiased with a windowed sinc, and larger at 32³ than at 128³.
#[test]
fn artifact_shrinks_with_antialiasing_and_resolution() {
    // Look at the x-face (the antialiased one) nearly head-on, slightly oblique so the ray
    // phase at the face varies across the image.
    let diff = |mut s: Scene| {
        s.camera = generate::camera_towards(s.dims[0], [1.0, 0.13, 0.21]);
        rms_diff(
            &render(&s, ModeChoice::Separate),
            &render(&s, ModeChoice::OpacityWeighted),
        )
    };
    let aliased32 = diff(generate::corner(32, false, BLACK_AIR));
    let aa32 = diff(generate::corner(32, true, BLACK_AIR));
    let aliased128 = diff(generate::corner(128, false, BLACK_AIR));
    println!("RMS(separate - opacity-weighted): aliased 32³ {aliased32:.3}, antialiased 32³ {aa32:.3}, aliased 128³ {aliased128:.3}");
    assert!(
        aliased32 > aa32,
        "aliased {aliased32} <= antialiased {aa32}"
    );
    assert!(
        aliased32 > aliased128,
        "32³ {aliased32} <= 128³ {aliased128}"
    );
}

/// The OpacityWeighted image of a solid material does not depend on the ray phase: every ray
/// that meets the material shows exactly the material's color (Wittenbrink §4), while the
/// Separate image changes with the phase.
#[test]
fn opacity_weighted_color_is_phase_independent() {
    let material = 0.9f32;
    let mut worst_ow = 0.0f32;
    let mut sep_colors = Vec::new();
    for phase in [0.0f32, 0.25, 0.5, 0.75] {
        let mut scene = generate::phase(32);
        scene.phase = phase;
        scene.background = volsample::Sample::TRANSPARENT;
        for (mode, sink) in [
            (ModeChoice::OpacityWeighted, true),
            (ModeChoice::Separate, false),
        ] {
            let img = render(&scene, mode);
            for p in img.iter().filter(|p| p.a > 0.01) {
                let c = p.straight_color()[0];
                if sink {
                    worst_ow = worst_ow.max((c - material).abs());
                }
            }
            if !sink {
                let lit: Vec<f32> = img
                    .iter()
                    .filter(|p| p.a > 0.01)
                    .map(|p| p.straight_color()[0])
                    .collect();
                sep_colors.push(lit.iter().sum::<f32>() / lit.len().max(1) as f32);
            }
        }
    }
    let spread = sep_colors.iter().fold(0.0f32, |m, &c| m.max(c))
        - sep_colors.iter().fold(1.0f32, |m, &c| m.min(c));
    println!("opacity-weighted worst color error {worst_ow:e}; separate mean color over phases {sep_colors:?}");
    assert!(
        worst_ow <= 1e-5,
        "opacity-weighted color depends on phase: {worst_ow}"
    );
    assert!(spread > 1e-3, "separate should vary with phase: {spread}");
}
