//! The error-against-time plot.

use std::path::Path;

use plotters::coord::CoordTranslate;
use plotters::prelude::*;

use crate::float_checks::FilterKind;
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

/// The marker of a filter: nearest a square, trilinear a circle, the tree order a diamond,
/// the B-spline a triangle.
fn marker_name(f: FilterKind) -> &'static str {
    match f {
        FilterKind::Nearest => "square: nearest",
        FilterKind::TrilinearSum => "circle: trilinear",
        FilterKind::TrilinearTree => "diamond: trilinear (tree order)",
        FilterKind::BSpline => "triangle: B-spline",
    }
}

/// Draws the marker of filter `f` at `at` (in `area`'s coordinates) in `style`.
fn marker<DB: DrawingBackend, X, CT: CoordTranslate<From = X>>(
    area: &DrawingArea<DB, CT>,
    f: FilterKind,
    at: X,
    style: ShapeStyle,
) -> Result<(), String> {
    let r = 6;
    let at = EmptyElement::at(at);
    match f {
        FilterKind::Nearest => area.draw(&(at + Rectangle::new([(-r, -r), (r, r)], style))),
        FilterKind::TrilinearSum => area.draw(&(at + Circle::new((0, 0), r, style))),
        FilterKind::TrilinearTree => {
            area.draw(&(at + Polygon::new(vec![(0, -r), (r, 0), (0, r), (-r, 0)], style)))
        }
        FilterKind::BSpline => area.draw(&(at + TriangleMarker::new((0, 0), r + 1, style))),
    }
    .map_err(|e| e.to_string())
}

/// Plots mean RMS error (8-bit levels) against ns/sample, one point per method: color by
/// mode, marker shape by filter, filled for `f32` and hollow for integer arithmetic; the
/// legend beside the data, not over it. `subtitle` names the scenes and the truth.
///
/// # Errors
/// Missing font or an unwritable file, as text.
pub fn error_vs_time(
    path: &Path,
    subtitle: &str,
    summary: &[(Method, f64, f64, f64, usize)],
) -> Result<(), String> {
    register_font()?;
    let (w, h) = PLOT_SIZE;
    let mut buf = vec![0u8; 3 * w as usize * h as usize];
    draw(
        BitMapBackend::with_buffer(&mut buf, PLOT_SIZE).into_drawing_area(),
        subtitle,
        summary,
    )?;
    crate::images::write_rgb8(path, w as usize, h as usize, &buf)
}

/// The plot of [`error_vs_time`] as SVG text (for the report's page).
///
/// # Errors
/// Missing font, as text.
pub fn error_vs_time_svg(
    subtitle: &str,
    summary: &[(Method, f64, f64, f64, usize)],
) -> Result<String, String> {
    register_font()?;
    let mut svg = String::new();
    draw(
        SVGBackend::with_string(&mut svg, PLOT_SIZE).into_drawing_area(),
        subtitle,
        summary,
    )?;
    Ok(svg)
}

/// The plot's size in pixels.
const PLOT_SIZE: (u32, u32) = (1200, 680);

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    subtitle: &str,
    summary: &[(Method, f64, f64, f64, usize)],
) -> Result<(), String> {
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let (plot_area, legend) = root.split_horizontally(900);
    let finite = |v: f64| if v.is_finite() { v } else { 0.0 };
    let xmax = summary.iter().map(|s| finite(s.3)).fold(1.0, f64::max) * 1.1;
    let ymax = summary.iter().map(|s| finite(s.1)).fold(0.1, f64::max) * 1.1;
    let mut chart = ChartBuilder::on(&plot_area)
        .caption(
            format!("error against time: {subtitle}"),
            ("sans-serif", 20),
        )
        .margin(16)
        .x_label_area_size(48)
        .y_label_area_size(64)
        .build_cartesian_2d(0.0..xmax, 0.0..ymax)
        .map_err(|e| e.to_string())?;
    chart
        .configure_mesh()
        .x_desc("ns per sample")
        .y_desc("mean RMS error (8-bit levels)")
        .draw()
        .map_err(|e| e.to_string())?;
    for s in summary
        .iter()
        .filter(|s| s.3.is_finite() && s.1.is_finite())
    {
        let c = color(&s.0);
        let style = if s.0.precision == Precision::F32 {
            c.filled()
        } else {
            c.stroke_width(2)
        };
        marker(chart.plotting_area(), s.0.filter, (s.3, s.1), style)?;
    }
    // The legend: colors (modes), shapes (filters), fill (precision).
    let text = ("sans-serif", 15).into_font();
    let mut y = 40;
    let line = |y: i32, label: &str| {
        legend
            .draw(&Text::new(label.to_string(), (44, y - 8), text.clone()))
            .map_err(|e| e.to_string())
    };
    for mode in ModeChoice::ALL {
        if !summary.iter().any(|s| s.0.mode == mode) {
            continue;
        }
        let m = Method {
            mode,
            precision: Precision::F32,
            filter: FilterKind::TrilinearSum,
        };
        legend
            .draw(&Rectangle::new(
                [(16, y - 7), (30, y + 7)],
                color(&m).filled(),
            ))
            .map_err(|e| e.to_string())?;
        line(y, mode.label())?;
        y += 24;
    }
    y += 12;
    for f in FilterKind::ALL {
        if !summary.iter().any(|s| s.0.filter == f) {
            continue;
        }
        marker(&legend, f, (23, y), BLACK.stroke_width(2))?;
        line(y, marker_name(f))?;
        y += 24;
    }
    y += 12;
    marker(&legend, FilterKind::TrilinearSum, (23, y), BLACK.filled())?;
    line(y, "filled: f32 arithmetic")?;
    y += 24;
    marker(
        &legend,
        FilterKind::TrilinearSum,
        (23, y),
        BLACK.stroke_width(2),
    )?;
    line(y, "hollow: integer (F = 8)")?;
    root.present().map_err(|e| e.to_string())
}
