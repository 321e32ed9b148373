//! Figures written to disk, decoded and checked.

use std::collections::HashSet;
use std::path::Path;

use edmd_plot::{histogram, Figure, PlotError, Series, FIGURE_SIZE, PALETTE};

/// A decoded RGB image.
struct Image {
    width: u32,
    height: u32,
    rgb: Vec<u8>,
}

impl Image {
    fn decode(bytes: &[u8]) -> Image {
        let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
        let mut reader = decoder.read_info().expect("PNG header");
        let mut buf = vec![0; reader.output_buffer_size().expect("buffer size")];
        let info = reader.next_frame(&mut buf).expect("PNG data");
        assert_eq!(info.color_type, png::ColorType::Rgb);
        assert_eq!(info.bit_depth, png::BitDepth::Eight);
        buf.truncate(info.buffer_size());
        Image {
            width: info.width,
            height: info.height,
            rgb: buf,
        }
    }

    fn load(path: &Path) -> Image {
        Image::decode(&std::fs::read(path).expect("PNG file"))
    }

    fn pixel(&self, x: u32, y: u32) -> [u8; 3] {
        let i = 3 * (y as usize * self.width as usize + x as usize);
        [self.rgb[i], self.rgb[i + 1], self.rgb[i + 2]]
    }

    /// Pixels darker than mid-grey (text, axes) in a rectangle.
    fn dark_pixels(&self, xs: std::ops::Range<u32>, ys: std::ops::Range<u32>) -> usize {
        ys.flat_map(|y| xs.clone().map(move |x| (x, y)))
            .filter(|&(x, y)| self.pixel(x, y).iter().all(|&c| c < 100))
            .count()
    }

    fn count_colour(&self, rgb: [u8; 3]) -> usize {
        self.rgb.chunks_exact(3).filter(|p| *p == rgb).count()
    }
}

fn sample_figure() -> Figure {
    let speeds: Vec<f64> = (0..500).map(|i| ((i * 37) % 101) as f64 / 50.0).collect();
    let curve: Vec<(f64, f64)> = (0..=40)
        .map(|i| (i as f64 * 0.05, 0.5 + 0.1 * i as f64 / 40.0))
        .collect();
    let measured = vec![(0.25, 0.4), (0.75, 0.5), (1.25, 0.45), (1.75, 0.55)];
    Figure::new(
        "Distribution of speeds",
        "speed v (σ/τ)",
        "density P(v) (τ/σ)",
    )
    .with(Series::bars(
        "histogram",
        histogram(&speeds, 10, None, true),
    ))
    .with(Series::line("fit", curve))
    .with(Series::error_bars(
        "measured",
        measured,
        vec![0.05, 0.04, 0.06, 0.05],
    ))
}

#[test]
fn save_writes_a_png_and_an_svg() {
    let dir = tempfile::tempdir().unwrap();
    let fig = sample_figure();
    let (png_path, svg_path) = fig
        .save(&dir.path().join("figs").join("speeds_T0.5"))
        .unwrap();
    assert_eq!(png_path, dir.path().join("figs/speeds_T0.5.png"));
    assert_eq!(svg_path, dir.path().join("figs/speeds_T0.5.svg"));

    let img = Image::load(&png_path);
    assert_eq!((img.width, img.height), FIGURE_SIZE);
    assert_eq!((img.width, img.height), (1000, 700));
    let colours: HashSet<[u8; 3]> = img
        .rgb
        .chunks_exact(3)
        .map(|p| [p[0], p[1], p[2]])
        .collect();
    assert!(colours.len() > 20, "only {} colours", colours.len());
    // The background is white.
    assert_eq!(img.pixel(0, 0), [255, 255, 255]);
    assert_eq!(img.pixel(999, 699), [255, 255, 255]);
    // Text was rendered with the embedded font: the title (top band), the
    // rotated y label (left band) and the x label (bottom band).
    assert!(img.dark_pixels(300..700, 0..40) > 200, "no title");
    assert!(img.dark_pixels(0..40, 150..550) > 200, "no y label");
    assert!(img.dark_pixels(300..700, 650..700) > 200, "no x label");
    // The fit line is drawn in the second palette colour, the error bars'
    // markers in the third.
    assert!(img.count_colour(PALETTE[1]) > 300);
    assert!(img.count_colour(PALETTE[2]) > 50);

    let svg = std::fs::read_to_string(&svg_path).unwrap();
    assert!(svg.starts_with("<svg"));
    assert!(svg.contains(r#"width="1000" height="700""#));
    for text in [
        "Distribution of speeds",
        "speed v (σ/τ)",
        "density P(v) (τ/σ)",
    ] {
        assert!(svg.contains(text), "SVG lacks {text:?}");
    }
    // Three series: a legend naming them.
    for label in ["histogram", "fit", "measured"] {
        assert!(
            svg.contains(&format!(">\n{label}\n<")),
            "legend lacks {label:?}"
        );
    }
    // Tick labels.
    assert!(svg.contains(">\n0.5\n<"));
}

#[test]
fn png_bytes_match_the_saved_file() {
    let dir = tempfile::tempdir().unwrap();
    let fig = sample_figure();
    let (png_path, svg_path) = fig.save(&dir.path().join("a")).unwrap();
    assert_eq!(std::fs::read(png_path).unwrap(), fig.to_png().unwrap());
    assert_eq!(
        std::fs::read_to_string(svg_path).unwrap(),
        fig.to_svg().unwrap()
    );
    let png = fig.to_png().unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    // IHDR: width and height, big-endian.
    assert_eq!(&png[16..24], &[0, 0, 0x03, 0xe8, 0, 0, 0x02, 0xbc]);
}

#[test]
fn legend_only_with_several_series() {
    let one = Figure::new("t", "x (m)", "y (s)")
        .with(Series::line("lonely-series", vec![(0.0, 0.0), (1.0, 1.0)]));
    assert!(!one.to_svg().unwrap().contains("lonely-series"));
    let two = one.with(Series::points("other-series", vec![(0.5, 0.5)]));
    let svg = two.to_svg().unwrap();
    assert!(svg.contains("lonely-series") && svg.contains("other-series"));
}

#[test]
fn text_is_escaped_in_svg() {
    let svg = Figure::new("a < b & c", "x", "y").to_svg().unwrap();
    assert!(svg.contains("a &lt; b &amp; c"));
}

#[test]
fn explicit_colours_are_used() {
    let fig = Figure::new("t", "x", "y")
        .with(Series::line("l", vec![(0.0, 0.0), (1.0, 1.0), (2.0, 0.0)]).coloured([200, 0, 100]));
    let img = Image::decode(&fig.to_png().unwrap());
    assert!(img.count_colour([200, 0, 100]) > 300);
    assert_eq!(img.count_colour(PALETTE[0]), 0);
}

#[test]
fn histogram_counts_by_hand() {
    let values = [0.0, 0.1, 0.5, 0.9, 1.0, 2.0, -0.1, f64::NAN, f64::INFINITY];
    // [0, 0.5): 0.0, 0.1; [0.5, 1]: 0.5, 0.9, 1.0; 2.0 and -0.1 outside.
    assert_eq!(
        histogram(&values, 2, Some((0.0, 1.0)), false),
        vec![(0.25, 2.0), (0.75, 3.0)]
    );
    // Density: count / (5 * 0.5).
    assert_eq!(
        histogram(&values, 2, Some((0.0, 1.0)), true),
        vec![(0.25, 0.8), (0.75, 1.2)]
    );
    // Default range: the finite extent, -0.1 ..= 2.0, in 3 bins of 0.7:
    // [-0.1, 0.6) holds -0.1, 0.0, 0.1, 0.5; [0.6, 1.3) 0.9, 1.0; [1.3, 2.0] 2.0.
    let h = histogram(&values, 3, None, false);
    let expect = [(0.25, 4.0), (0.95, 2.0), (1.65, 1.0)];
    assert_eq!(h.len(), 3);
    for ((c, n), (ec, en)) in h.iter().zip(expect) {
        assert!((c - ec).abs() < 1e-12, "centre {c} vs {ec}");
        assert_eq!(*n, en);
    }
    // Densities integrate to one.
    let h = histogram(&[0.3, 1.7, 2.2, 2.9, 3.3, 9.0], 7, None, true);
    let width = h[1].0 - h[0].0;
    let total: f64 = h.iter().map(|(_, d)| d * width).sum();
    assert!((total - 1.0).abs() < 1e-12);
    // A reversed range is sorted.
    assert_eq!(
        histogram(&[0.2], 1, Some((1.0, 0.0)), false),
        vec![(0.5, 1.0)]
    );
}

#[test]
fn histogram_degenerate_input() {
    assert!(histogram(&[1.0, 2.0], 0, None, false).is_empty());
    assert!(histogram(&[], 4, None, false).is_empty());
    assert!(histogram(&[f64::NAN], 4, None, true).is_empty());
    // No values but a range: empty bins, zero density.
    assert_eq!(
        histogram(&[], 2, Some((0.0, 2.0)), true),
        vec![(0.5, 0.0), (1.5, 0.0)]
    );
    // All equal: the range is widened around the value and all land in one bin.
    let h = histogram(&[3.0; 5], 2, None, false);
    assert_eq!(h.iter().map(|p| p.1).sum::<f64>(), 5.0);
    assert!(h[0].0 < 3.0 && h[1].0 > 3.0);
}

#[test]
fn bad_data_does_not_panic() {
    let nan = f64::NAN;
    let inf = f64::INFINITY;
    let figures = vec![
        Figure::new("", "", ""),
        Figure::new("empty series", "x", "y")
            .with(Series::line("a", vec![]))
            .with(Series::points("b", vec![]))
            .with(Series::bars("c", vec![]))
            .with(Series::error_bars("d", vec![], vec![])),
        Figure::new("all NaN", "x", "y")
            .with(Series::line("a", vec![(nan, nan), (nan, 1.0), (1.0, inf)]))
            .with(Series::bars("b", vec![(nan, 1.0), (inf, 2.0)])),
        Figure::new("single points", "x", "y")
            .with(Series::line("a", vec![(1.0, 1.0)]))
            .with(Series::bars("b", vec![(0.0, 0.0)]))
            .with(Series::error_bars("c", vec![(0.0, 0.0)], vec![nan])),
        Figure::new("mismatched errors", "x", "y")
            .with(Series::error_bars(
                "a",
                vec![(0.0, 1.0), (1.0, 2.0), (2.0, 3.0)],
                vec![0.1],
            ))
            .with(Series::error_bars(
                "b",
                vec![(0.0, 1.0)],
                vec![-0.5, 1.0, 2.0],
            )),
        Figure::new("zero-width ranges", "x", "y")
            .with(Series::line("a", vec![(1.0, 5.0), (1.0, 5.0)]))
            .with_x_range(2.0, 2.0)
            .with_y_range(nan, 3.0),
        Figure::new("log of non-positive", "x", "y")
            .with(Series::line(
                "a",
                vec![(0.0, -1.0), (1.0, 0.0), (2.0, -3.0)],
            ))
            .with(Series::bars("b", vec![(0.0, 0.0), (1.0, -2.0)]))
            .with_log_y(),
        Figure::new("log with gaps", "x", "y")
            .with(Series::line(
                "a",
                vec![(0.0, 1.0), (1.0, -1.0), (2.0, 100.0), (3.0, 1e-300)],
            ))
            .with(Series::bars("b", vec![(0.0, 3.0), (1.0, 0.0), (2.0, 30.0)]))
            .with(Series::error_bars("c", vec![(0.5, 2.0)], vec![5.0]))
            .with_log_y()
            .with_y_range(0.0, 1e3),
        Figure::new("data outside a fixed range", "x", "y")
            .with(Series::line(
                "a",
                vec![(-10.0, -10.0), (10.0, 10.0), (0.5, 30.0)],
            ))
            .with(Series::bars(
                "b",
                vec![(-5.0, 3.0), (0.5, 4.0), (5.0, -3.0)],
            ))
            .with(Series::error_bars("c", vec![(0.5, 0.5)], vec![10.0]))
            .with_x_range(0.0, 1.0)
            .with_y_range(0.0, 1.0),
        Figure::new("huge and tiny", "x", "y").with(Series::points(
            "a",
            vec![(f64::MAX, f64::MIN_POSITIVE), (-f64::MAX, 1e300)],
        )),
    ];
    for fig in &figures {
        let png = fig
            .to_png()
            .unwrap_or_else(|e| panic!("{}: {e}", fig.title));
        let img = Image::decode(&png);
        assert_eq!((img.width, img.height), FIGURE_SIZE);
        fig.to_svg()
            .unwrap_or_else(|e| panic!("{}: {e}", fig.title));
    }
}

#[test]
fn unwritable_path_is_an_io_error() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("not-a-folder");
    std::fs::write(&file, b"x").unwrap();
    let err = Figure::new("t", "x", "y")
        .save(&file.join("fig"))
        .unwrap_err();
    assert!(matches!(err, PlotError::Io { .. }), "{err:?}");
    assert!(err.to_string().contains("not-a-folder"), "{err}");
}
