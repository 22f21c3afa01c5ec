//! The error-against-time plot.

use std::path::Path;

use plotters::prelude::*;

use crate::pipeline::{Method, ModeChoice, Precision};

/// DejaVu Sans, where Debian's `fonts-dejavu-core` puts it; the plot needs a font for its
/// labels and `.ci/run` installs the package.
pub const FONT: &str = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

/// Registers [`FONT`] as plotters' "sans-serif" (once per call; cheap next to a plot).
///
/// # Errors
/// A missing or unusable font file, as text.
pub fn register_font() -> Result<(), String> {
    let bytes =
        std::fs::read(FONT).map_err(|e| format!("{FONT}: {e} (install fonts-dejavu-core)"))?;
    let leaked: &'static [u8] = Box::leak(bytes.into_boxed_slice());
    plotters::style::register_font("sans-serif", FontStyle::Normal, leaked)
        .map_err(|_| format!("{FONT}: not a usable font"))
}

fn color(m: &Method) -> RGBColor {
    match m.mode {
        ModeChoice::Separate => RGBColor(220, 50, 47),
        ModeChoice::OpacityWeighted => RGBColor(38, 139, 210),
        ModeChoice::Preweighted => RGBColor(133, 153, 0),
        ModeChoice::PreweightedU8 => RGBColor(181, 137, 0),
        ModeChoice::ExtinctionWeighted => RGBColor(108, 113, 196),
        ModeChoice::PostClassified => RGBColor(42, 161, 152),
    }
}

/// Plots mean RMS error (8-bit levels) against ns/sample, one point per method: color by
/// mode, filled for f32 and hollow for integer.
///
/// # Errors
/// Missing font or an unwritable file, as text.
pub fn error_vs_time(
    path: &Path,
    summary: &[(Method, f64, f64, f64, usize)],
) -> Result<(), String> {
    register_font()?;
    let root = BitMapBackend::new(path, (960, 640)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let xmax = summary.iter().map(|s| s.3).fold(1.0, f64::max) * 1.1;
    let ymax = summary.iter().map(|s| s.1).fold(0.1, f64::max) * 1.1;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "volsample: error against time (mean over scenes)",
            ("sans-serif", 24),
        )
        .margin(16)
        .x_label_area_size(48)
        .y_label_area_size(64)
        .build_cartesian_2d(0.0..xmax, 0.0..ymax)
        .map_err(|e| e.to_string())?;
    chart
        .configure_mesh()
        .x_desc("ns per sample")
        .y_desc("RMS error (8-bit levels)")
        .draw()
        .map_err(|e| e.to_string())?;
    for mode in ModeChoice::ALL {
        let pts: Vec<&(Method, f64, f64, f64, usize)> =
            summary.iter().filter(|s| s.0.mode == mode).collect();
        if pts.is_empty() {
            continue;
        }
        let c = color(&pts[0].0);
        chart
            .draw_series(pts.iter().map(|s| {
                let style = if s.0.precision == Precision::F32 {
                    c.filled()
                } else {
                    c.stroke_width(2)
                };
                Circle::new((s.3, s.1), 6, style)
            }))
            .map_err(|e| e.to_string())?
            .label(mode.label())
            .legend(move |(x, y)| Circle::new((x, y), 6, c.filled()));
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(|e| e.to_string())?;
    root.present().map_err(|e| e.to_string())
}
