//! The report in text and files: the terminal tables, CSV, JSON, the plots and the page.

use std::fmt::Write as _;
use std::path::Path;

use super::verdict::precision_lines;
use super::verdict::{group_verdict, scene_verdict};
use super::{time_cells, Errors, Group, Report, Row, Summary, Truth, VISIBLE_LEVELS};
use crate::pipeline::Method;

fn errors_cells(e: Option<Errors>) -> String {
    match e {
        Some(e) => format!("{:>7.2} {:>6.1} {:>6.1}", e.rms, e.p99, 100.0 * e.over),
        None => format!("{:>7} {:>6} {:>6}", "-", "-", "-"),
    }
}

/// The terminal report: the truths named, each scene's table and verdict, each group's
/// summary and verdict, and where the times come from.
pub fn format_report(report: &Report) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "truths (errors in 8-bit levels; p99: the 99th-percentile pixel; >{VISIBLE_LEVELS}: % of pixels off by more than {VISIBLE_LEVELS} levels):");
    for t in [Truth::Continuous, Truth::Field] {
        let _ = writeln!(out, "  {}: {}", t.label(), t.describes());
    }
    let _ = writeln!(out, "times: ns/sample of one frame (median of the timed frames) on each group's timing scene, {}", report.machine.line());
    for t in report
        .groups()
        .into_iter()
        .filter_map(|g| report.timings.iter().find(|t| t.group == g))
    {
        let ((d, i), rays) = (t.sizes, t.sizes.1[0] * t.sizes.1[1]);
        let _ = writeln!(
            out,
            "  {}: {} ({}x{}x{} voxels, {}x{} = {rays} rays)",
            t.group.label(),
            t.scene,
            d[0],
            d[1],
            d[2],
            i[0],
            i[1]
        );
    }
    let header = |out: &mut String, title: &str| {
        let _ = writeln!(out);
        let _ = writeln!(out, "{title}");
        let _ = writeln!(
            out,
            "{:<40} {:>22} {:>22} {:>9} {:>6}",
            "", "-- continuous scene --", "-- extinction field --", "", ""
        );
        let _ = writeln!(
            out,
            "{:<40} {:>7} {:>6} {:>6} {:>7} {:>6} {:>6} {:>9} {:>6}",
            "method (mode/precision/filter)",
            "RMS",
            "p99",
            ">8 %",
            "RMS",
            "p99",
            ">8 %",
            "ns/sample",
            "cost"
        );
    };
    for scene in report.scenes() {
        let rows: Vec<&Row> = report.rows.iter().filter(|r| r.scene == scene).collect();
        let Some(group) = rows.first().map(|r| r.group) else {
            continue;
        };
        let cheapest = rows
            .iter()
            .map(|r| report.ns(group, &r.method))
            .fold(f64::INFINITY, f64::min);
        header(&mut out, &format!("scene {scene}"));
        let mut sorted = rows.clone();
        sorted.sort_by(|a, b| {
            let k = |r: &Row| r.continuous.map_or(r.field.rms, |e| e.rms);
            k(a).total_cmp(&k(b))
        });
        for r in sorted {
            let (ns, cost) = time_cells(report.ns(group, &r.method), cheapest);
            let _ = writeln!(
                out,
                "{:<40} {} {} {ns:>9} {cost:>6}",
                r.method.label(),
                errors_cells(r.continuous),
                errors_cells(Some(r.field)),
            );
        }
        for l in scene_verdict(report, scene) {
            let _ = writeln!(out, "{l}");
        }
    }
    for group in report.groups() {
        let c = report.summary(group, Truth::Continuous);
        let f = report.summary(group, Truth::Field);
        let n = f.first().map_or(0, |x| x.scenes);
        header(
            &mut out,
            &format!("summary, {} ({n}; means over the scenes)", group.label()),
        );
        let cheapest = f.iter().map(|x| x.ns).fold(f64::INFINITY, f64::min);
        let order: Vec<&Summary> = if c.is_empty() {
            f.iter().collect()
        } else {
            c.iter().collect()
        };
        for x in order {
            let cont = c.iter().find(|y| y.method == x.method).map(|y| y.errors);
            let field = f.iter().find(|y| y.method == x.method).map(|y| y.errors);
            let (ns, cost) = time_cells(x.ns, cheapest);
            let _ = writeln!(
                out,
                "{:<40} {} {} {ns:>9} {cost:>6}",
                x.method.label(),
                errors_cells(cont),
                errors_cells(field),
            );
        }
        for l in precision_lines(report, group) {
            let _ = writeln!(out, "{l}");
        }
    }
    let _ = writeln!(out);
    for group in report.groups() {
        for l in group_verdict(report, group) {
            let _ = writeln!(out, "{l}");
        }
    }
    out
}

pub(super) fn write_outputs(out: &Path, report: &Report) -> Result<(), String> {
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let mut csv = String::from(
        "scene,group,mode,precision,filter,rms_continuous,p99_continuous,over8_continuous,rms_field,p99_field,over8_field,rms_from_f32,ns_per_sample,samples\n",
    );
    let mut json = Vec::new();
    let cell = |x: Option<f64>| x.map_or(String::new(), |v| format!("{v:.4}"));
    for r in &report.rows {
        let l = r.method.label();
        let parts: Vec<&str> = l.split('/').collect();
        let (mode, precision, filter) = (parts[0], parts[1], parts[2]);
        let ns = report.ns(r.group, &r.method);
        let _ = writeln!(
            csv,
            "{},{},{mode},{precision},{filter},{},{},{},{:.4},{:.4},{:.4},{},{:.3},{}",
            r.scene,
            r.group.label(),
            cell(r.continuous.map(|e| e.rms)),
            cell(r.continuous.map(|e| e.p99)),
            cell(r.continuous.map(|e| e.over)),
            r.field.rms,
            r.field.p99,
            r.field.over,
            cell(r.from_f32.map(|e| e.rms)),
            ns,
            r.samples
        );
        let e = |x: Option<Errors>| {
            x.map(|e| serde_json::json!({ "rms_8bit": e.rms, "p99_8bit": e.p99, "share_over_8": e.over }))
        };
        json.push(serde_json::json!({
            "scene": r.scene, "group": r.group.label(), "mode": mode, "precision": precision, "filter": filter,
            "continuous": e(r.continuous), "field": e(Some(r.field)), "from_f32": e(r.from_f32), "ns_per_sample": ns, "samples": r.samples,
        }));
    }
    let timings: Vec<_> = report
        .timings
        .iter()
        .map(|t| {
            serde_json::json!({
                "group": t.group.label(), "scene": t.scene, "dims": t.sizes.0, "image": t.sizes.1,
                "method": t.method.label(), "ns_per_sample": t.ns_per_sample, "samples": t.samples,
            })
        })
        .collect();
    let verdicts: Vec<String> = report
        .groups()
        .into_iter()
        .flat_map(|g| group_verdict(report, g))
        .collect();
    let w = |name: &str, text: String| {
        let p = out.join(name);
        std::fs::write(&p, text).map_err(|e| format!("{}: {e}", p.display()))
    };
    w("report.csv", csv)?;
    w(
        "report.json",
        serde_json::to_string_pretty(&serde_json::json!({
            "machine": { "isa": report.machine.isa.name(), "threads": report.machine.threads, "cpu": report.machine.cpu },
            "rows": json, "timings": timings, "verdict": verdicts,
        }))
        .map_err(|e| e.to_string())?,
    )?;
    w("report.txt", format_report(report))?;

    // One plot per group (the first, the RGBA scenes, keeps the former file name), also as
    // SVG in the page.
    let mut svgs = Vec::new();
    for (k, g) in report.groups().into_iter().enumerate() {
        let truth = report.truth_of(g);
        let s = report.summary(g, truth);
        let plotted: Vec<(Method, f64, f64, f64, usize)> = s
            .iter()
            .map(|x| (x.method, x.errors.rms, x.errors.p99, x.ns, x.scenes))
            .collect();
        let name = if k == 0 {
            "error_vs_time.png".to_string()
        } else {
            format!("error_vs_time-{}.png", plot_slug(g))
        };
        let subtitle = format!(
            "{} ({}), against the {}",
            g.label(),
            s.first().map_or(0, |x| x.scenes),
            truth.label()
        );
        crate::plot::error_vs_time(&out.join(name), &subtitle, &plotted)?;
        svgs.push(crate::plot::error_vs_time_svg(&subtitle, &plotted)?);
    }
    w("index.html", super::html::page_with(report, &svgs))
}

fn plot_slug(g: Group) -> &'static str {
    match g {
        Group::Rgba => "rgba",
        Group::Transfer => "transfer",
    }
}
