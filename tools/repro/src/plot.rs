//! The probability figures as SVG: one panel per tolerance (or per listed
//! (a, eps) / (d, eps) pair), one curve per `a` or sampler; and T3's
//! comparison figure, the running best of every configuration with the
//! peers' copied figures beside it.
//!
//! Text is written as SVG `<text>` in a generic `sans-serif` family and
//! laid out with plotters' built-in size estimates, so no font file,
//! fontconfig or freetype is needed. No PNG is written: plotters' bitmap
//! backend can only draw text with a font file (its `ab_glyph` feature),
//! and turning that on makes the SVG layout need the font as well.

use std::path::Path;

use plotters::prelude::*;

use crate::compare::paper_mean;
use crate::config::{Method, RunSpec};
use crate::error::ReproError;
use crate::exec::ProtocolResult;
use crate::protocol::SeriesKey;

const PANEL: (u32, u32) = (480, 340);
const COLOURS: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(23, 190, 207),
];

fn series_label(key: SeriesKey, s: &RunSpec) -> String {
    let t = s.temperature;
    match key {
        SeriesKey::Sampler => s.method.label(),
        SeriesKey::Temperature => format!("{} = {}", t.label_name(), t.label_value()),
    }
}

/// Draws the figure of `r` into `path` (SVG).
pub fn figure(r: &ProtocolResult, path: &Path) -> Result<(), ReproError> {
    draw(r, path).map_err(|e| ReproError::Plot {
        path: path.to_path_buf(),
        message: e.to_string(),
    })
}

fn draw(r: &ProtocolResult, path: &Path) -> Result<(), Box<dyn std::error::Error>> {
    let panels = &r.plan.panels;
    let cols = panels.len().clamp(1, 3);
    let rows = panels.len().div_ceil(cols);
    let size = (PANEL.0 * cols as u32, PANEL.1 * rows as u32 + 40);
    let root = SVGBackend::new(path, size).into_drawing_area();
    root.fill(&WHITE)?;
    let root = root.titled(
        &format!(
            "{}: {} (M = {} runs)",
            r.plan.id.name(),
            r.plan.id.title(),
            r.plan.runs
        ),
        ("sans-serif", 22),
    )?;
    let m = r.plan.runs as f64;
    for (panel, area) in panels.iter().zip(root.split_evenly((rows, cols))) {
        let members: Vec<_> = r
            .configs
            .iter()
            .filter(|c| panel.filter.accepts(&c.spec) && c.spec.curve_every.is_some())
            .collect();
        let k_max = members.iter().map(|c| c.spec.steps).max().unwrap_or(1);
        let mut chart = ChartBuilder::on(&area)
            .caption(&panel.title, ("sans-serif", 18))
            .margin(8)
            // Room for the last x tick label ("100000") at the right edge.
            .margin_right(28)
            .x_label_area_size(36)
            .y_label_area_size(48)
            .build_cartesian_2d(0f64..k_max as f64, 0f64..1.02f64)?;
        chart
            .configure_mesh()
            .x_desc("iterate k")
            .y_desc("P(U(x_k) - U* <= eps)")
            .x_labels(6)
            .y_labels(6)
            .x_label_formatter(&|k| format!("{k:.0}"))
            .label_style(("sans-serif", 13))
            .axis_desc_style(("sans-serif", 14))
            .draw()?;
        for (i, c) in members.iter().enumerate() {
            let s = &c.spec;
            let Some(e) = s.eps.iter().position(|&x| x == panel.eps) else {
                continue;
            };
            let colour = COLOURS[i % COLOURS.len()];
            let data = c.curve(e).map(|(k, hits)| (k as f64, f64::from(hits) / m));
            chart
                .draw_series(LineSeries::new(data, colour.stroke_width(2)))?
                .label(series_label(r.plan.series, s))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(2))
                });
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::LowerRight)
            .label_font(("sans-serif", 13))
            .background_style(WHITE.mix(0.6))
            .border_style(BLACK)
            .draw()?;
    }
    root.present()?;
    Ok(())
}

/// Draws T3's comparison into `path` (SVG): one panel per checkpoint, one
/// row per configuration, its mean running best (dot) and mean ± SD (bar)
/// on a log scale, and the paper's copied mean (cross) where there is one.
pub fn comparison_figure(r: &ProtocolResult, path: &Path) -> Result<(), ReproError> {
    draw_comparison(r, path).map_err(|e| ReproError::Plot {
        path: path.to_path_buf(),
        message: e.to_string(),
    })
}

fn draw_comparison(r: &ProtocolResult, path: &Path) -> Result<(), Box<dyn std::error::Error>> {
    let checkpoints: Vec<u64> = r.configs[0].spec.checkpoints.clone();
    let labels: Vec<String> = r.configs.iter().map(|c| c.spec.label()).collect();
    let n = labels.len() as i32;
    // Every mean and copied figure, and the bars' right ends, fit; the
    // bars' left ends are cut at the axis (a log scale has no 0).
    let mut lo = f64::INFINITY;
    let mut hi: f64 = 0.0;
    for c in &r.configs {
        for p in &c.checkpoints {
            let m = &p.summary;
            lo = lo.min(m.mean).min(m.min);
            hi = hi.max(m.mean + m.sd);
            if let Some(v) = paper_mean(&c.spec, p.k) {
                lo = lo.min(v);
                hi = hi.max(v);
            }
        }
    }
    // Padded by a factor 1.5 each way, within the finite floats and at
    // most 300 decades wide (smaller values are cut at the axis like the
    // bars): plotters counts the log scale's decades as `hi / lo`, and an
    // infinite count (a range reaching +inf, or spanning more than the
    // floats' 617 decades) sends its tick loop on without end.
    let (lo, hi) = if lo / 1.5 > 0.0 && hi.is_finite() {
        let hi = (hi * 1.5).min(f64::MAX);
        ((lo / 1.5).max(hi * 1e-300), hi)
    } else {
        (1e-3, 1e3)
    };
    let panels = checkpoints.len().max(1) as u32;
    let size = (520 * panels, 90 + 18 * n as u32);
    let root = SVGBackend::new(path, size).into_drawing_area();
    root.fill(&WHITE)?;
    let root = root.titled(
        &format!(
            "{}: running best, mean (dot) and ± SD (bar) over M = {} runs; x: copied figure",
            r.plan.id.name(),
            r.plan.runs
        ),
        ("sans-serif", 16),
    )?;
    // Row 0 at the top: the first configuration is drawn highest.
    let row = |i: usize| SegmentValue::CenterOf(n - 1 - i as i32);
    let formatter = |v: &SegmentValue<i32>| match v {
        SegmentValue::CenterOf(j) => labels
            .get((n - 1 - *j) as usize)
            .cloned()
            .unwrap_or_default(),
        _ => String::new(),
    };
    for (area, &k) in root
        .split_evenly((1, checkpoints.len()))
        .iter()
        .zip(&checkpoints)
    {
        let mut chart = ChartBuilder::on(area)
            .caption(format!("k = {k}"), ("sans-serif", 15))
            .margin(8)
            .margin_right(16)
            .x_label_area_size(36)
            .y_label_area_size(230)
            .build_cartesian_2d((lo..hi).log_scale(), (0..n).into_segmented())?;
        chart
            .configure_mesh()
            .disable_y_mesh()
            .y_labels(n as usize)
            .y_label_formatter(&formatter)
            .x_desc("running best (log scale)")
            .label_style(("sans-serif", 11))
            .axis_desc_style(("sans-serif", 12))
            .draw()?;
        for (i, c) in r.configs.iter().enumerate() {
            let Some(p) = c.checkpoints.iter().find(|p| p.k == k) else {
                continue;
            };
            let colour = match c.spec.method {
                Method::Kernel(_) => COLOURS[0],
                Method::Peer { .. } => COLOURS[1],
            };
            let m = &p.summary;
            let left = (m.mean - m.sd).max(lo);
            chart.draw_series(std::iter::once(PathElement::new(
                vec![(left, row(i)), (m.mean + m.sd, row(i))],
                colour.stroke_width(2),
            )))?;
            chart.draw_series(std::iter::once(Circle::new(
                (m.mean, row(i)),
                4,
                colour.filled(),
            )))?;
            if let Some(v) = paper_mean(&c.spec, k) {
                chart.draw_series(std::iter::once(Cross::new(
                    (v, row(i)),
                    5,
                    BLACK.stroke_width(2),
                )))?;
            }
        }
    }
    root.present()?;
    Ok(())
}
