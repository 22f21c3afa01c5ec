//! Writing images: rendered pixels, error images, histogram-equalised error images.

use std::path::Path;

use volsample::Sample;

/// Writes an 8-bit RGB PNG from rows of `[r, g, b]` in `[0, 1]` (round half up).
///
/// # Errors
/// I/O or encoder errors, as text.
pub fn write_rgb(path: &Path, width: usize, height: usize, rgb: &[[f32; 3]]) -> Result<(), String> {
    let file = std::fs::File::create(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), width as u32, height as u32);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let mut w = enc
        .write_header()
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let bytes: Vec<u8> = rgb
        .iter()
        .flat_map(|p| p.map(|x| (x.clamp(0.0, 1.0) * 255.0 + 0.5).floor() as u8))
        .collect();
    w.write_image_data(&bytes)
        .map_err(|e| format!("{}: {e}", path.display()))
}

/// The displayed color of a composited pixel (its associated color; the scenes composite
/// over an opaque background, so this is what a screen shows).
pub fn display(p: &Sample) -> [f32; 3] {
    p.c
}

/// Per-pixel absolute error (max over channels) between two displayed images.
pub fn error_map(a: &[[f32; 3]], b: &[[f32; 3]]) -> Vec<f32> {
    a.iter()
        .zip(b)
        .map(|(x, y)| (0..3).map(|k| (x[k] - y[k]).abs()).fold(0.0, f32::max))
        .collect()
}

/// An error map as a grey image, amplified `gain` times (as the paper's difference images).
pub fn error_image(err: &[f32], gain: f32) -> Vec<[f32; 3]> {
    err.iter().map(|&e| [(e * gain).min(1.0); 3]).collect()
}

/// An error map histogram-equalised (as the paper's fig. 12): each pixel's grey level is the
/// fraction of pixels with a smaller error, so the structure of small errors shows.
pub fn equalised_error_image(err: &[f32]) -> Vec<[f32; 3]> {
    let mut sorted: Vec<f32> = err.to_vec();
    sorted.sort_by(f32::total_cmp);
    let n = sorted.len().max(1) as f32;
    err.iter()
        .map(|&e| {
            if e <= 0.0 {
                return [0.0; 3];
            }
            let rank = sorted.partition_point(|&x| x < e) as f32;
            [rank / n; 3]
        })
        .collect()
}
