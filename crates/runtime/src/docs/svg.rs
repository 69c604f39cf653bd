//! The default experiment as an inline SVG: one panel per unit, every output of that unit
//! as a coloured line, time along a shared axis. Deterministic text (fixed number formats).

use super::{escape, Trajectory};
use std::fmt::Write as _;

const WIDTH: f64 = 760.0;
const PANEL: f64 = 150.0; // plot height of one panel
const GAP: f64 = 46.0; // between panels: title and tick labels
const LEFT: f64 = 72.0;
const RIGHT: f64 = 150.0; // legend
const TOP: f64 = 26.0;
const BOTTOM: f64 = 40.0;
/// At most this many points per line (the run is decimated by a fixed stride).
const MAX_POINTS: usize = 600;
/// Matplotlib's tab10: distinct, readable on white.
const COLORS: [&str; 10] = [
    "#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f",
    "#bcbd22", "#17becf",
];

/// The SVG of a run (an empty note when there is nothing to plot); `title` names it for
/// assistive technology.
pub fn plot(run: &Trajectory, title: &str) -> String {
    if run.time.len() < 2 || run.signals.is_empty() {
        return "<p><em>Nothing to plot.</em></p>\n".into();
    }
    // panels: units in order of first appearance
    let mut units: Vec<&str> = Vec::new();
    for (v, _) in &run.signals {
        if !units.contains(&v.unit) {
            units.push(v.unit);
        }
    }
    let height = TOP + units.len() as f64 * (PANEL + GAP) - GAP + BOTTOM;
    let (t0, t1) = (run.time[0], *run.time.last().expect("two points"));
    let plot_w = WIDTH - LEFT - RIGHT;
    let sx = |t: f64| LEFT + (t - t0) / (t1 - t0).max(f64::MIN_POSITIVE) * plot_w;
    let stride = run.time.len().div_ceil(MAX_POINTS).max(1);
    let mut idx: Vec<usize> = (0..run.time.len()).step_by(stride).collect();
    if idx.last() != Some(&(run.time.len() - 1)) {
        idx.push(run.time.len() - 1);
    }

    let mut s = String::new();
    let _ = writeln!(
        s,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 {WIDTH} {height:.0}\" width=\"{WIDTH}\" height=\"{height:.0}\" \
         font-family=\"system-ui, sans-serif\" font-size=\"12\" role=\"img\" aria-label=\"{}\">",
        escape(title)
    );
    let _ = writeln!(s, "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>");
    let (x_ticks, x_dec) = ticks(t0, t1);
    for (p, unit) in units.iter().enumerate() {
        let top = TOP + p as f64 * (PANEL + GAP);
        let bottom = top + PANEL;
        let series: Vec<_> = run
            .signals
            .iter()
            .filter(|(v, _)| v.unit == *unit)
            .collect();
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for (_, ys) in &series {
            for y in ys.iter().filter(|y| y.is_finite()) {
                lo = lo.min(*y);
                hi = hi.max(*y);
            }
        }
        if !lo.is_finite() {
            (lo, hi) = (-1.0, 1.0);
        }
        if hi - lo <= 1e-12 * hi.abs().max(lo.abs()).max(1e-300) {
            let pad = if hi == 0.0 { 1.0 } else { 0.1 * hi.abs() };
            (lo, hi) = (lo - pad, hi + pad);
        } else {
            let pad = 0.05 * (hi - lo);
            (lo, hi) = (lo - pad, hi + pad);
        }
        let (y_ticks, y_dec) = ticks(lo, hi);
        let sy = |y: f64| bottom - (y - lo) / (hi - lo) * PANEL;
        // frame, grid, ticks
        let _ = writeln!(
            s,
            "<text x=\"{LEFT}\" y=\"{:.1}\" font-weight=\"600\">{}</text>",
            top - 8.0,
            escape(&format!("unit: {unit}"))
        );
        for &y in &y_ticks {
            let py = sy(y);
            let _ = writeln!(
                s,
                "<line x1=\"{LEFT}\" x2=\"{:.1}\" y1=\"{py:.1}\" y2=\"{py:.1}\" stroke=\"#e5e7eb\"/>\
                 <text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"end\" fill=\"#444\">{}</text>",
                LEFT + plot_w,
                LEFT - 6.0,
                py + 4.0,
                label(y, y_dec)
            );
        }
        for &t in &x_ticks {
            let px = sx(t);
            let _ = writeln!(
                s,
                "<line x1=\"{px:.1}\" x2=\"{px:.1}\" y1=\"{top:.1}\" y2=\"{bottom:.1}\" stroke=\"#f0f1f3\"/>\
                 <text x=\"{px:.1}\" y=\"{:.1}\" text-anchor=\"middle\" fill=\"#444\">{}</text>",
                bottom + 15.0,
                label(t, x_dec)
            );
        }
        let _ = writeln!(
            s,
            "<rect x=\"{LEFT}\" y=\"{top:.1}\" width=\"{plot_w:.1}\" height=\"{PANEL}\" fill=\"none\" stroke=\"#888\"/>"
        );
        // lines and legend
        for (k, (v, ys)) in series.iter().enumerate() {
            let color = COLORS[k % COLORS.len()];
            let mut points = String::new();
            for &i in &idx {
                if ys[i].is_finite() {
                    let _ = write!(points, "{:.1},{:.1} ", sx(run.time[i]), sy(ys[i]));
                }
            }
            let _ = writeln!(
                s,
                "<polyline fill=\"none\" stroke=\"{color}\" stroke-width=\"1.6\" points=\"{}\"/>",
                points.trim_end()
            );
            let ly = top + 12.0 + k as f64 * 17.0;
            let lx = LEFT + plot_w + 12.0;
            let _ = writeln!(
                s,
                "<line x1=\"{lx:.1}\" x2=\"{:.1}\" y1=\"{:.1}\" y2=\"{:.1}\" stroke=\"{color}\" stroke-width=\"2.5\"/>\
                 <text x=\"{:.1}\" y=\"{ly:.1}\">{}</text>",
                lx + 18.0,
                ly - 4.0,
                ly - 4.0,
                lx + 24.0,
                escape(v.name)
            );
        }
    }
    let _ = writeln!(
        s,
        "<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\">time (s)</text>\n</svg>",
        LEFT + plot_w / 2.0,
        height - 6.0
    );
    s
}

/// Round tick values covering [lo, hi] (about five) and the decimals to print them with.
/// Rounding is the `libm` crate's, as everywhere in the library: `f64::floor` and `ceil`
/// are calls of the C library's on x86-64, which a Windows DLL would import from msvcrt.
fn ticks(lo: f64, hi: f64) -> (Vec<f64>, usize) {
    let span = (hi - lo).max(f64::MIN_POSITIVE);
    let raw = span / 5.0;
    let mag = libm::pow(10.0, libm::floor(libm::log10(raw)));
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| span / s <= 6.5)
        .unwrap_or(10.0 * mag);
    let decimals = (-libm::floor(libm::log10(step))).max(0.0) as usize;
    let first = libm::ceil(lo / step) as i64;
    let last = libm::floor(hi / step) as i64;
    let ticks = (first..=last).map(|k| k as f64 * step).collect();
    (ticks, decimals.min(12))
}

fn label(x: f64, decimals: usize) -> String {
    let a = x.abs();
    if a != 0.0 && !(1e-3..1e5).contains(&a) {
        return format!("{x:.1e}");
    }
    let s = format!("{x:.decimals$}");
    if s.trim_start_matches('-')
        .chars()
        .all(|c| c == '0' || c == '.')
    {
        "0".into()
    } else {
        s.replace('-', "\u{2212}")
    }
}
