//! Times the pieces of a viewer frame without a window: `cargo run --release -p edmd-view
//! --example draw_bench -- [N] [WIDTH] [HEIGHT]`.

use std::time::Instant;

use edmd_core::setup::generators::{generate, GenKind};
use edmd_core::{Options, Simulation};
use edmd_draw::{draw_into, Colouring, Pixmap, Scene};

fn main() {
    let args: Vec<usize> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let n = args.first().copied().unwrap_or(10_000);
    let (w, h) = (
        args.get(1).copied().unwrap_or(930) as u32,
        args.get(2).copied().unwrap_or(770) as u32,
    );
    let GenKind::Fluid(mut f) = GenKind::from_name("fluid").unwrap() else {
        unreachable!()
    };
    f.n = n;
    f.packing = 0.5;
    let sys = generate(&GenKind::Fluid(f), 1).unwrap();
    let sim = Simulation::from_system(&sys, Options::default()).unwrap();
    let mut pm = Pixmap::new(w, h).unwrap();
    for colouring in [Colouring::File, Colouring::Speed] {
        let reps = 20;
        let t0 = Instant::now();
        let mut scene = Scene::default();
        for _ in 0..reps {
            scene = Scene::capture(&sim, colouring);
        }
        let t1 = Instant::now();
        for _ in 0..reps {
            draw_into(&scene, &mut pm);
        }
        let t2 = Instant::now();
        for _ in 0..reps {
            let _ = eframe::egui::ColorImage::from_rgba_premultiplied(
                [w as usize, h as usize],
                pm.data(),
            );
        }
        let t3 = Instant::now();
        let ms = |a: Instant, b: Instant| 1e3 * (b - a).as_secs_f64() / reps as f64;
        println!(
            "{colouring:?}: N = {n}, {w} x {h}: capture {:.2} ms, draw {:.2} ms, to egui image {:.2} ms",
            ms(t0, t1),
            ms(t1, t2),
            ms(t2, t3)
        );
    }
}
