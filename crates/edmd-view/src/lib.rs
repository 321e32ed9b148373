//! # edmd-view: watch hard discs collide
//!
//! The interactive viewer of edmd. The simulation runs event by event; at every frame it is
//! advanced exactly to the frame's time (`run_until`, no collision skipped), and the picture is
//! drawn by [`edmd_draw::draw_into`], the same code as the offline renderer `edmd render`, then
//! shown as a texture in an eframe/egui window (OpenGL through glow).
//!
//! ```text
//! edmd-view FILE [--colour file|speed|species|energy] [--bonds] [--speed S]
//! edmd-view --gen KIND [--n N --packing P --boundary B --kt KT --seed S]
//! ```
//!
//! Controls: play/pause (space), one event (right arrow), restart (R), reverse velocities (V),
//! colouring (C or the buttons), bonds between the discs of the pairs inside a well or shoulder
//! of a stepped potential (B or the check box), a logarithmic slider for the simulated time per second, and a
//! click on a disc to tag it and draw its path. The side panel plots the temperature and the
//! pressure against time and the speed histogram against the Rayleigh law, with counters.
//! A 3D file (`# edmd dim 3`) is shown as shaded spheres in an orthographic view that turns
//! when the picture is dragged (and with the up, down and left arrow keys).
//! A 1D file (`# edmd dim 1`) is shown as rods on a line, drawn as `edmd render` draws them,
//! above its phase plane: one dot per rod at its position and velocity (for self-gravitating
//! sheets, the sheets' positions, so that a water bag winds up into its spiral); the velocity
//! histogram is compared with the 1D law, a Gaussian, and under self-gravity the virial ratio
//! `2K/U` takes the pressure's place.
//! A file with reaction rules (`# edmd reaction`) runs reactive, as `edmd run` runs it: the
//! colours are read from the simulation at every frame, so a disc that reacts is drawn in its
//! new species' colour from then on.
//!
//! Without a display the program prints one line and exits with status 2. For tests and
//! measurements: `--screenshot FILE.png --quit-after SECONDS` saves a real screenshot of the
//! window and quits; `--fps-report` prints the mean frame rate on exit.

#![forbid(unsafe_code)]

pub mod app;
pub mod args;
pub mod model;
pub mod painter;

use std::cell::RefCell;
use std::process::ExitCode;
use std::rc::Rc;

use eframe::egui;

pub use app::{Report, Settings, ViewerApp};
pub use args::ViewArgs;
pub use model::Model;

/// The advice given when there is no display.
pub const NO_DISPLAY_HINT: &str =
    "to draw frames without a screen, use `edmd render FILE -o out.gif --until T`";

/// Whether a display server is named in the environment (`DISPLAY` or `WAYLAND_DISPLAY`).
pub fn display_available() -> bool {
    ["DISPLAY", "WAYLAND_DISPLAY"]
        .iter()
        .any(|v| std::env::var_os(v).is_some_and(|s| !s.is_empty()))
}

/// Runs the program: parses the arguments, opens the window, returns the exit status.
pub fn main() -> ExitCode {
    let args: ViewArgs = match edmd::front::parse_args("edmd-view") {
        Ok(a) => a,
        Err(code) => return code,
    };
    if let Err(e) = args.validate() {
        return edmd::front::exit_with("edmd-view", Err(e));
    }
    if !display_available() {
        eprintln!(
            "edmd-view: no display (neither DISPLAY nor WAYLAND_DISPLAY is set); {NO_DISPLAY_HINT}"
        );
        return ExitCode::from(2);
    }
    let checked = |stepped: bool| args.check_potential(stepped);
    match args.simulation_any() {
        Ok(args::AnySimulation::One(sim)) => {
            match args.check_line().and_then(|()| checked(sim.is_stepped())) {
                Ok(()) => show(&args, sim),
                Err(e) => edmd::front::exit_with("edmd-view", Err(e)),
            }
        }
        Ok(args::AnySimulation::Two(sim)) => match checked(sim.is_stepped()) {
            Ok(()) => show(&args, sim),
            Err(e) => edmd::front::exit_with("edmd-view", Err(e)),
        },
        Ok(args::AnySimulation::Three(sim)) => match checked(sim.is_stepped()) {
            Ok(()) => show(&args, sim),
            Err(e) => edmd::front::exit_with("edmd-view", Err(e)),
        },
        Err(e) => edmd::front::exit_with("edmd-view", Err(e)),
    }
}

/// Opens the window on `sim` and runs it until it closes.
fn show<const D: usize>(args: &ViewArgs, sim: edmd_core::Simulation<D>) -> ExitCode {
    let settings = Settings {
        speed: args.speed.unwrap_or_else(|| model::default_speed(&sim)),
        playing: !args.paused,
        screenshot: args.screenshot.clone(),
        quit_after: args.quit_after,
    };
    let mut model = Model::new(sim, args.colour.into());
    model.bonds = args.bonds;
    let report = Rc::new(RefCell::new(Report::default()));
    let options = eframe::NativeOptions {
        renderer: eframe::Renderer::Glow,
        viewport: egui::ViewportBuilder::default()
            .with_title("edmd-view")
            .with_inner_size(args.size),
        ..Default::default()
    };
    let shared = report.clone();
    let result = eframe::run_native(
        "edmd-view",
        options,
        Box::new(move |cc| {
            Ok(Box::new(ViewerApp::new(
                &cc.egui_ctx,
                model,
                settings,
                shared,
            )))
        }),
    );
    if let Err(e) = result {
        let why = e.to_string().replace('\n', " ");
        eprintln!("edmd-view: no display: cannot open a window ({why}); {NO_DISPLAY_HINT}");
        return ExitCode::from(2);
    }
    let report = report.borrow();
    if args.fps_report {
        println!("{}", report.summary());
    }
    if let Some(e) = &report.error {
        eprintln!("edmd-view: error: {e}");
        return ExitCode::from(1);
    }
    ExitCode::SUCCESS
}
