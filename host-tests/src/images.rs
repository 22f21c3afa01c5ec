//! Writing images: rendered pixels (enlarged where small), error images, labelled strips.

use std::path::Path;

use volsample::Sample;

/// Writes an 8-bit RGB PNG from rows of `[r, g, b]` in `[0, 1]` (round half up).
///
/// # Errors
/// I/O or encoder errors, as text.
pub fn write_rgb(path: &Path, width: usize, height: usize, rgb: &[[f32; 3]]) -> Result<(), String> {
    let bytes: Vec<u8> = rgb
        .iter()
        .flat_map(|p| p.map(|x| (x.clamp(0.0, 1.0) * 255.0 + 0.5).floor() as u8))
        .collect();
    write_rgb8(path, width, height, &bytes)
}

/// Writes an 8-bit RGB PNG from `width × height` pixels of three bytes each, row by row.
///
/// # Errors
/// I/O or encoder errors (also a buffer of another size), as text.
pub(crate) fn write_rgb8(
    path: &Path,
    width: usize,
    height: usize,
    bytes: &[u8],
) -> Result<(), String> {
    let (w, h) = match (u32::try_from(width), u32::try_from(height)) {
        (Ok(w), Ok(h)) => (w, h),
        _ => return Err(format!("{}: {width}×{height} is too large", path.display())),
    };
    let file = std::fs::File::create(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), w, h);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    enc.write_header()
        .and_then(|mut w| w.write_image_data(bytes))
        .map_err(|e| format!("{}: {e}", path.display()))
}

/// [`write_rgb`] of the image enlarged `k` times (each pixel a `k × k` block), so that a
/// small frame shows at a size a person can see.
///
/// # Errors
/// As [`write_rgb`].
pub fn write_rgb_scaled(
    path: &Path,
    width: usize,
    height: usize,
    rgb: &[[f32; 3]],
    k: usize,
) -> Result<(), String> {
    let k = k.max(1);
    let mut big = Vec::with_capacity(width * height * k * k);
    for row in rgb.chunks(width.max(1)).take(height) {
        for _ in 0..k {
            for p in row {
                big.extend(std::iter::repeat_n(*p, k));
            }
        }
    }
    write_rgb(path, width * k, height * k, &big)
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

/// Height of the label bar above each panel of [`write_panels`], pixels.
pub const LABEL_BAR: usize = 18;

/// Writes panels of `width × height` pixels side by side, left to right, into an 8-bit RGB
/// PNG, each under a bar with its label (DejaVu Sans, [`crate::plot::FONT`]). Returns a
/// warning where the font is missing (the bars are then left blank).
///
/// # Errors
/// An image over [`crate::view::render::MAX_PIXELS`], I/O or encoder errors, as text.
pub fn write_panels(
    path: &Path,
    width: usize,
    height: usize,
    panels: &[(String, Vec<[f32; 3]>)],
) -> Result<Option<String>, String> {
    use plotters::prelude::*;
    let total_w = width.saturating_mul(panels.len());
    let total_h = height.saturating_add(LABEL_BAR);
    let px = total_w.saturating_mul(total_h);
    if px == 0 || px > crate::view::render::MAX_PIXELS {
        return Err(format!(
            "{}: a strip of {} panels of {width} x {height} is too large or empty",
            path.display(),
            panels.len()
        ));
    }
    let mut buf = vec![0u8; px * 3];
    for (k, (_, rgb)) in panels.iter().enumerate() {
        for j in 0..height {
            for i in 0..width {
                let o = 3 * ((j + LABEL_BAR) * total_w + k * width + i);
                if let (Some(p), Some(dst)) = (rgb.get(j * width + i), buf.get_mut(o..o + 3)) {
                    for (d, x) in dst.iter_mut().zip(p) {
                        *d = (x.clamp(0.0, 1.0) * 255.0 + 0.5).floor() as u8;
                    }
                }
            }
        }
    }
    let warning = match crate::plot::register_font() {
        Err(e) => Some(format!("panel labels left out: {e}")),
        Ok(()) => {
            let root = BitMapBackend::with_buffer(&mut buf, (total_w as u32, total_h as u32))
                .into_drawing_area();
            let style = ("sans-serif", 13).into_font().color(&WHITE);
            for (k, (label, _)) in panels.iter().enumerate() {
                root.draw_text(label, &style, ((k * width + 4) as i32, 2))
                    .map_err(|e| format!("{}: label: {e}", path.display()))?;
            }
            root.present()
                .map_err(|e| format!("{}: label: {e}", path.display()))?;
            None
        }
    };
    write_rgb8(path, total_w, total_h, &buf)?;
    Ok(warning)
}
