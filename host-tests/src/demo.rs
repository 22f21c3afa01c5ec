//! The small demonstration `cargo run --release` prints until the full report exists:
//! Wittenbrink's §2/§3 three-sample ray, and an ASCII rendering of a white ball in
//! transparent red air with `Separate` and `OpacityWeighted` side by side.

use std::fmt::Write as _;

use volsample::{
    Mode, OpacityWeighted, Orthographic, RayMarcher, Sample, Separate, Step, StraightU8, Trilinear,
    Volume,
};

/// The §2/§3 ray: transparent black air (voxel 0) then opaque white material (voxel 1),
/// sampled at `x = 0, ½, 1` with `d = d′ = ½`. Returns the displayed ray color `C/A`.
///
/// # Errors
/// Only if the core rejects the fixed scene (a bug).
pub fn three_sample_ray<M: Mode<StraightU8> + Copy>(mode: M) -> Result<f32, volsample::Error> {
    let voxels = [StraightU8([0, 0, 0, 0]), StraightU8([255, 255, 255, 255])];
    let vol = Volume::new(&voxels, [2, 1, 1])?.with_reference_distance(0.5)?;
    let marcher = RayMarcher::new(
        vol,
        mode,
        Trilinear::new(),
        crate::pipeline::front_to_back()?,
        Step::new(0.5)?,
    )?;
    let ray = volsample::Ray::new([0.0, 0.0, 0.0], [1.0, 0.0, 0.0])?;
    let px = marcher.cast(&ray);
    Ok(px.straight_color()[0])
}

/// A `n³` volume: an opaque white ball of radius `0.3·n` in transparent *red* air.
pub fn ball_in_red_air(n: usize) -> Vec<StraightU8> {
    let c = (n as f32 - 1.0) * 0.5;
    let r = 0.3 * n as f32;
    let mut v = Vec::with_capacity(n * n * n);
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                let d2 = [x, y, z]
                    .iter()
                    .map(|&i| (i as f32 - c).powi(2))
                    .sum::<f32>();
                v.push(if d2 <= r * r {
                    StraightU8([255, 255, 255, 255])
                } else {
                    StraightU8([255, 0, 0, 0])
                });
            }
        }
    }
    v
}

/// One character per pixel: blank for empty, a luminance ramp for neutral pixels, and
/// `r`/`R` where red dominates (bleeding from the transparent red air).
pub fn ascii_pixel(p: &Sample) -> char {
    const RAMP: &[u8] = b" .:-=+*#%@";
    if p.a < 0.02 {
        return ' ';
    }
    let [r, g, _] = p.c;
    if r - g > 0.04 {
        return if r - g > 0.15 { 'R' } else { 'r' };
    }
    let i = ((g * (RAMP.len() - 1) as f32).round() as usize).min(RAMP.len() - 1);
    char::from(RAMP.get(i).copied().unwrap_or(b'@'))
}

fn render<M: Mode<StraightU8> + Copy>(
    vol: Volume<'_, StraightU8>,
    mode: M,
    n: usize,
) -> Result<Vec<Sample>, volsample::Error> {
    let marcher = RayMarcher::new(
        vol,
        mode,
        Trilinear::new(),
        crate::pipeline::front_to_back()?,
        Step::new(1.0)?.with_phase(0.5)?,
    )?;
    let mut image = vec![Sample::TRANSPARENT; n * n];
    marcher.render_into(&Orthographic::looking_down_z([n, n, n])?, n, n, &mut image)?;
    Ok(image)
}

/// The demo text.
///
/// # Errors
/// Only if the core rejects the fixed scenes (a bug).
pub fn run() -> Result<String, volsample::Error> {
    let mut out = String::new();
    let sep = three_sample_ray(Separate)?;
    let ow = three_sample_ray(OpacityWeighted)?;
    let _ = writeln!(
        out,
        "Wittenbrink §2/§3: air then opaque white material, samples at x = 0, 0.5, 1"
    );
    let _ = writeln!(
        out,
        "  Separate interpolation:          ray color {sep:.4}  (paper: 0.75, wrong)"
    );
    let _ = writeln!(
        out,
        "  Opacity-weighted interpolation:  ray color {ow:.4}  (paper: 1.0, right)"
    );
    let _ = writeln!(out);
    let n = 24;
    let voxels = ball_in_red_air(n);
    let vol = Volume::new(&voxels, [n, n, n])?;
    let a = render(vol, Separate, n)?;
    let b = render(vol, OpacityWeighted, n)?;
    let _ = writeln!(out, "A white ball in transparent red air, {n}³, trilinear, d = 1 (samples between voxel planes), looking down z");
    let _ = writeln!(
        out,
        "('R'/'r' = red bled in from air that should be invisible)"
    );
    let _ = writeln!(out, "{:<w$}   OpacityWeighted", "Separate", w = n);
    for (ra, rb) in a.chunks(n).zip(b.chunks(n)) {
        let la: String = ra.iter().map(ascii_pixel).collect();
        let lb: String = rb.iter().map(ascii_pixel).collect();
        let _ = writeln!(out, "{la}   {lb}");
    }
    let red = |img: &[Sample]| img.iter().filter(|p| p.c[0] - p.c[1] > 0.04).count();
    let _ = writeln!(
        out,
        "red-tinted pixels: Separate {}, OpacityWeighted {}",
        red(&a),
        red(&b)
    );
    Ok(out)
}
