//! Charts as SVG (plotters): panels of series on log or linear axes, with
//! optional vertical marker lines. SVG needs no font files and opens in any
//! browser.

use crate::error::{err, Result};
use plotters::prelude::*;
use std::path::Path;

/// One line (or scatter) of a panel.
pub struct Series {
    /// Legend text.
    pub name: String,
    /// Points `(x, y)`; non-finite or (on log axes) non-positive ones are skipped.
    pub points: Vec<(f64, f64)>,
    /// Colour index into a fixed palette.
    pub color: usize,
    /// Draw markers only (no line).
    pub markers_only: bool,
}

/// One panel of a chart.
pub struct Panel {
    /// Caption above the panel.
    pub title: String,
    /// Label of the horizontal axis.
    pub x_label: String,
    /// Label of the vertical axis.
    pub y_label: String,
    /// Logarithmic horizontal axis (points with `x <= 0` are skipped).
    pub log_x: bool,
    /// Logarithmic vertical axis (points with `y <= 0` are skipped).
    pub log_y: bool,
    /// The series drawn, in order; the axes span their drawable points
    /// (and the `vlines`).
    pub series: Vec<Series>,
    /// Vertical lines `(x, label)`.
    pub vlines: Vec<(f64, String)>,
}

const PALETTE: [RGBColor; 7] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(127, 127, 127),
    RGBColor(140, 86, 75),
];

fn range(values: impl Iterator<Item = f64>, log: bool) -> Option<(f64, f64)> {
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    for v in values.filter(|v| v.is_finite() && (!log || *v > 0.0)) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return None;
    }
    if log {
        if hi <= lo * 1.0001 {
            return Some((lo / 10.0, hi * 10.0));
        }
        Some((lo / 2.0, hi * 2.0))
    } else {
        let pad = ((hi - lo) * 0.05)
            .max(hi.abs().max(lo.abs()) * 1e-3)
            .max(1e-300);
        Some((lo - pad, hi + pad))
    }
}

fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    p: &Panel,
) -> Result<()>
where
    DB::ErrorType: 'static,
{
    let ok = |x: f64, y: f64| {
        x.is_finite() && y.is_finite() && (!p.log_x || x > 0.0) && (!p.log_y || y > 0.0)
    };
    let xs = p
        .series
        .iter()
        .flat_map(|s| s.points.iter().filter(|(x, y)| ok(*x, *y)).map(|(x, _)| *x))
        .chain(p.vlines.iter().map(|(x, _)| *x));
    let ys = p
        .series
        .iter()
        .flat_map(|s| s.points.iter().filter(|(x, y)| ok(*x, *y)).map(|(_, y)| *y));
    let (Some((x0, x1)), Some((y0, y1))) = (range(xs, p.log_x), range(ys, p.log_y)) else {
        area.titled(&format!("{} (no data)", p.title), ("sans-serif", 16))
            .map_err(|e| err!("plot: {e:?}"))?;
        return Ok(());
    };
    macro_rules! body {
        ($chart:expr) => {{
            let mut chart = $chart;
            chart
                .configure_mesh()
                .x_desc(p.x_label.as_str())
                .y_desc(p.y_label.as_str())
                .x_label_formatter(&|v| format!("{v:.1e}"))
                .y_label_formatter(&|v| format!("{v:.1e}"))
                .draw()
                .map_err(|e| err!("plot: {e:?}"))?;
            for (x, label) in &p.vlines {
                let style = ShapeStyle::from(&BLACK).stroke_width(1);
                chart
                    .draw_series(LineSeries::new(vec![(*x, y0), (*x, y1)], style))
                    .map_err(|e| err!("plot: {e:?}"))?
                    .label(label.as_str())
                    .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK));
            }
            for s in &p.series {
                let c = PALETTE[s.color % PALETTE.len()];
                let pts: Vec<(f64, f64)> = s
                    .points
                    .iter()
                    .copied()
                    .filter(|(x, y)| ok(*x, *y))
                    .collect();
                if !s.markers_only {
                    chart
                        .draw_series(LineSeries::new(pts.clone(), c.stroke_width(2)))
                        .map_err(|e| err!("plot: {e:?}"))?;
                }
                chart
                    .draw_series(pts.iter().map(|&(x, y)| Circle::new((x, y), 3, c.filled())))
                    .map_err(|e| err!("plot: {e:?}"))?
                    .label(s.name.as_str())
                    .legend(move |(x, y)| Circle::new((x + 10, y), 4, c.filled()));
            }
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .position(SeriesLabelPosition::UpperRight)
                .draw()
                .map_err(|e| err!("plot: {e:?}"))?;
        }};
    }
    let mut b = ChartBuilder::on(area);
    b.caption(&p.title, ("sans-serif", 16))
        .margin(10)
        .x_label_area_size(40)
        .y_label_area_size(70);
    match (p.log_x, p.log_y) {
        (true, true) => body!(b
            .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
            .map_err(|e| err!("plot: {e:?}"))?),
        (true, false) => body!(b
            .build_cartesian_2d((x0..x1).log_scale(), y0..y1)
            .map_err(|e| err!("plot: {e:?}"))?),
        (false, true) => body!(b
            .build_cartesian_2d(x0..x1, (y0..y1).log_scale())
            .map_err(|e| err!("plot: {e:?}"))?),
        (false, false) => body!(b
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(|e| err!("plot: {e:?}"))?),
    }
    Ok(())
}

/// Write panels stacked vertically into one SVG file.
pub fn write_svg(path: &Path, panels: &[Panel]) -> Result<()> {
    let height = 360 * panels.len() as u32;
    let root = SVGBackend::new(path, (900, height)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err!("plot: {e:?}"))?;
    let areas = root.split_evenly((panels.len(), 1));
    for (a, p) in areas.iter().zip(panels) {
        draw_panel(a, p)?;
    }
    root.present()
        .map_err(|e| err!("cannot write chart {}: {e:?}", path.display()))
}
