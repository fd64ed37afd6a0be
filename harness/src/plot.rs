//! The harness's one plot engine, SVG text: the Pareto view of a scene (error against frame
//! time) and a sweep's figures against the swept value, inlined in the report and written as
//! files ([`file`]: `pareto/<scene>.svg`, `sweep.svg`). Hand-written, because the viewer (a
//! browser, a vector editor) lays out SVG text itself, so drawing needs no font and no system
//! library; each point carries a `<title>` the browser shows on hover.

use crate::pareto::{ParetoScene, YARDSTICK};
use std::fmt::Write as _;

/// The plots' style: the report's stylesheet includes it, and every SVG file carries it.
pub const PLOT_STYLE: &str = "\
svg.plot { font: 11px system-ui, sans-serif; }
svg.plot .area { fill: #fff; stroke: #999; }
svg.plot .grid { stroke: #e6e6e6; }
svg.plot .tick { fill: #555; }
svg.plot .label { fill: #222; font-size: 12px; }
svg.plot .title { fill: #222; font-size: 13px; font-weight: 600; }
svg.plot .category { fill: #555; font-size: 10px; }
svg.plot .point circle { fill: #888; stroke: #fff; }
svg.plot .point text { fill: #444; font-size: 10px; }
svg.plot .point.on-front circle { fill: #c8282a; }
svg.plot .point.tracer circle { fill: #2850c8; }
svg.plot .front { fill: none; stroke: #c8282a; stroke-width: 1.5; stroke-dasharray: 4 3; }
svg.plot .series { fill: none; stroke: #1f5fbf; stroke-width: 1.5; }
svg.plot .point:hover circle { stroke: #000; stroke-width: 2; }
svg.plot .legend { fill: #222; font-size: 11px; }
";

const WIDTH: f64 = 640.0;
const HEIGHT: f64 = 360.0;
/// Plot area inside the SVG: left, top, right, bottom.
const AREA: (f64, f64, f64, f64) = (70.0, 30.0, 620.0, 310.0);

/// Escapes text for XML (content and attribute values).
pub fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// A number as a label: up to four significant figures, no trailing zeros.
pub fn short(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let magnitude = v.abs().log10().floor() as i32;
    if !(-4..6).contains(&magnitude) {
        return format!("{v:.3e}");
    }
    let decimals = (3 - magnitude).max(0) as usize;
    let text = format!("{v:.decimals$}");
    match text.contains('.') {
        true => text.trim_end_matches('0').trim_end_matches('.').to_string(),
        false => text,
    }
}

/// One axis: a data range mapped onto a pixel range, linear or logarithmic.
#[derive(Clone, Copy, Debug)]
struct Scale {
    lo: f64,
    hi: f64,
    log: bool,
    px: (f64, f64),
}

impl Scale {
    /// A linear axis from 0 (or the lowest value, if negative) to a little above the highest.
    fn linear_from_zero(values: impl Iterator<Item = f64>, px: (f64, f64)) -> Self {
        let (lo, hi) = values
            .filter(|v| v.is_finite())
            .fold((0.0f64, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
        let hi = if hi > lo { hi * 1.1 } else { lo + 1.0 };
        Scale {
            lo,
            hi,
            log: false,
            px,
        }
    }

    /// A linear axis over the values with 5 % room at both ends.
    fn linear(values: impl Iterator<Item = f64>, px: (f64, f64)) -> Self {
        let (lo, hi) = values
            .filter(|v| v.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                (a.min(v), b.max(v))
            });
        let (lo, hi) = match (lo.is_finite(), hi > lo) {
            (false, _) => (0.0, 1.0),
            (true, false) => (lo - 0.5, lo + 0.5),
            (true, true) => (lo - 0.05 * (hi - lo), hi + 0.05 * (hi - lo)),
        };
        Scale {
            lo,
            hi,
            log: false,
            px,
        }
    }

    /// A log axis over the positive values, half a factor of two of room at both ends.
    fn log(values: impl Iterator<Item = f64>, px: (f64, f64)) -> Self {
        let (lo, hi) = values
            .filter(|v| v.is_finite() && *v > 0.0)
            .fold((f64::INFINITY, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
        let (lo, hi) = if lo.is_finite() {
            (lo / 1.5, hi * 1.5)
        } else {
            (0.1, 10.0)
        };
        Scale {
            lo,
            hi,
            log: true,
            px,
        }
    }

    fn at(&self, v: f64) -> f64 {
        let t = if self.log {
            (v.max(self.lo).ln() - self.lo.ln()) / (self.hi.ln() - self.lo.ln())
        } else {
            (v - self.lo) / (self.hi - self.lo)
        };
        self.px.0 + t.clamp(-0.02, 1.02) * (self.px.1 - self.px.0)
    }

    /// Tick values: 1-2-5 steps (about six) on a linear axis, 1-2-5 of each decade on a log
    /// axis (powers of ten only when it spans more than two decades).
    fn ticks(&self) -> Vec<f64> {
        if self.log {
            let decades = (self.hi / self.lo).log10();
            let mantissas: &[f64] = if decades > 2.0 {
                &[1.0]
            } else {
                &[1.0, 2.0, 5.0]
            };
            let first = self.lo.log10().floor() as i32;
            let last = self.hi.log10().ceil() as i32;
            return (first..=last)
                .flat_map(|e| mantissas.iter().map(move |m| m * 10f64.powi(e)))
                .filter(|v| *v >= self.lo && *v <= self.hi)
                .collect();
        }
        let raw = (self.hi - self.lo) / 6.0;
        let magnitude = 10f64.powf(raw.log10().floor());
        let step = [1.0, 2.0, 5.0, 10.0]
            .iter()
            .map(|m| m * magnitude)
            .find(|s| *s >= raw)
            .unwrap_or(raw);
        let first = (self.lo / step).ceil() as i64;
        let last = (self.hi / step).floor() as i64;
        (first..=last).map(|i| i as f64 * step).collect()
    }
}

/// The frame of a chart: background, grid, ticks, axis labels, title.
fn frame(out: &mut String, title: &str, x: &Scale, y: &Scale, x_label: &str, y_label: &str) {
    let (l, t, r, b) = AREA;
    let _ = write!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" class="plot" viewBox="0 0 {WIDTH} {HEIGHT}" role="img"><title>{}</title><rect x="{l}" y="{t}" width="{}" height="{}" class="area"/>"#,
        escape(title),
        r - l,
        b - t
    );
    for v in x.ticks() {
        let px = x.at(v);
        let _ = write!(
            out,
            r#"<line x1="{px:.1}" y1="{t}" x2="{px:.1}" y2="{b}" class="grid"/><text x="{px:.1}" y="{}" class="tick" text-anchor="middle">{}</text>"#,
            b + 16.0,
            short(v)
        );
    }
    for v in y.ticks() {
        let py = y.at(v);
        let _ = write!(
            out,
            r#"<line x1="{l}" y1="{py:.1}" x2="{r}" y2="{py:.1}" class="grid"/><text x="{}" y="{:.1}" class="tick" text-anchor="end">{}</text>"#,
            l - 6.0,
            py + 4.0,
            short(v)
        );
    }
    let _ = write!(
        out,
        r#"<text x="{}" y="{}" class="label" text-anchor="middle">{}</text><text x="16" y="{}" class="label" text-anchor="middle" transform="rotate(-90 16 {})">{}</text><text x="{l}" y="18" class="title">{}</text>"#,
        (l + r) / 2.0,
        HEIGHT - 12.0,
        escape(x_label),
        (t + b) / 2.0,
        (t + b) / 2.0,
        escape(y_label),
        escape(title)
    );
}

/// The Pareto view of one scene: one numbered point per technique (the numbers of
/// `scene.points`' order, fastest first in the legend beside it), the front as a red
/// staircase, the exact tracer in blue at error 0. None without points.
pub fn pareto(scene: &ParetoScene) -> Option<String> {
    if scene.points.is_empty() {
        return None;
    }
    let (l, t, r, b) = AREA;
    let x = Scale::log(scene.points.iter().map(|p| p.frame_ms), (l, r));
    let y = Scale::linear_from_zero(scene.points.iter().map(|p| p.error), (b, t));
    let mut out = String::new();
    let y_label = match scene.error_metric.as_str() {
        "flip_mean_masked" => "FLIP over the mask (mean along the path)",
        _ => "FLIP (mean along the path)",
    };
    frame(
        &mut out,
        &format!("{}: error against frame time", scene.scene),
        &x,
        &y,
        "frame time, ms (median, log scale)",
        y_label,
    );
    let mut front: Vec<&crate::pareto::ParetoPoint> =
        scene.points.iter().filter(|p| p.on_front).collect();
    front.sort_by(|a, b| a.frame_ms.total_cmp(&b.frame_ms));
    if !front.is_empty() {
        // Staircase: from each front point across to the next one's time, then down to it.
        let mut d = format!(
            "M{:.1} {:.1}",
            x.at(front[0].frame_ms),
            y.at(front[0].error)
        );
        for pair in front.windows(2) {
            let (px, py) = (x.at(pair[1].frame_ms), y.at(pair[1].error));
            let _ = write!(d, " H{px:.1} V{py:.1}");
        }
        let _ = write!(out, r#"<path d="{d}" class="front"/>"#);
    }
    for (i, p) in scene.points.iter().enumerate() {
        let class = match (p.technique == YARDSTICK, p.on_front) {
            (true, _) => "point tracer",
            (false, true) => "point on-front",
            (false, false) => "point",
        };
        let (px, py) = (x.at(p.frame_ms), y.at(p.error));
        let _ = write!(
            out,
            r#"<g class="{class}" data-technique="{}"><title>{}: {} ms, error {}{}</title><circle cx="{px:.1}" cy="{py:.1}" r="5"/><text x="{:.1}" y="{:.1}">{}</text></g>"#,
            escape(&p.technique),
            escape(&p.technique),
            short(p.frame_ms),
            short(p.measured_error),
            if p.on_front { " (on the front)" } else { "" },
            px + 7.0,
            py - 6.0,
            i + 1
        );
    }
    out.push_str("</svg>");
    Some(out)
}

/// One figure of a sweep against the swept value: numeric values on a linear axis, other values
/// in order as categories. None when no value has the figure.
pub fn sweep(
    title: &str,
    param: &str,
    figure: &str,
    points: &[(String, Option<f64>)],
) -> Option<String> {
    let numeric: Option<Vec<f64>> = points
        .iter()
        .map(|(v, _)| v.parse::<f64>().ok().filter(|v| v.is_finite()))
        .collect();
    let xs: Vec<f64> = numeric
        .clone()
        .unwrap_or_else(|| (0..points.len()).map(|i| i as f64).collect());
    let drawn: Vec<(usize, f64, f64)> = points
        .iter()
        .enumerate()
        .filter_map(|(i, (_, y))| y.filter(|y| y.is_finite()).map(|y| (i, xs[i], y)))
        .collect();
    if drawn.is_empty() {
        return None;
    }
    let (l, t, r, b) = AREA;
    let x = Scale::linear(xs.iter().copied(), (l, r));
    let y = Scale::linear_from_zero(drawn.iter().map(|d| d.2), (b, t));
    let mut out = String::new();
    frame(&mut out, title, &x, &y, param, figure);
    if numeric.is_none() {
        // Category names replace the numeric ticks' meaning: label each value under its point.
        for (i, (value, _)) in points.iter().enumerate() {
            let _ = write!(
                out,
                r#"<text x="{:.1}" y="{}" class="category" text-anchor="middle">{}</text>"#,
                x.at(xs[i]),
                b - 6.0,
                escape(value)
            );
        }
    }
    let mut order = drawn.clone();
    order.sort_by(|a, b| a.1.total_cmp(&b.1));
    let d: Vec<String> = order
        .iter()
        .enumerate()
        .map(|(k, (_, vx, vy))| {
            let cmd = if k == 0 { 'M' } else { 'L' };
            format!("{cmd}{:.1} {:.1}", x.at(*vx), y.at(*vy))
        })
        .collect();
    let _ = write!(out, r#"<path d="{}" class="series"/>"#, d.join(" "));
    for (i, vx, vy) in drawn {
        let _ = write!(
            out,
            r#"<g class="point"><title>{} = {}: {}</title><circle cx="{:.1}" cy="{:.1}" r="4"/></g>"#,
            escape(param),
            escape(&points[i].0),
            short(vy),
            x.at(vx),
            y.at(vy)
        );
    }
    out.push_str("</svg>");
    Some(out)
}

/// An SVG file of `figures` (each one of this module's plots) one under the other, then
/// `legend`, one line each: what `sweep.svg` and `pareto/<scene>.svg` hold, readable in any
/// browser or vector editor without the report (the style inside, text laid out by the viewer).
pub fn file(figures: &[String], legend: &[String]) -> String {
    let line = 16.0;
    let legend_height = if legend.is_empty() {
        0.0
    } else {
        line * legend.len() as f64 + 12.0
    };
    let height = HEIGHT * figures.len() as f64 + legend_height;
    let mut out = format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" class=\"plot\" width=\"{WIDTH}\" height=\"{height}\" viewBox=\"0 0 {WIDTH} {height}\"><style>{PLOT_STYLE}</style><rect width=\"{WIDTH}\" height=\"{height}\" fill=\"#fff\"/>"
    );
    for (i, figure) in figures.iter().enumerate() {
        // Each figure is an <svg> of its own, placed at its slot.
        let placed = figure.replacen(
            "<svg ",
            &format!(
                r#"<svg y="{}" width="{WIDTH}" height="{HEIGHT}" "#,
                HEIGHT * i as f64
            ),
            1,
        );
        out.push_str(&placed);
    }
    let top = HEIGHT * figures.len() as f64;
    for (i, text) in legend.iter().enumerate() {
        let _ = write!(
            out,
            r#"<text x="{}" y="{:.1}" class="legend">{}</text>"#,
            AREA.0,
            top + line * (i as f64 + 1.0),
            escape(text)
        );
    }
    out.push_str("</svg>\n");
    out
}

/// The Pareto view's legend lines for [`file`]: each point's number, technique, time and error.
pub fn pareto_legend(scene: &ParetoScene) -> Vec<String> {
    scene
        .points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let front = if p.on_front { ", on the front" } else { "" };
            format!(
                "{} {}: {} ms, error {}{front}",
                i + 1,
                p.technique,
                short(p.frame_ms),
                short(p.measured_error)
            )
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pareto::ParetoPoint;

    #[test]
    fn short_numbers_read_like_a_paper() {
        assert_eq!(short(0.0), "0");
        assert_eq!(short(0.012346), "0.01235");
        assert_eq!(short(12.5), "12.5");
        assert_eq!(short(1000.0), "1000");
        assert_eq!(short(2.0e-7), "2.000e-7");
        assert_eq!(short(f64::INFINITY), "inf");
    }

    #[test]
    fn ticks_are_round_and_inside_the_axis() {
        let s = Scale::linear_from_zero([0.37].into_iter(), (0.0, 100.0));
        let ticks = s.ticks();
        assert_eq!(ticks.first(), Some(&0.0));
        assert!(
            ticks.len() >= 4 && ticks.iter().all(|v| *v <= s.hi),
            "{ticks:?}"
        );
        let s = Scale::log([0.5, 3000.0].into_iter(), (0.0, 100.0));
        assert_eq!(s.ticks(), vec![1.0, 10.0, 100.0, 1000.0]);
        assert!(s.at(0.5) < s.at(3000.0));
        let s = Scale::log([2.0, 30.0].into_iter(), (0.0, 100.0));
        assert_eq!(s.ticks(), vec![2.0, 5.0, 10.0, 20.0]);
    }

    #[test]
    fn pareto_svg_has_every_point_the_front_and_escaped_names() {
        let point = |technique: &str, frame_ms, error, on_front| ParetoPoint {
            technique: technique.into(),
            frame_ms,
            error,
            measured_error: error,
            on_front,
        };
        let scene = ParetoScene {
            scene: "a<b".into(),
            error_metric: "flip_mean_masked".into(),
            yardstick_ms: Some(100.0),
            points: vec![
                point(YARDSTICK, 100.0, 0.0, true),
                point("fast/one", 1.0, 0.2, true),
                point("slow/bad", 10.0, 0.3, false),
            ],
            plot: None,
        };
        let svg = pareto(&scene).unwrap();
        assert!(svg.starts_with("<svg") && svg.ends_with("</svg>"));
        assert_eq!(svg.matches("<circle").count(), 3);
        assert_eq!(svg.matches(r#"class="front""#).count(), 1);
        assert!(svg.contains("a&lt;b") && !svg.contains("a<b"));
        assert!(svg.contains(r#"class="point tracer""#));
        let empty = ParetoScene {
            points: Vec::new(),
            ..scene
        };
        assert!(pareto(&empty).is_none());
    }

    #[test]
    fn sweep_svg_draws_numeric_and_categorical_values() {
        let numeric = [("8".to_string(), Some(0.3)), ("32".into(), Some(0.1))];
        let svg = sweep("t", "resolution", "FLIP", &numeric).unwrap();
        assert_eq!(svg.matches("<circle").count(), 2);
        assert!(!svg.contains(r#"class="category""#));
        let named = [
            ("glass".to_string(), Some(0.3)),
            ("gold".into(), None),
            ("mirror".into(), Some(f64::NAN)),
        ];
        let svg = sweep("t", "material", "FLIP", &named).unwrap();
        assert_eq!(
            svg.matches("<circle").count(),
            1,
            "missing and NaN values are not drawn"
        );
        assert_eq!(svg.matches(r#"class="category""#).count(), 3);
        assert!(sweep("t", "m", "FLIP", &[("a".into(), None)]).is_none());
    }
}
