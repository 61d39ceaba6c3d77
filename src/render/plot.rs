//! The time-against-error plot of `tetkit tradeoff`, drawn with plotters.
//!
//! Text needs a font: plotters' ab_glyph backend takes font bytes, which are read at run time
//! from the usual system locations (DejaVu, Liberation, FreeFont; `.ci/run` installs
//! fonts-dejavu-core). Without one the plot is still drawn (points, grid, axes, colours per
//! sort) but without text, and the caller says so; the numbers are in the table either way.

// Negated comparisons are deliberate: they also catch NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use anyhow::{anyhow, Result};
use plotters::prelude::*;
use std::path::Path;
use std::sync::OnceLock;

/// One combination on the plot.
#[derive(Clone, Debug)]
pub struct PlotPoint {
    /// Series (colour and legend entry), e.g. the sort.
    pub series: String,
    /// Text beside the point, e.g. the integration mode.
    pub label: String,
    pub seconds: f64,
    pub error: f64,
}

const FONT_PATHS: &[&str] = &[
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/truetype/liberation/LiberationSans-Regular.ttf",
    "/usr/share/fonts/liberation/LiberationSans-Regular.ttf",
    "/usr/share/fonts/truetype/freefont/FreeSans.ttf",
    "/Library/Fonts/Arial.ttf",
    "/System/Library/Fonts/Supplemental/Arial.ttf",
    "C:\\Windows\\Fonts\\arial.ttf",
];

/// Registers a system font as "sans-serif" once; whether text can be drawn.
pub fn font_available() -> bool {
    static FONT: OnceLock<bool> = OnceLock::new();
    *FONT.get_or_init(|| {
        let paths = std::env::var("TETKIT_FONT")
            .ok()
            .into_iter()
            .chain(FONT_PATHS.iter().map(|s| s.to_string()));
        for p in paths {
            if let Ok(bytes) = std::fs::read(&p) {
                let leaked: &'static [u8] = Box::leak(bytes.into_boxed_slice());
                if plotters::style::register_font("sans-serif", FontStyle::Normal, leaked).is_ok() {
                    return true;
                }
            }
        }
        false
    })
}

const COLORS: [RGBColor; 6] = [
    RGBColor(200, 60, 50),
    RGBColor(230, 150, 30),
    RGBColor(60, 130, 200),
    RGBColor(40, 160, 80),
    RGBColor(140, 80, 180),
    RGBColor(90, 90, 90),
];

/// Log-log scatter of time per frame against error, one labelled point per combination.
pub fn tradeoff_plot(
    path: &Path,
    points: &[PlotPoint],
    title: &str,
    x_label: &str,
    y_label: &str,
) -> Result<bool> {
    let text = font_available();
    let pos: Vec<&PlotPoint> = points
        .iter()
        .filter(|p| p.seconds > 0.0 && p.error.is_finite())
        .collect();
    let (mut x0, mut x1) = (f64::INFINITY, 0.0f64);
    let (mut y0, mut y1) = (f64::INFINITY, 0.0f64);
    for p in &pos {
        x0 = x0.min(p.seconds);
        x1 = x1.max(p.seconds);
        let e = p.error.max(1e-6);
        y0 = y0.min(e);
        y1 = y1.max(e);
    }
    if pos.is_empty() {
        (x0, x1, y0, y1) = (1e-3, 1.0, 1e-4, 1.0);
    }
    let (x0, x1) = (x0 / 1.6, x1 * 1.6);
    let (y0, y1) = (y0 / 2.0, y1 * 2.0);
    let mut series: Vec<String> = Vec::new();
    for p in &pos {
        if !series.contains(&p.series) {
            series.push(p.series.clone());
        }
    }
    let tmp = path.with_extension("tmp-plot.png");
    {
        let root = BitMapBackend::new(&tmp, (900, 600)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| anyhow!("plot: {e}"))?;
        let mut builder = ChartBuilder::on(&root);
        builder.margin(20);
        if text {
            builder
                .caption(title, ("sans-serif", 22))
                .x_label_area_size(50)
                .y_label_area_size(70);
        } else {
            builder.x_label_area_size(10).y_label_area_size(10);
        }
        let mut chart = builder
            .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
            .map_err(|e| anyhow!("plot: {e}"))?;
        let mut mesh = chart.configure_mesh();
        if text {
            mesh.x_desc(x_label)
                .y_desc(y_label)
                .x_label_formatter(&|v| format!("{v:.3}"))
                .y_label_formatter(&|v| format!("{v:.0e}"));
        } else {
            mesh.disable_x_axis().disable_y_axis();
        }
        mesh.draw().map_err(|e| anyhow!("plot: {e}"))?;
        for (si, s) in series.iter().enumerate() {
            let color = COLORS[si % COLORS.len()];
            let pts: Vec<(f64, f64)> = pos
                .iter()
                .filter(|p| &p.series == s)
                .map(|p| (p.seconds, p.error.max(1e-6)))
                .collect();
            let drawn = chart
                .draw_series(
                    pts.iter()
                        .map(|&(x, y)| Circle::new((x, y), 6, color.filled())),
                )
                .map_err(|e| anyhow!("plot: {e}"))?;
            if text {
                drawn
                    .label(s.clone())
                    .legend(move |(x, y)| Circle::new((x + 10, y), 6, color.filled()));
            }
        }
        if text {
            chart
                .draw_series(pos.iter().map(|p| {
                    Text::new(
                        format!(" {}", p.label),
                        (p.seconds, p.error.max(1e-6)),
                        ("sans-serif", 14).into_font(),
                    )
                }))
                .map_err(|e| anyhow!("plot: {e}"))?;
            chart
                .configure_series_labels()
                .border_style(BLACK)
                .background_style(WHITE.mix(0.9))
                .position(SeriesLabelPosition::UpperRight)
                .draw()
                .map_err(|e| anyhow!("plot: {e}"))?;
        }
        root.present().map_err(|e| anyhow!("plot: {e}"))?;
    }
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        anyhow!("{}: writing: {e}", path.display())
    })?;
    Ok(text)
}
