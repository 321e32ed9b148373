//! Writes a few sample figures, to look at: `cargo run -p edmd-plot --example gallery -- DIR`.

use std::path::PathBuf;

use edmd_plot::{histogram, Figure, Series};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "gallery".to_owned()),
    );

    // A Maxwell–Boltzmann-like speed histogram against its curve.
    let speeds: Vec<f64> = (0..4000)
        .map(|i| {
            let u = (i as f64 + 0.5) / 4000.0;
            (-2.0 * (1.0 - u).ln()).sqrt()
        })
        .collect();
    let theory: Vec<(f64, f64)> = (0..=120)
        .map(|i| {
            let v = i as f64 * 0.035;
            (v, v * (-v * v / 2.0).exp())
        })
        .collect();
    let fig = Figure::new(
        "Speed distribution, N = 4000 discs, T = 1",
        "speed v (σ/τ)",
        "probability density P(v) (τ/σ)",
    )
    .with(Series::bars(
        "simulation",
        histogram(&speeds, 30, None, true),
    ))
    .with(Series::line("Maxwell–Boltzmann, 2D", theory));
    println!("{:?}", fig.save(&dir.join("speeds"))?);

    // Pressure against density with error bars, a fit line and raw points.
    let rho: Vec<f64> = (1..=12).map(|i| i as f64 * 0.07).collect();
    let p: Vec<(f64, f64)> = rho.iter().map(|&r| (r, r / (1.0 - r).powi(2))).collect();
    let err: Vec<f64> = p.iter().map(|&(_, y)| 0.04 * y + 0.05).collect();
    let fit: Vec<(f64, f64)> = (0..=100)
        .map(|i| {
            let r = 0.05 + i as f64 * 0.0082;
            (r, r / (1.0 - r).powi(2) * 1.02)
        })
        .collect();
    let raw: Vec<(f64, f64)> = p.iter().map(|&(x, y)| (x + 0.01, y * 0.97)).collect();
    let fig = Figure::new(
        "Equation of state",
        "packing fraction φ",
        "reduced pressure βP/ρ",
    )
    .with(Series::error_bars("measured", p, err))
    .with(Series::line("Henderson fit", fit))
    .with(Series::points("short runs", raw));
    println!("{:?}", fig.save(&dir.join("eos"))?);

    // Logarithmic y: a decaying correlation with noise going negative.
    let c: Vec<(f64, f64)> = (0..200)
        .map(|i| {
            let t = i as f64 * 0.1;
            (t, (-t / 3.0).exp() + 1e-4 * (i as f64 * 1.7).sin())
        })
        .collect();
    let fig = Figure::new("Velocity autocorrelation", "time t (τ)", "C(t) / C(0)")
        .with(Series::line("", c))
        .with_log_y();
    println!("{:?}", fig.save(&dir.join("vacf"))?);

    // Degenerate data: nothing, a NaN, a single point.
    let fig = Figure::new("Degenerate", "x (1)", "y (1)")
        .with(Series::line("empty", vec![]))
        .with(Series::points("one", vec![(2.0, 2.0), (f64::NAN, 1.0)]));
    println!("{:?}", fig.save(&dir.join("degenerate"))?);
    Ok(())
}
