//! Figures for edmd's measurements and experiments.
//!
//! A [`Figure`] is a title, two axis labels (units included, as the caller
//! writes them) and a list of [`Series`]: lines, points, histogram bars or
//! points with error bars. [`Figure::save`] writes it twice, as
//! `<stem>.png` (1000 × 700 pixels) and `<stem>.svg`, drawn with
//! [`plotters`]. The font (DejaVu Sans) is embedded in the binary, so no
//! system font is needed when the figures are made; the SVG names the
//! generic family `sans-serif`, which every viewer has.
//!
//! Drawing never fails on bad data: non-finite points (and, on a
//! logarithmic y axis, non-positive ones) are skipped, empty series draw
//! nothing, degenerate ranges are widened. Only writing the files can fail.
//!
//! ```
//! use edmd_plot::{histogram, Figure, Series};
//!
//! let dir = tempfile::tempdir()?;
//! let speeds = [0.1, 0.4, 0.5, 0.9, 1.2, 1.3, 1.4, 2.0];
//! let fig = Figure::new("Speed distribution", "speed v (σ/τ)", "density P(v) (τ/σ)")
//!     .with(Series::bars("simulation", histogram(&speeds, 4, None, true)))
//!     .with(Series::line("theory", vec![(0.0, 0.0), (1.0, 0.6), (2.0, 0.1)]).coloured([0, 0, 0]));
//! let (png, svg) = fig.save(&dir.path().join("speeds"))?;
//! assert!(png.ends_with("speeds.png") && svg.ends_with("speeds.svg"));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![forbid(unsafe_code)]

mod axes;
mod geometry;
mod render;

use std::ffi::OsString;
use std::path::{Path, PathBuf};

pub use geometry::histogram;

/// Width and height in pixels of the PNG that [`Figure::save`] writes (the
/// SVG has the same size in user units).
pub const FIGURE_SIZE: (u32, u32) = (1000, 700);

/// The colours given in turn to series that have none of their own
/// (the "tab10" palette), as RGB.
pub const PALETTE: [[u8; 3]; 10] = [
    [31, 119, 180],
    [255, 127, 14],
    [44, 160, 44],
    [214, 39, 40],
    [148, 103, 189],
    [140, 86, 75],
    [227, 119, 194],
    [127, 127, 127],
    [188, 189, 34],
    [23, 190, 207],
];

/// What can go wrong when a figure is saved.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// A file or its folder could not be written. The operating system's reason is the
    /// error's source, so that a chain of causes printed on one line names it once.
    #[error("cannot write {}", path.display())]
    Io {
        /// The file (or folder) that could not be written.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// The drawing library or the PNG encoder failed. This is not expected
    /// to happen (everything is drawn in memory with the embedded font); it
    /// is reported rather than panicking.
    #[error("cannot draw figure {title:?}: {message}")]
    Render {
        /// The figure's title.
        title: String,
        /// What the drawing library said.
        message: String,
    },
}

/// How a [`Series`] is drawn.
#[derive(Debug, Clone, PartialEq)]
pub enum SeriesKind {
    /// Points joined by straight lines, in the order given. A non-finite
    /// point breaks the line.
    Line,
    /// Unjoined markers.
    Points,
    /// A histogram: each point is (bin centre, height) and is drawn as a
    /// bar from 0 (or, on a logarithmic axis, from the bottom of the plot).
    /// All bars have the same width, the smallest spacing between
    /// neighbouring centres.
    Bars,
    /// Markers with symmetric vertical error bars: `y ± errors[i]` for the
    /// i-th point. A point with no (or a non-finite) error gets no bar.
    ErrorBars(Vec<f64>),
}

/// One data set of a [`Figure`].
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Name shown in the legend (the legend is drawn when the figure has
    /// more than one series; series with an empty label are left out of it).
    pub label: String,
    /// How the points are drawn.
    pub kind: SeriesKind,
    /// Data points (x, y).
    pub points: Vec<(f64, f64)>,
    /// RGB colour; `None` takes the next colour of [`PALETTE`] by the
    /// series' position in the figure.
    pub colour: Option<[u8; 3]>,
}

impl Series {
    fn new(label: &str, kind: SeriesKind, points: Vec<(f64, f64)>) -> Self {
        Self {
            label: label.to_owned(),
            kind,
            points,
            colour: None,
        }
    }

    /// Points joined by lines.
    pub fn line(label: &str, points: Vec<(f64, f64)>) -> Self {
        Self::new(label, SeriesKind::Line, points)
    }

    /// Unjoined markers.
    pub fn points(label: &str, points: Vec<(f64, f64)>) -> Self {
        Self::new(label, SeriesKind::Points, points)
    }

    /// Histogram bars from (bin centre, height) pairs, e.g. the output of
    /// [`histogram`].
    pub fn bars(label: &str, points: Vec<(f64, f64)>) -> Self {
        Self::new(label, SeriesKind::Bars, points)
    }

    /// Markers with symmetric y error bars, `errors[i]` for `points[i]`.
    pub fn error_bars(label: &str, points: Vec<(f64, f64)>, errors: Vec<f64>) -> Self {
        Self::new(label, SeriesKind::ErrorBars(errors), points)
    }

    /// Sets the colour (RGB).
    pub fn coloured(mut self, rgb: [u8; 3]) -> Self {
        self.colour = Some(rgb);
        self
    }
}

/// A figure: title, axis labels, series and axis options.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    /// Title drawn above the plot.
    pub title: String,
    /// Label of the x axis, with its unit.
    pub x_label: String,
    /// Label of the y axis, with its unit.
    pub y_label: String,
    /// The data, drawn in order (later series on top).
    pub series: Vec<Series>,
    /// Fixed x range; `None` for the data's extent plus a 5% margin.
    pub x_range: Option<(f64, f64)>,
    /// Fixed y range; `None` for the data's extent plus a 5% margin
    /// (measured in decades when `log_y`).
    pub y_range: Option<(f64, f64)>,
    /// Logarithmic y axis (non-positive values are then skipped).
    pub log_y: bool,
}

impl Figure {
    /// An empty figure with a title and axis labels (units included).
    pub fn new(title: &str, x_label: &str, y_label: &str) -> Self {
        Self {
            title: title.to_owned(),
            x_label: x_label.to_owned(),
            y_label: y_label.to_owned(),
            series: Vec::new(),
            x_range: None,
            y_range: None,
            log_y: false,
        }
    }

    /// Adds a series (builder style).
    pub fn with(mut self, s: Series) -> Self {
        self.series.push(s);
        self
    }

    /// Fixes the x range (builder style). Data outside it is clipped.
    pub fn with_x_range(mut self, lo: f64, hi: f64) -> Self {
        self.x_range = Some((lo, hi));
        self
    }

    /// Fixes the y range (builder style). Data outside it is clipped.
    pub fn with_y_range(mut self, lo: f64, hi: f64) -> Self {
        self.y_range = Some((lo, hi));
        self
    }

    /// Makes the y axis logarithmic (builder style).
    pub fn with_log_y(mut self) -> Self {
        self.log_y = true;
        self
    }

    /// The figure as an SVG document.
    pub fn to_svg(&self) -> Result<String, PlotError> {
        render::svg(self).map_err(|message| self.render_error(message))
    }

    /// The figure as a PNG file's bytes (1000 × 700, RGB).
    pub fn to_png(&self) -> Result<Vec<u8>, PlotError> {
        render::png(self).map_err(|message| self.render_error(message))
    }

    /// Writes `<stem>.png` (1000 × 700) and `<stem>.svg`; returns both paths.
    ///
    /// The extensions are appended to `stem` (so `fig_T0.5` gives
    /// `fig_T0.5.png`), and missing parent folders are created.
    pub fn save(&self, stem: &Path) -> Result<(PathBuf, PathBuf), PlotError> {
        let png_path = with_suffix(stem, "png");
        let svg_path = with_suffix(stem, "svg");
        if let Some(parent) = stem.parent().filter(|p| !p.as_os_str().is_empty()) {
            std::fs::create_dir_all(parent).map_err(|source| PlotError::Io {
                path: parent.to_owned(),
                source,
            })?;
        }
        let png = self.to_png()?;
        let svg = self.to_svg()?;
        write(&png_path, &png)?;
        write(&svg_path, svg.as_bytes())?;
        Ok((png_path, svg_path))
    }

    fn render_error(&self, message: String) -> PlotError {
        PlotError::Render {
            title: self.title.clone(),
            message,
        }
    }
}

fn with_suffix(stem: &Path, ext: &str) -> PathBuf {
    let mut name = OsString::from(stem.as_os_str());
    name.push(".");
    name.push(ext);
    PathBuf::from(name)
}

fn write(path: &Path, bytes: &[u8]) -> Result<(), PlotError> {
    std::fs::write(path, bytes).map_err(|source| PlotError::Io {
        path: path.to_owned(),
        source,
    })
}
