//! The report as one page: `report-out/index.html`, self-contained (no network: the plots
//! inline as SVG, the images relative files beside it), with the verdict, the tables and,
//! per scene, a labelled contact sheet of the truths, each method and its difference ×8.

use std::fmt::Write as _;

use super::{
    format_report, group_verdict, scene_verdict, Errors, Report, Row, Truth, SHOWN, VISIBLE_LEVELS,
};

/// A script that, once the page has loaded, records on `<body data-images=…>` whether every
/// image resolved: `ok N` (N images, each decoded with a width), or `broken: ` and the sources
/// that did not (a test reads it from headless Chromium's DOM).
pub const IMAGE_CHECK: &str = "<script>window.addEventListener('load',function(){\
var im=Array.from(document.images),bad=im.filter(function(i){return !(i.complete&&i.naturalWidth>0);});\
document.body.dataset.images=bad.length?'broken: '+bad.map(function(i){return i.getAttribute('src');}).join(' '):'ok '+im.length;});</script>";

/// HTML-escapes text.
pub fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

fn cells(e: Option<Errors>) -> String {
    match e {
        Some(e) => format!(
            "<td>{:.2}</td><td>{:.1}</td><td>{:.1}</td>",
            e.rms,
            e.p99,
            100.0 * e.over
        ),
        None => "<td>-</td><td>-</td><td>-</td>".into(),
    }
}

/// The file name of a method's image in a scene's folder.
fn image_name(row: &Row) -> String {
    row.method.label().replace('/', "_")
}

/// The page. The plots are read from `plots` (SVG text per group, inlined).
pub fn page_with(report: &Report, plots: &[String]) -> String {
    let mut h = String::new();
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <title>volsample report</title><style>\
         body{{font-family:sans-serif;margin:2em;max-width:1400px}}\
         table{{border-collapse:collapse;font-size:13px}}td,th{{border:1px solid #ccc;padding:2px 6px;text-align:right}}\
         td:first-child,th:first-child{{text-align:left}}\
         .sheet{{display:flex;flex-wrap:wrap;gap:10px}}figure{{margin:0;width:{SHOWN}px;font-size:12px}}\
         figure img{{width:{SHOWN}px;image-rendering:pixelated;display:block}}\
         .verdict{{background:#eef6ee;padding:8px;border-left:4px solid #4a4}}\
         pre{{font-size:12px;overflow-x:auto}}</style></head><body>\n"
    );
    let _ = writeln!(h, "<h1>volsample: what each sampling choice costs</h1>");
    let _ = writeln!(h, "<p>Times: {}.</p>", escape(&report.machine.line()));
    let _ = writeln!(h, "<h2>Verdict</h2><div class=\"verdict\" id=\"verdict\">");
    for g in report.groups() {
        for l in group_verdict(report, g) {
            let _ = writeln!(h, "<p>{}</p>", escape(&l));
        }
    }
    let _ = writeln!(h, "</div><h2>Truths</h2><ul>");
    for t in [Truth::Continuous, Truth::Field] {
        let _ = writeln!(
            h,
            "<li><b>{}</b>: {}</li>",
            t.label(),
            escape(t.describes())
        );
    }
    let _ = writeln!(
        h,
        "</ul><p>Errors in 8-bit levels: RMS over pixels and channels, p99 the 99th-percentile \
         pixel, &gt;{VISIBLE_LEVELS} the share of pixels (%) off by more than {VISIBLE_LEVELS} levels.</p>"
    );
    let _ = writeln!(h, "<h2>Error against time</h2>");
    for svg in plots {
        let _ = writeln!(h, "<div class=\"plot\">{svg}</div>");
    }
    for g in report.groups() {
        let c = report.summary(g, Truth::Continuous);
        let f = report.summary(g, Truth::Field);
        let cheapest = f.iter().map(|x| x.ns).fold(f64::INFINITY, f64::min);
        let _ = writeln!(
            h,
            "<h2>Summary: {} ({} scenes, means)</h2><table><tr><th>method</th>\
             <th colspan=3>continuous scene: RMS, p99, &gt;8 %</th>\
             <th colspan=3>extinction field: RMS, p99, &gt;8 %</th><th>ns/sample</th><th>cost</th></tr>",
            g.label(),
            f.first().map_or(0, |x| x.scenes)
        );
        let order = if c.is_empty() { &f } else { &c };
        for x in order {
            let cont = c.iter().find(|y| y.method == x.method).map(|y| y.errors);
            let field = f.iter().find(|y| y.method == x.method).map(|y| y.errors);
            let (ns, cost) = super::time_cells(x.ns, cheapest);
            let _ = writeln!(
                h,
                "<tr><td>{}</td>{}{}<td>{ns}</td><td>{cost}</td></tr>",
                escape(&x.method.label()),
                cells(cont),
                cells(field),
            );
        }
        let _ = writeln!(h, "</table>");
        let lines = super::precision_lines(report, g);
        if !lines.is_empty() {
            let _ = writeln!(
                h,
                "<div class=\"precision\" id=\"precision-{}\">",
                g.label().replace(' ', "-")
            );
            for l in lines {
                let _ = writeln!(h, "<p>{}</p>", escape(&l));
            }
            let _ = writeln!(h, "</div>");
        }
    }
    let _ = writeln!(h, "<h2>Scenes</h2>");
    for scene in report.scenes() {
        let _ = writeln!(h, "<h3 id=\"{0}\">{0}</h3>", escape(scene));
        for l in scene_verdict(report, scene) {
            let _ = writeln!(h, "<p>{}</p>", escape(&l));
        }
        let _ = writeln!(h, "<div class=\"sheet\">");
        let mut rows: Vec<&Row> = report.rows.iter().filter(|r| r.scene == scene).collect();
        if rows.iter().all(|r| r.continuous.is_some()) {
            let _ = writeln!(
                h,
                "<figure><img src=\"images/{0}/truth-continuous.png\" alt=\"continuous truth\">\
                 <figcaption>truth: continuous scene</figcaption></figure>",
                escape(scene)
            );
        }
        let _ = writeln!(
            h,
            "<figure><img src=\"images/{0}/truth.png\" alt=\"extinction-field truth\">\
             <figcaption>truth: extinction field</figcaption></figure></div>",
            escape(scene)
        );
        rows.sort_by(|a, b| {
            let k = |r: &Row| r.continuous.map_or(r.field.rms, |e| e.rms);
            k(a).total_cmp(&k(b))
        });
        let _ = writeln!(h, "<div class=\"sheet\">");
        for r in rows {
            let e = r.continuous.unwrap_or(r.field);
            let _ = writeln!(
                h,
                "<figure><img src=\"images/{s}/{f}.png\" alt=\"{l}\">\
                 <img src=\"images/{s}/{f}-diff.png\" alt=\"{l}: difference x8\">\
                 <figcaption><b>{l}</b><br>RMS {:.2}, p99 {:.1}, &gt;8: {:.1} % \
                 (image; below it the difference from the truth x8)</figcaption></figure>",
                e.rms,
                e.p99,
                100.0 * e.over,
                s = escape(scene),
                f = escape(&image_name(r)),
                l = escape(&r.method.label()),
            );
        }
        let _ = writeln!(h, "</div>");
    }
    let _ = writeln!(
        h,
        "<h2>The terminal report</h2><pre>{}</pre>{IMAGE_CHECK}</body></html>",
        escape(&format_report(report))
    );
    h
}

/// [`page_with`] without plots.
pub fn page(report: &Report) -> String {
    page_with(report, &[])
}
