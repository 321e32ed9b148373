//! Drawing with plotters, on either backend.

use std::sync::OnceLock;

use plotters::coord::ranged1d::{BoldPoints, ValueFormatter};
use plotters::coord::Shift;
use plotters::element::{Drawable, PointCollection};
use plotters::prelude::*;
use plotters_backend::{BackendCoord, DrawingErrorKind};

use crate::axes::{LinearAxis, LogAxis};
use crate::geometry::{bar_width, legend_corner, tick_digits, tick_label, Corner, Frame};
use crate::{Figure, Series, SeriesKind, FIGURE_SIZE, PALETTE};

/// DejaVu Sans (Bitstream Vera licence, see `assets/DejaVuSans-LICENSE.txt`).
static FONT: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");

/// The family the font is registered under; the SVG names it too, so
/// viewers fall back to their own sans-serif font.
const FAMILY: &str = "sans-serif";

// Text sizes in pixels. Keep them even: plotters' ab_glyph renderer places
// each glyph at `size / 2 + top` truncated to an integer, so with an odd size
// letters of different heights land on baselines a pixel apart.
const TITLE_SIZE: f64 = 30.0;
const AXIS_LABEL_SIZE: f64 = 22.0;
const TICK_SIZE: f64 = 18.0;
const LEGEND_SIZE: f64 = 18.0;
const MARKER_RADIUS: u32 = 4;
/// Most labelled ticks on each axis.
const X_LABELS: usize = 10;
const Y_LABELS: usize = 10;
const CAP_HALF_WIDTH: i32 = 5;

/// Registers the embedded font with plotters, once.
fn ensure_font() -> Result<(), String> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED
        .get_or_init(|| plotters::style::register_font(FAMILY, FontStyle::Normal, FONT).is_ok());
    if ok {
        Ok(())
    } else {
        Err("the embedded font could not be loaded".to_owned())
    }
}

/// The figure as an SVG document.
pub(crate) fn svg(fig: &Figure) -> Result<String, String> {
    ensure_font()?;
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, FIGURE_SIZE).into_drawing_area();
        draw(&root, fig).map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(out)
}

/// The figure as PNG bytes.
pub(crate) fn png(fig: &Figure) -> Result<Vec<u8>, String> {
    ensure_font()?;
    let (w, h) = FIGURE_SIZE;
    let mut rgb = vec![255u8; w as usize * h as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, FIGURE_SIZE).into_drawing_area();
        draw(&root, fig).map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    let mut out = Vec::new();
    let mut encoder = png::Encoder::new(&mut out, w, h);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_compression(png::Compression::Balanced);
    let mut writer = encoder.write_header().map_err(|e| e.to_string())?;
    writer.write_image_data(&rgb).map_err(|e| e.to_string())?;
    writer.finish().map_err(|e| e.to_string())?;
    Ok(out)
}

type DrawResult<DB> = Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

fn draw<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, fig: &Figure) -> DrawResult<DB> {
    root.fill(&WHITE)?;
    let frame = Frame::of(fig);
    let (y0, y1) = frame.y;
    if frame.log_y {
        draw_chart(root, fig, &frame, LogAxis::new(y0, y1))
    } else {
        draw_chart(root, fig, &frame, LinearAxis::new(y0, y1))
    }
}

fn font(size: f64) -> TextStyle<'static> {
    (FAMILY, size).into_font().color(&BLACK)
}

fn draw_chart<DB, Y>(
    root: &DrawingArea<DB, Shift>,
    fig: &Figure,
    frame: &Frame,
    y_coord: Y,
) -> DrawResult<DB>
where
    DB: DrawingBackend,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let (x0, x1) = frame.x;
    // Enough digits to tell the labelled ticks apart, and room on the left
    // for the widest y label, the gap and the rotated axis label.
    let x_axis = LinearAxis::new(x0, x1);
    let x_digits = tick_digits(&x_axis.key_points(BoldPoints(X_LABELS)));
    let y_ticks = y_coord.key_points(BoldPoints(Y_LABELS));
    let y_digits = tick_digits(&y_ticks);
    let tick_font = (FAMILY, TICK_SIZE).into_font();
    let widest = y_ticks
        .iter()
        .filter_map(|v| tick_font.box_size(&tick_label(*v, y_digits)).ok())
        .map(|(w, _)| w)
        .max()
        .unwrap_or(0);
    let y_area = (widest + 20 + (AXIS_LABEL_SIZE * 1.8) as u32).max(70);
    let mut chart = ChartBuilder::on(root)
        .caption(&fig.title, font(TITLE_SIZE))
        .margin_top(10)
        .margin_left(15)
        .margin_right(30)
        .margin_bottom(15)
        .x_label_area_size(70)
        .y_label_area_size(y_area)
        .build_cartesian_2d(x_axis, y_coord)?;

    let x_fmt = |v: &f64| tick_label(*v, x_digits);
    let y_fmt = |v: &f64| tick_label(*v, y_digits);
    chart
        .configure_mesh()
        .x_desc(fig.x_label.as_str())
        .y_desc(fig.y_label.as_str())
        .axis_desc_style(font(AXIS_LABEL_SIZE))
        .label_style(font(TICK_SIZE))
        .x_label_formatter(&x_fmt)
        .y_label_formatter(&y_fmt)
        .x_labels(X_LABELS)
        .y_labels(Y_LABELS)
        .bold_line_style(BLACK.mix(0.12))
        .light_line_style(BLACK.mix(0.04))
        .axis_style(BLACK)
        .draw()?;

    for (index, series) in fig.series.iter().enumerate() {
        let [r, g, b] = series.colour.unwrap_or(PALETTE[index % PALETTE.len()]);
        let colour = RGBColor(r, g, b);
        draw_series(&mut chart, series, frame, colour)?;
    }

    if fig.series.len() > 1 && fig.series.iter().any(|s| !s.label.is_empty()) {
        let position = match legend_corner(fig, frame) {
            Corner::UpperRight => SeriesLabelPosition::UpperRight,
            Corner::UpperLeft => SeriesLabelPosition::UpperLeft,
            Corner::LowerRight => SeriesLabelPosition::LowerRight,
            Corner::LowerLeft => SeriesLabelPosition::LowerLeft,
        };
        chart
            .configure_series_labels()
            .position(position)
            .margin(12)
            .legend_area_size(30)
            .label_font(font(LEGEND_SIZE))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.4))
            .draw()?;
    }
    Ok(())
}

fn draw_series<'a, DB, Y>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<LinearAxis, Y>>,
    series: &Series,
    frame: &Frame,
    colour: RGBColor,
) -> DrawResult<DB>
where
    DB: DrawingBackend + 'a,
    Y: Ranged<ValueType = f64>,
{
    let line = colour.stroke_width(2);
    let thin = colour.stroke_width(1);
    let filled = colour.filled();
    let label = series.label.clone();
    let inside: Vec<(f64, f64)> = series
        .points
        .iter()
        .copied()
        .filter(|&p| frame.contains(p))
        .collect();

    // Each kind draws its shapes, then returns the annotation of the part
    // that carries the legend entry.
    let anno = match &series.kind {
        SeriesKind::Line => {
            let runs = frame.clip_polyline(&series.points);
            let anno =
                chart.draw_series(runs.into_iter().map(|run| PathElement::new(run, line)))?;
            Some((anno, GlyphKind::LegendLine))
        }
        SeriesKind::Points => {
            let anno = chart.draw_series(
                inside
                    .iter()
                    .map(|&p| Circle::new(p, MARKER_RADIUS, filled)),
            )?;
            Some((anno, GlyphKind::LegendMarker))
        }
        SeriesKind::Bars => {
            let half = 0.5 * bar_width(&series.points, frame.log_y);
            let base = if frame.log_y {
                frame.y.0
            } else {
                frame.clamp_y(0.0)
            };
            let fill = colour.mix(0.55).filled();
            let bars: Vec<[(f64, f64); 2]> = series
                .points
                .iter()
                .filter(|&&p| frame.valid(p))
                .filter_map(|&(x, h)| {
                    let l = (x - half).max(frame.x.0);
                    let r = (x + half).min(frame.x.1);
                    let top = frame.clamp_y(h);
                    (l < r && top != base).then_some([(l, base), (r, top)])
                })
                .collect();
            chart.draw_series(bars.iter().map(|&c| Rectangle::new(c, fill)))?;
            let anno = chart.draw_series(bars.iter().map(|&c| Rectangle::new(c, thin)))?;
            Some((anno, GlyphKind::LegendBar))
        }
        SeriesKind::ErrorBars(errors) => {
            let mut stems = Vec::new();
            let mut caps = Vec::new();
            for (i, &(x, y)) in series.points.iter().enumerate() {
                let Some(e) = errors.get(i).map(|e| e.abs()).filter(|e| e.is_finite()) else {
                    continue;
                };
                if !frame.contains((x, y)) || e == 0.0 {
                    continue;
                }
                let (lo, hi) = (frame.clamp_y(y - e), frame.clamp_y(y + e));
                stems.push([(x, lo), (x, hi)]);
                for (end, cut) in [(y - e, lo), (y + e, hi)] {
                    // No cap where the bar leaves the plot.
                    if end == cut {
                        caps.push((x, end));
                    }
                }
            }
            chart.draw_series(stems.into_iter().map(|s| PathElement::new(s, thin)))?;
            chart.draw_series(caps.into_iter().map(|at| Glyph {
                at,
                kind: GlyphKind::Cap,
                colour,
            }))?;
            let anno = chart.draw_series(
                inside
                    .iter()
                    .map(|&p| Circle::new(p, MARKER_RADIUS, filled)),
            )?;
            Some((anno, GlyphKind::LegendErrorBar))
        }
    };

    if let Some((anno, glyph)) = anno {
        if !label.is_empty() {
            anno.label(label).legend(move |at| Glyph {
                at,
                kind: glyph,
                colour,
            });
        }
    }
    Ok(())
}

/// A small picture drawn around one point, in pixels: an error bar's cap,
/// or the icon of a legend entry (whose anchor is the entry's left end).
///
/// A type of our own rather than a composition of plotters elements:
/// plotters' composed elements are generic over the backend, and its legend
/// then demands a `'static` backend, which the in-memory backends are not.
struct Glyph<C> {
    at: C,
    kind: GlyphKind,
    colour: RGBColor,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum GlyphKind {
    Cap,
    LegendLine,
    LegendMarker,
    LegendBar,
    LegendErrorBar,
}

impl<'a, C: 'a> PointCollection<'a, C> for &'a Glyph<C> {
    type Point = &'a C;
    type IntoIter = std::iter::Once<&'a C>;
    fn point_iter(self) -> Self::IntoIter {
        std::iter::once(&self.at)
    }
}

impl<C, DB: DrawingBackend> Drawable<DB> for Glyph<C> {
    fn draw<I: Iterator<Item = BackendCoord>>(
        &self,
        mut pos: I,
        backend: &mut DB,
        _parent_dim: (u32, u32),
    ) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
        let Some((x, y)) = pos.next() else {
            return Ok(());
        };
        let c = self.colour;
        let thin = c.stroke_width(1);
        let cap = CAP_HALF_WIDTH;
        match self.kind {
            GlyphKind::Cap => backend.draw_line((x - cap, y), (x + cap, y), &thin),
            GlyphKind::LegendLine => backend.draw_line((x, y), (x + 20, y), &c.stroke_width(2)),
            GlyphKind::LegendMarker => {
                backend.draw_circle((x + 10, y), MARKER_RADIUS, &c.filled(), true)
            }
            GlyphKind::LegendBar => {
                backend.draw_rect((x, y - 6), (x + 20, y + 6), &c.mix(0.55).filled(), true)?;
                backend.draw_rect((x, y - 6), (x + 20, y + 6), &thin, false)
            }
            GlyphKind::LegendErrorBar => {
                let m = x + 10;
                backend.draw_line((m, y - 8), (m, y + 8), &thin)?;
                backend.draw_line((m - cap, y - 8), (m + cap, y - 8), &thin)?;
                backend.draw_line((m - cap, y + 8), (m + cap, y + 8), &thin)?;
                backend.draw_circle((m, y), MARKER_RADIUS, &c.filled(), true)
            }
        }
    }
}
