//! The probability figures as SVG: one panel per tolerance (or per listed
//! (a, eps) / (d, eps) pair), one curve per `a` or sampler.
//!
//! Text is written as SVG `<text>` in a generic `sans-serif` family and
//! laid out with plotters' built-in size estimates, so no font file,
//! fontconfig or freetype is needed. No PNG is written: plotters' bitmap
//! backend can only draw text with a font file (its `ab_glyph` feature),
//! and turning that on makes the SVG layout need the font as well.

use std::path::Path;

use plotters::prelude::*;

use crate::config::{RunSpec, sampler_label};
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
        SeriesKey::Sampler => sampler_label(s.sampler),
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
