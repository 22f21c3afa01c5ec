//! The verdicts, computed from the report's numbers (never typed in).

use super::{Group, Report, Row, Summary, Truth, VISIBLE_LEVELS};
use crate::float_checks::FilterKind;
use crate::pipeline::{Method, ModeChoice, Precision, INT_BITS_SWEEP, INT_TABLE_SWEEP};

/// How close to the most accurate a method must be to count as "as good": within 5 % of its
/// RMS or half a level, whichever is more.
pub fn as_good(rms: f64, best: f64) -> bool {
    rms <= (best * 1.05).max(best + 0.5)
}

/// The cheapest of `items` (by `ns`, then RMS) whose RMS is [`as_good`] as the best's.
fn pick<'a>(items: &[(&'a Method, f64, f64)]) -> Option<(&'a Method, f64, f64)> {
    let best = items.iter().map(|x| x.1).fold(f64::INFINITY, f64::min);
    items
        .iter()
        .filter(|x| as_good(x.1, best))
        .min_by(|a, b| a.2.total_cmp(&b.2).then(a.1.total_cmp(&b.1)))
        .copied()
}

fn separate_vs_ow<T>(items: &[T], method: impl Fn(&T) -> &Method) -> Option<(&T, &T)> {
    let find = |mode| {
        items.iter().find(|x| {
            let m = method(x);
            m.mode == mode && m.precision == Precision::F32 && m.filter == FilterKind::TrilinearSum
        })
    };
    Some((
        find(ModeChoice::Separate)?,
        find(ModeChoice::OpacityWeighted)?,
    ))
}

/// Whether `Separate` leaks visibly where `OpacityWeighted` (both f32 trilinear) has RMS
/// `ow`: more than a level worse, and by more than a fifth.
pub fn leaks(separate: f64, ow: f64) -> bool {
    separate > ow + 1.0 && separate > 1.2 * ow
}

/// The verdict lines of one scene, computed from its rows and the times.
pub fn scene_verdict(report: &Report, scene: &str) -> Vec<String> {
    let rows: Vec<&Row> = report.rows.iter().filter(|r| r.scene == scene).collect();
    let Some(first) = rows.first() else {
        return Vec::new();
    };
    let truth = if rows.iter().all(|r| r.continuous.is_some()) {
        Truth::Continuous
    } else {
        Truth::Field
    };
    let items: Vec<(&Method, f64, f64)> = rows
        .iter()
        .filter_map(|r| {
            Some((
                &r.method,
                r.against(truth)?.rms,
                report.ns(first.group, &r.method),
            ))
        })
        .collect();
    let mut out = Vec::new();
    let best = items.iter().min_by(|a, b| a.1.total_cmp(&b.1));
    if let (Some(best), Some(p)) = (best, pick(&items)) {
        out.push(format!(
            "verdict {scene} (against the {}): most accurate {} (RMS {:.2}); pick {} (RMS {:.2}, {:.1} ns/sample)",
            truth.label(),
            best.0.label(),
            best.1,
            p.0.label(),
            p.1,
            p.2
        ));
    }
    if let Some((s, o)) = separate_vs_ow(&rows, |r| &r.method) {
        if let (Some(se), Some(oe)) = (s.against(truth), o.against(truth)) {
            out.push(if leaks(se.rms, oe.rms) {
                format!(
                    "  Separate leaks: RMS {:.2} against {:.2} for opacity-weighted, {:.1} % of pixels off by more than {VISIBLE_LEVELS} levels against {:.1} %",
                    se.rms, oe.rms, 100.0 * se.over, 100.0 * oe.over
                )
            } else {
                format!(
                    "  Separate does not leak visibly here: RMS {:.2} against {:.2} for opacity-weighted",
                    se.rms, oe.rms
                )
            });
        }
    }
    out
}

/// The overall verdict of a group, computed from its summary.
pub fn group_verdict(report: &Report, group: Group) -> Vec<String> {
    let truth = report.truth_of(group);
    let s = report.summary(group, truth);
    let items: Vec<(&Method, f64, f64)> =
        s.iter().map(|x| (&x.method, x.errors.rms, x.ns)).collect();
    let mut out = Vec::new();
    let scenes = s.first().map_or(0, |x| x.scenes);
    if let (Some(p), Some(best)) = (pick(&items), s.first()) {
        out.push(format!(
            "VERDICT, {} ({scenes}, against the {}): pick {}: mean RMS {:.2}, {:.1} ns/sample (the most accurate, {}, has {:.2} at {:.1} ns/sample)",
            group.label(),
            truth.label(),
            p.0.label(),
            p.1,
            p.2,
            best.method.label(),
            best.errors.rms,
            best.ns
        ));
    }
    // The budget ladder: the Pareto front by time, each the most accurate at its cost.
    let mut by_time: Vec<&(&Method, f64, f64)> = items.iter().filter(|x| x.2.is_finite()).collect();
    by_time.sort_by(|a, b| a.2.total_cmp(&b.2).then(a.1.total_cmp(&b.1)));
    let mut best_so_far = f64::INFINITY;
    let mut ladder = Vec::new();
    for x in by_time {
        if x.1 < best_so_far {
            best_so_far = x.1;
            ladder.push(format!("{:.1} ns: {} (RMS {:.2})", x.2, x.0.label(), x.1));
        }
    }
    if !ladder.is_empty() {
        out.push(format!("  by budget: {}", ladder.join("; ")));
    }
    // Where Separate leaks, scene by scene.
    let mut leaking = Vec::new();
    let mut total = 0;
    for scene in report.scenes() {
        let rows: Vec<&Row> = report
            .rows
            .iter()
            .filter(|r| r.scene == scene && r.group == group)
            .collect();
        if let Some((sr, or)) = separate_vs_ow(&rows, |r| &r.method) {
            if let (Some(se), Some(oe)) = (sr.against(truth), or.against(truth)) {
                total += 1;
                if leaks(se.rms, oe.rms) {
                    leaking.push(format!("{scene} {:.1} vs {:.1}", se.rms, oe.rms));
                }
            }
        }
    }
    if total > 0 {
        out.push(format!(
            "  Separate leaks in {} of {total} scenes{}",
            leaking.len(),
            if leaking.is_empty() {
                String::new()
            } else {
                format!(" (RMS against opacity-weighted: {})", leaking.join(", "))
            }
        ));
    }
    // What the choice of truth changes.
    let other = if truth == Truth::Continuous {
        Truth::Field
    } else {
        Truth::Continuous
    };
    let o = report.summary(group, other);
    if let (Some(a), Some(b)) = (s.first(), o.first()) {
        if !o.is_empty() && o.iter().all(|x| x.scenes == scenes) {
            out.push(format!(
                "  most accurate against the {}: {} (RMS {:.2}); against the {}: {} (RMS {:.2})",
                truth.label(),
                a.method.label(),
                a.errors.rms,
                other.label(),
                b.method.label(),
                b.errors.rms
            ));
        }
    }
    out
}

/// The precision lines of a group, from its summary (means over its scenes, against the
/// group's truth): error and time against the integer kernels' fractional position bits
/// (`OpacityWeighted` trilinear), against the integer extinction tables' size, and the GPU
/// texture unit's filtering against the `f32` filter on the same storage. Empty where the
/// group has none of these rows.
pub fn precision_lines(report: &Report, group: Group) -> Vec<String> {
    let truth = report.truth_of(group);
    let s = report.summary(group, truth);
    let find = |mode, precision| {
        s.iter().find(|x| {
            x.method
                == Method {
                    mode,
                    precision,
                    filter: FilterKind::TrilinearSum,
                }
        })
    };
    let cell = |x: &Summary| {
        let from = x
            .from_f32
            .map_or(String::new(), |f| format!("{f:.2} from f32, "));
        if x.ns.is_finite() {
            format!("{from}RMS {:.2} at {:.1} ns", x.errors.rms, x.ns)
        } else {
            format!("{from}RMS {:.2}", x.errors.rms)
        }
    };
    let mut out = Vec::new();
    let sweep = |mode, points: Vec<(String, Precision)>| -> Option<String> {
        let cells: Vec<String> = points
            .into_iter()
            .filter_map(|(name, p)| find(mode, p).map(|x| format!("{name}: {}", cell(x))))
            .collect();
        (cells.len() > 1).then(|| cells.join("; "))
    };
    let mut bits: Vec<(u32, Precision)> = INT_BITS_SWEEP
        .iter()
        .map(|&b| (b, Precision::IntBits(b)))
        .collect();
    bits.push((crate::pipeline::INT_FRAC_BITS, Precision::Int8));
    bits.sort_by_key(|x| x.0);
    let f32_of = |mode| find(mode, Precision::F32).map(|x| format!(" (f32: {})", cell(x)));
    if let Some(l) = sweep(
        ModeChoice::OpacityWeighted,
        bits.into_iter()
            .map(|(b, p)| (format!("F={b}"), p))
            .collect(),
    ) {
        out.push(format!(
            "  precision, opacity-weighted trilinear, integer, by fractional position bits (RMS from the f32 image, and against the {}): {l}{}",
            truth.label(),
            f32_of(ModeChoice::OpacityWeighted).unwrap_or_default()
        ));
    }
    let mut tables: Vec<(usize, Precision)> = INT_TABLE_SWEEP
        .iter()
        .map(|&n| (n, Precision::IntTable(n)))
        .collect();
    tables.push((crate::pipeline::INT_EXTINCTION_TABLE, Precision::Int8));
    tables.sort_by_key(|x| x.0);
    if let Some(l) = sweep(
        ModeChoice::ExtinctionWeighted,
        tables
            .into_iter()
            .map(|(n, p)| (format!("N={n}"), p))
            .collect(),
    ) {
        out.push(format!(
            "  precision, extinction trilinear, integer F=8, by table nodes (RMS from the f32 image, and against the {}): {l}{}",
            truth.label(),
            f32_of(ModeChoice::ExtinctionWeighted).unwrap_or_default()
        ));
    }
    for (mode, storage) in [
        (ModeChoice::Separate, "straight RGBA8 (separate)"),
        (
            ModeChoice::PreweightedU8,
            "premultiplied RGBA8 (preweighted-u8)",
        ),
    ] {
        if let (Some(g), Some(f)) = (find(mode, Precision::Texture8), find(mode, Precision::F32)) {
            out.push(format!(
                "  GPU texture unit (8-bit weights, f32 compositing, not timed) on {storage}: {}RMS {:.2}; the f32 filter on {}: RMS {:.2}",
                g.from_f32.map_or(String::new(), |x| format!("{x:.2} from f32, ")),
                g.errors.rms,
                if mode == ModeChoice::Separate {
                    "f32 straight voxels"
                } else {
                    "the same storage"
                },
                f.errors.rms
            ));
        }
    }
    out
}
