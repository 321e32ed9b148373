//! The window: controls, live plots and counters, and the picture drawn by `edmd_draw`.

use std::cell::RefCell;
use std::path::{Path, PathBuf};
use std::rc::Rc;
use std::time::{Duration, Instant};

use eframe::egui;
use egui::{Color32, ColorImage, Key, TextureHandle, TextureOptions, ViewportCommand};
use egui_plot::{Bar, BarChart, Legend, Line, MarkerShape, Plot, PlotPoints, Points};

use edmd_core::{EventKind, StepHit};
use edmd_draw::{pick, AnyScene, Colouring, View, OUTSIDE};

use crate::model::Model;
use crate::painter::{Painter, Picture};

/// Wall time between measurement samples (temperature, pressure block, speed histogram).
const SAMPLE_EVERY: Duration = Duration::from_millis(250);
/// Longest wall-clock step taken at once (after a stall, the simulation does not jump ahead).
const MAX_FRAME_DT: f64 = 0.1;
/// How long to wait for a requested screenshot before giving up.
const SCREENSHOT_TIMEOUT: Duration = Duration::from_secs(10);
/// Delay before the screenshot when `--screenshot` comes without `--quit-after`.
const DEFAULT_SCREENSHOT_DELAY: f64 = 2.0;

/// Frame timings, shared with `main` so that it can print the frame rate on exit.
#[derive(Clone, Debug, Default)]
pub struct Report {
    /// Pictures shown (frames of the simulation).
    pub pictures: u64,
    /// Frames of the interface (egui updates).
    pub updates: u64,
    /// Time of the first frame.
    pub first: Option<Instant>,
    /// Time of the last frame.
    pub last: Option<Instant>,
    /// Wall time spent running the simulation, in seconds.
    pub simulate: f64,
    /// Wall time spent drawing the picture (`edmd_draw`), in seconds.
    pub draw: f64,
    /// Wall time spent converting and uploading the picture, in seconds.
    pub upload: f64,
    /// Number of rods, discs or spheres.
    pub discs: usize,
    /// What they are: "rods", "discs" or "spheres".
    pub noun: &'static str,
    /// A failure to report on exit (for example, a screenshot that could not be written).
    pub error: Option<String>,
}

impl Report {
    /// Mean pictures (new frames of the simulation) per second between the first and the last
    /// interface frame.
    pub fn fps(&self) -> Option<f64> {
        let span = self.last?.duration_since(self.first?).as_secs_f64();
        (self.pictures > 1 && span > 0.0).then(|| self.pictures as f64 / span)
    }

    /// One line: frame rate and mean time per frame in each stage.
    pub fn summary(&self) -> String {
        let per = |s: f64| 1e3 * s / self.pictures.max(1) as f64;
        match self.fps() {
            Some(fps) => format!(
                "edmd-view: {fps:.1} frames per second ({} frames in {:.1} s, {} {}; per frame: simulate {:.1} ms, draw {:.1} ms (drawing thread), upload {:.1} ms; {} interface updates)",
                self.pictures,
                self.last.unwrap().duration_since(self.first.unwrap()).as_secs_f64(),
                self.discs,
                self.noun,
                per(self.simulate),
                per(self.draw),
                per(self.upload),
                self.updates
            ),
            None => format!("edmd-view: too few frames to measure a frame rate ({})", self.pictures),
        }
    }
}

/// What the command line asks of the window besides the system.
#[derive(Clone, Debug)]
pub struct Settings {
    /// Simulated time per second of wall time.
    pub speed: f64,
    /// Start running (else paused).
    pub playing: bool,
    /// Save a screenshot here, then quit.
    pub screenshot: Option<PathBuf>,
    /// Quit after this many seconds.
    pub quit_after: Option<f64>,
}

/// Counts over a sliding window of wall time, for rates.
#[derive(Clone, Copy, Debug)]
struct Rates {
    start: Instant,
    frames: u64,
    collisions: u64,
    fps: f64,
    collisions_per_second: f64,
}

/// The viewer application.
pub struct ViewerApp<const D: usize = 2> {
    model: Model<D>,
    playing: bool,
    speed: f64,
    speed_range: (f64, f64),
    painter: Painter,
    shown_size: (u32, u32),
    texture: Option<TextureHandle>,
    scene: AnyScene,
    redraw: bool,
    last_frame: Option<Instant>,
    last_sample: Instant,
    started: Instant,
    rates: Rates,
    screenshot: Option<PathBuf>,
    quit_after: Option<Duration>,
    screenshot_requested: Option<Instant>,
    last_event: String,
    /// On a line, the phase plane's extent so far, `[x_min, x_max, v_min, v_max]`: it only
    /// grows (until a restart), so that the plot does not jump at every frame.
    phase_bounds: Option<[f64; 4]>,
    report: Rc<RefCell<Report>>,
}

impl<const D: usize> ViewerApp<D> {
    /// A window showing `model`.
    pub fn new(
        ctx: &egui::Context,
        model: Model<D>,
        settings: Settings,
        report: Rc<RefCell<Report>>,
    ) -> Self {
        let now = Instant::now();
        let wake = ctx.clone();
        let painter = Painter::new(move || wake.request_repaint());
        report.borrow_mut().discs = model.sim.len();
        report.borrow_mut().noun = particles::<D>();
        let quit_after = settings
            .quit_after
            .or(settings
                .screenshot
                .as_ref()
                .map(|_| DEFAULT_SCREENSHOT_DELAY))
            .map(Duration::from_secs_f64);
        let collisions = model.sim.stats().disc_disc;
        ViewerApp {
            model,
            playing: settings.playing,
            speed: settings.speed,
            speed_range: (settings.speed * 1e-3, settings.speed * 1e3),
            painter,
            shown_size: (0, 0),
            texture: None,
            scene: AnyScene::default(),
            redraw: true,
            last_frame: None,
            last_sample: now,
            started: now,
            rates: Rates {
                start: now,
                frames: 0,
                collisions,
                fps: 0.0,
                collisions_per_second: 0.0,
            },
            screenshot: settings.screenshot,
            quit_after,
            screenshot_requested: None,
            last_event: String::new(),
            phase_bounds: None,
            report,
        }
    }

    /// Turns a 3D view by `azimuth` and `elevation` degrees (the elevation stays within +-90).
    fn turn(&mut self, azimuth: f64, elevation: f64) {
        if let View::Orbit {
            azimuth: a,
            elevation: e,
        } = &mut self.model.view
        {
            *a = (*a + azimuth).rem_euclid(360.0);
            *e = (*e + elevation).clamp(-90.0, 90.0);
            self.redraw = true;
        }
    }

    fn keys(&mut self, ctx: &egui::Context) {
        if D == 3 {
            let (up, down, left) = ctx.input(|i| {
                (
                    i.key_pressed(Key::ArrowUp),
                    i.key_pressed(Key::ArrowDown),
                    i.key_pressed(Key::ArrowLeft),
                )
            });
            if up {
                self.turn(0.0, 10.0);
            }
            if down {
                self.turn(0.0, -10.0);
            }
            if left {
                self.turn(10.0, 0.0);
            }
        }
        if ctx.input(|i| i.key_pressed(Key::F)) {
            self.step_frame();
        }
        let (space, right, r, v, c) = ctx.input(|i| {
            (
                i.key_pressed(Key::Space),
                i.key_pressed(Key::ArrowRight),
                i.key_pressed(Key::R),
                i.key_pressed(Key::V),
                i.key_pressed(Key::C),
            )
        });
        if space {
            self.playing = !self.playing;
        }
        if right {
            self.step_event();
        }
        if r {
            self.restart();
        }
        if v {
            self.model.reverse();
        }
        if c {
            let stepped = self.model.sim.is_stepped();
            self.model.colouring = match self.model.colouring {
                Colouring::File => Colouring::Speed,
                Colouring::Speed => Colouring::Species,
                Colouring::Species if stepped => Colouring::Energy,
                Colouring::Species | Colouring::Energy => Colouring::File,
            };
            self.redraw = true;
        }
        if ctx.input(|i| i.key_pressed(Key::B)) && self.model.sim.is_stepped() && D != 1 {
            self.model.bonds = !self.model.bonds;
            self.redraw = true;
        }
    }

    /// One frame at the current speed (1/30 s of wall time), paused.
    fn step_frame(&mut self) {
        self.playing = false;
        let t = self.model.sim.time() + self.speed / 30.0;
        self.model.run_until(t);
        self.redraw = true;
    }

    fn step_event(&mut self) {
        self.playing = false;
        let (what_, one) = (particles::<D>(), particle::<D>());
        self.last_event = match self.model.step_event() {
            None => "nothing will ever happen".to_string(),
            Some(e) => {
                let what = match e.kind {
                    EventKind::DiscDisc { i, j } => format!("{what_} {i} and {j} collide"),
                    EventKind::Reaction { i, j, .. } => format!("{what_} {i} and {j} react"),
                    EventKind::Wall { i, .. } => format!("{one} {i} hits a wall"),
                    EventKind::Barrier { i, barrier, .. } => {
                        format!("{one} {i} meets barrier {barrier}")
                    }
                    EventKind::CellCrossing { i, .. } => format!("{one} {i} changes cell"),
                    EventKind::Slide { i } => {
                        format!("{one} {i} looks again across the sliding boundary")
                    }
                    EventKind::NeighbourList { i } => {
                        format!("{one} {i}'s neighbour list is made again")
                    }
                    EventKind::Thermostat { i } => {
                        format!("{one} {i} is given a new velocity by the thermostat")
                    }
                    EventKind::Step { i, j, hit } => {
                        let how = match hit {
                            StepHit::Entered => "cross a step inward",
                            StepHit::Left => "cross a step outward",
                            StepHit::Repelled => "bounce off a step",
                            StepHit::Held => "are held inside a step",
                        };
                        format!("{what_} {i} and {j} {how}")
                    }
                };
                format!("t = {:.6}: {what}", e.time)
            }
        };
        self.model.sample();
        self.redraw = true;
    }

    fn restart(&mut self) {
        self.model.restart();
        self.last_event.clear();
        self.phase_bounds = None;
        self.rates.collisions = 0;
        self.redraw = true;
    }

    /// Handles screenshot replies and the `--quit-after` timer.
    fn timers(&mut self, ctx: &egui::Context, now: Instant) {
        let images: Vec<_> = ctx.input(|i| {
            i.raw
                .events
                .iter()
                .filter_map(|e| match e {
                    egui::Event::Screenshot { image, .. } => Some(image.clone()),
                    _ => None,
                })
                .collect()
        });
        if let (Some(image), Some(path)) = (images.first(), &self.screenshot) {
            if let Err(e) = save_png(path, image) {
                self.report.borrow_mut().error = Some(format!(
                    "{}: cannot write the screenshot: {e}",
                    path.display()
                ));
            }
            ctx.send_viewport_cmd(ViewportCommand::Close);
            return;
        }
        let Some(after) = self.quit_after else {
            return;
        };
        let elapsed = now.duration_since(self.started);
        match (&self.screenshot, self.screenshot_requested) {
            _ if elapsed < after => ctx.request_repaint_after(after - elapsed),
            (Some(_), None) => {
                ctx.send_viewport_cmd(ViewportCommand::Screenshot(egui::UserData::default()));
                self.screenshot_requested = Some(now);
                ctx.request_repaint();
            }
            (Some(_), Some(asked)) => {
                if now.duration_since(asked) > SCREENSHOT_TIMEOUT {
                    self.report.borrow_mut().error =
                        Some("the window system did not deliver the screenshot".to_string());
                    ctx.send_viewport_cmd(ViewportCommand::Close);
                } else {
                    ctx.request_repaint_after(Duration::from_millis(50));
                }
            }
            (None, _) => ctx.send_viewport_cmd(ViewportCommand::Close),
        }
    }

    fn update_rates(&mut self, now: Instant) {
        let span = now.duration_since(self.rates.start).as_secs_f64();
        if span >= 0.5 {
            let c = self.model.sim.stats().disc_disc;
            let pictures = self.report.borrow().pictures;
            self.rates.fps = pictures.saturating_sub(self.rates.frames) as f64 / span;
            self.rates.collisions_per_second =
                c.saturating_sub(self.rates.collisions) as f64 / span;
            self.rates = Rates {
                start: now,
                frames: pictures,
                collisions: c,
                ..self.rates
            };
        }
    }

    fn controls(&mut self, ui: &mut egui::Ui) {
        ui.horizontal_wrapped(|ui| {
            let label = if self.playing {
                "⏸ Pause"
            } else {
                "▶ Play"
            };
            if ui.button(label).on_hover_text("space").clicked() {
                self.playing = !self.playing;
            }
            if ui
                .button("Step event")
                .on_hover_text("right arrow: run to the next collision")
                .clicked()
            {
                self.step_event();
            }
            if ui
                .button("Step frame")
                .on_hover_text("F: advance by one frame (1/30 s at the current speed)")
                .clicked()
            {
                self.step_frame();
            }
            if ui
                .button("Restart")
                .on_hover_text("R: back to the initial state")
                .clicked()
            {
                self.restart();
            }
            if ui
                .button("Reverse velocities")
                .on_hover_text(format!("V: the {} retrace their paths", particles::<D>()))
                .clicked()
            {
                self.model.reverse();
            }
            ui.separator();
            ui.label("time per second");
            let (lo, hi) = self.speed_range;
            ui.add(
                egui::Slider::new(&mut self.speed, lo..=hi)
                    .logarithmic(true)
                    .custom_formatter(|v, _| format!("{v:.3e}")),
            );
            ui.separator();
            ui.label("colour");
            let before = (self.model.colouring, self.model.bonds);
            for (c, name) in [
                (Colouring::File, "file"),
                (Colouring::Speed, "speed"),
                (Colouring::Species, "species"),
            ] {
                ui.selectable_value(&mut self.model.colouring, c, name);
            }
            // A stepped potential's own views: the energy of each disc's pairs, and the pairs
            // inside a well or shoulder as bonds (not on a line, where the rods of a pair are
            // neighbours anyway).
            if self.model.sim.is_stepped() {
                ui.selectable_value(&mut self.model.colouring, Colouring::Energy, "energy")
                    .on_hover_text(if D == 1 {
                        "potential energy of each rod's pairs: blue bound, grey free, red repelled"
                    } else {
                        "potential energy of each disc's pairs: blue bound, grey free, red repelled"
                    });
                if D != 1 {
                    ui.separator();
                    ui.checkbox(&mut self.model.bonds, "bonds")
                        .on_hover_text(format!(
                            "B: a line between the {} of each pair inside a well or shoulder",
                            particles::<D>()
                        ));
                }
            }
            if (self.model.colouring, self.model.bonds) != before {
                self.redraw = true;
            }
            ui.separator();
            if ui
                .add_enabled(
                    !self.model.trails().tagged().is_empty(),
                    egui::Button::new("Untag all"),
                )
                .clicked()
            {
                for i in self.model.trails().tagged().to_vec() {
                    self.model.toggle_tag(i);
                }
                self.redraw = true;
            }
        });
    }

    fn side_panel(&self, ui: &mut egui::Ui) {
        let stats = self.model.sim.stats();
        let events = stats.disc_disc
            + stats.wall
            + stats.barrier
            + stats.cell_crossing
            + stats.neighbour_list
            + stats.step
            + stats.thermostat;
        egui::Grid::new("counters")
            .num_columns(2)
            .striped(true)
            .show(ui, |ui| {
                let mut row = |name: &str, value: String| {
                    ui.label(name);
                    ui.monospace(value);
                    ui.end_row();
                };
                row(particles::<D>(), self.model.sim.len().to_string());
                row("time", format!("{:.4}", self.model.sim.time()));
                row("events", events.to_string());
                row(
                    &format!("{} collisions", particle::<D>()),
                    stats.disc_disc.to_string(),
                );
                row("wall collisions", stats.wall.to_string());
                row(
                    "collisions / s",
                    format!("{:.0}", self.rates.collisions_per_second),
                );
                row("frames / s", format!("{:.1}", self.rates.fps));
                if self.model.sim.self_gravity().is_some() {
                    let (k, u) = (
                        self.model.sim.kinetic_energy(),
                        self.model.sim.self_gravity_energy(),
                    );
                    row("kinetic energy K", format!("{k:.6}"));
                    row("self-gravity energy U", format!("{u:.6}"));
                    row("K + U", format!("{:.9}", k + u));
                }
                if self.model.sim.is_stepped() {
                    row("step events", stats.step.to_string());
                    row(
                        "potential energy",
                        format!("{:.4}", self.model.sim.potential_energy()),
                    );
                }
                row("tagged", format!("{:?}", self.model.trails().tagged()));
            });
        if !self.last_event.is_empty() {
            ui.label(&self.last_event);
        }
        if let Some(stall) = self.model.stall_message() {
            ui.colored_label(egui::Color32::RED, stall);
        }
        let b = if self.model.sim.is_stepped() {
            ", B bonds"
        } else {
            ""
        };
        if D == 3 {
            ui.small(format!("Drag the picture to turn the view. Keys: space play/pause, right arrow one event, F one frame, R restart, V reverse, C colouring{b}, arrows up/down tilt."));
        } else if D == 1 {
            ui.small("Click a rod to tag it: its dot in the phase plane is ringed; click again to untag. Keys: space play/pause, right arrow one event, F one frame, R restart, V reverse, C colouring.");
        } else {
            ui.small(format!("Click a disc to tag it and draw its path; click again to untag. Keys: space play/pause, right arrow one event, F one frame, R restart, V reverse, C colouring{b}."));
        }
        ui.separator();
        let h = ((ui.available_height() - 3.0 * 24.0) / 3.0).clamp(80.0, 220.0);
        ui.label("temperature kT");
        fixed_plot("temperature", h).include_y(0.0).show(ui, |p| {
            p.line(Line::new(
                "kT",
                PlotPoints::new(self.model.temperature_series()),
            ));
        });
        if self.model.sim.self_gravity().is_some() {
            // The collision virial leaves out gravity's pull, so the sheets' pressure would be
            // that of a gas filling the walled line; their virial theorem is 2<K> = <U>.
            ui.label("virial ratio 2K/U (1 on average)");
            fixed_plot("virial", h)
                .include_y(0.0)
                .include_y(1.5)
                .show(ui, |p| {
                    p.line(Line::new(
                        "2K/U",
                        PlotPoints::new(self.model.virial_series().to_vec()),
                    ));
                });
        } else {
            ui.label(if D == 1 {
                "pressure (virial; a force on a line)"
            } else {
                "pressure (virial)"
            });
            fixed_plot("pressure", h).include_y(0.0).show(ui, |p| {
                p.line(Line::new(
                    "P",
                    PlotPoints::new(self.model.pressure_series().to_vec()),
                ));
            });
        }
        let law = match D {
            1 => "Gaussian",
            3 => "Maxwell",
            _ => "Rayleigh",
        };
        ui.label(if D == 1 {
            format!("velocities against Maxwell-Boltzmann ({law})")
        } else {
            format!("speeds against Maxwell-Boltzmann ({law})")
        });
        let bins = self.model.speeds();
        let width = bins.get(1).map_or(1.0, |b| b.speed - bins[0].speed);
        fixed_plot("speeds", h)
            .legend(Legend::default())
            .show(ui, |p| {
                let bars = bins
                    .iter()
                    .map(|b| Bar::new(b.speed, b.density).width(width))
                    .collect();
                p.bar_chart(BarChart::new("measured", bars).color(Color32::from_rgb(31, 119, 180)));
                let curve: Vec<[f64; 2]> = bins.iter().map(|b| [b.speed, b.rayleigh]).collect();
                p.line(
                    Line::new(law, PlotPoints::new(curve)).color(Color32::from_rgb(214, 39, 40)),
                );
            });
    }

    /// Shows the latest finished picture, and hands the current state to the drawing thread
    /// when it is free.
    fn picture(&mut self, ui: &mut egui::Ui) {
        let ctx = ui.ctx().clone();
        let ppp = ctx.pixels_per_point();
        let avail = ui.available_size();
        let w = (avail.x * ppp).floor().max(1.0) as u32;
        let h = (avail.y * ppp).floor().max(1.0) as u32;
        if let Some(pic) = self.painter.finished() {
            self.show(&ctx, pic);
        }
        if self.shown_size != (w, h) {
            self.redraw = true;
        }
        if self.redraw && !self.painter.busy() {
            self.painter.submit(self.model.scene(), w, h);
            self.redraw = false;
            if self.texture.is_none() {
                // The very first picture: wait for it rather than show an empty window.
                if let Some(pic) = self.painter.wait() {
                    self.show(&ctx, pic);
                }
            }
        }
        let (sw, sh) = self.shown_size;
        let size = egui::vec2(sw as f32 / ppp, sh as f32 / ppp);
        let (rect, response) = ui.allocate_exact_size(size, egui::Sense::click_and_drag());
        if D == 3 && response.dragged() {
            // Half a degree per point: a drag across the picture turns it by a few hundred.
            let d = response.drag_delta();
            self.turn(f64::from(d.x) * -0.5, f64::from(d.y) * 0.5);
            ctx.request_repaint();
        }
        if let Some(t) = &self.texture {
            let uv = egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0));
            ui.painter().image(t.id(), rect, uv, Color32::WHITE);
        }
        if response.clicked() {
            if let Some(pos) = response.interact_pointer_pos() {
                let px = f64::from((pos.x - rect.min.x) * ppp);
                let py = f64::from((pos.y - rect.min.y) * ppp);
                let hit = match &self.scene {
                    AnyScene::Flat(scene) => pick(scene, sw, sh, px, py),
                    AnyScene::Solid(..) => None,
                    AnyScene::Line(scene) => edmd_draw::pick_line(scene, sw, sh, px),
                };
                if let Some(i) = hit {
                    self.model.toggle_tag(i);
                    self.redraw = true;
                    ctx.request_repaint();
                }
            }
        }
    }

    /// On a line, the phase plane: one dot per rod at its position and velocity (the sheets'
    /// positions under self-gravity), in the rods' colours, the tagged rods' dots ringed.
    fn phase_plane(&mut self, ui: &mut egui::Ui) {
        let points = self.model.phase_points();
        let colours = match self.model.scene() {
            AnyScene::Line(s) => s.colours,
            _ => Vec::new(),
        };
        let sheets = self.model.sim.self_gravity().is_some();
        let mut bounds = points.iter().fold(self.phase_bounds, |b, &[x, v]| {
            let [x0, x1, v0, v1] = b.unwrap_or([x, x, v, v]);
            Some([x0.min(x), x1.max(x), v0.min(v), v1.max(v)])
        });
        if !sheets {
            // Rods fill their line: show all of it.
            let l = self.model.sim.sim_box().lengths[0];
            bounds = bounds.map(|[_, _, v0, v1]| [0.0, l, v0, v1]);
        }
        self.phase_bounds = bounds;
        let mut groups: std::collections::BTreeMap<[u8; 3], Vec<[f64; 2]>> = Default::default();
        for (i, &p) in points.iter().enumerate() {
            let c = colours.get(i).copied().unwrap_or([31, 119, 180]);
            groups.entry(c).or_default().push(p);
        }
        let tagged: Vec<[f64; 2]> = self
            .model
            .trails()
            .tagged()
            .iter()
            .filter_map(|&i| points.get(i).copied())
            .collect();
        let radius: f32 = match points.len() {
            0..=100 => 3.5,
            101..=2000 => 2.0,
            _ => 1.2,
        };
        let ring = ui.visuals().strong_text_color();
        let mut plot = Plot::new("phase plane")
            .allow_drag(false)
            .allow_zoom(false)
            .allow_scroll(false)
            .allow_boxed_zoom(false)
            .x_axis_label(if sheets {
                "sheet position (rods' lengths taken out)"
            } else {
                "position x"
            })
            .y_axis_label("velocity v")
            .include_y(0.0);
        if let Some([x0, x1, v0, v1]) = bounds {
            plot = plot.include_x(x0).include_x(x1).include_y(v0).include_y(v1);
        }
        ui.label(format!(
            "phase plane: one dot per {} at (x, v)",
            if sheets { "sheet" } else { "rod" }
        ));
        plot.show(ui, |p| {
            for (c, pts) in groups {
                let [r, g, b] = c;
                p.points(
                    Points::new("", PlotPoints::new(pts))
                        .radius(radius)
                        .color(Color32::from_rgb(r, g, b)),
                );
            }
            if !tagged.is_empty() {
                p.points(
                    Points::new("tagged", PlotPoints::new(tagged))
                        .shape(MarkerShape::Circle)
                        .filled(false)
                        .radius(6.0)
                        .color(ring),
                );
            }
        });
    }

    /// Uploads a finished picture as the texture.
    fn show(&mut self, ctx: &egui::Context, pic: Picture) {
        let t0 = Instant::now();
        let (w, h) = (pic.pixmap.width(), pic.pixmap.height());
        // Every pixel is opaque, so premultiplied and straight alpha agree.
        let image =
            ColorImage::from_rgba_premultiplied([w as usize, h as usize], pic.pixmap.data());
        match &mut self.texture {
            Some(t) => t.set(image, TextureOptions::NEAREST),
            None => self.texture = Some(ctx.load_texture("discs", image, TextureOptions::NEAREST)),
        }
        self.painter.recycle(pic.pixmap);
        self.scene = pic.scene;
        self.shown_size = (w, h);
        let mut r = self.report.borrow_mut();
        r.pictures += 1;
        r.draw += pic.took.as_secs_f64();
        r.upload += t0.elapsed().as_secs_f64();
    }
}

impl<const D: usize> eframe::App for ViewerApp<D> {
    fn update(&mut self, ctx: &egui::Context, _frame: &mut eframe::Frame) {
        let now = Instant::now();
        {
            let mut r = self.report.borrow_mut();
            r.updates += 1;
            r.first.get_or_insert(now);
            r.last = Some(now);
        }
        self.timers(ctx, now);
        self.keys(ctx);
        if self.playing {
            let dt = self.last_frame.map_or(0.0, |t| {
                now.duration_since(t).as_secs_f64().min(MAX_FRAME_DT)
            });
            let t0 = Instant::now();
            self.model
                .run_until(self.model.sim.time() + dt * self.speed);
            self.report.borrow_mut().simulate += t0.elapsed().as_secs_f64();
            if self.model.sim.stalled().is_some() {
                self.playing = false;
            }
            self.redraw = true;
        }
        self.last_frame = Some(now);
        if self.playing && now.duration_since(self.last_sample) >= SAMPLE_EVERY {
            self.model.sample();
            self.last_sample = now;
        }
        self.update_rates(now);

        egui::TopBottomPanel::top("controls").show(ctx, |ui| self.controls(ui));
        egui::SidePanel::right("plots")
            .default_width(340.0)
            .resizable(true)
            .show(ctx, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| self.side_panel(ui));
            });
        let [r, g, b] = OUTSIDE;
        egui::CentralPanel::default()
            .frame(egui::Frame::NONE.fill(Color32::from_rgb(r, g, b)))
            .show(ctx, |ui| {
                if D == 1 {
                    // The line is a low strip; the room beneath it holds the phase plane.
                    let strip = (ui.available_height() * 0.22).clamp(60.0, 160.0);
                    let width = ui.available_width();
                    ui.allocate_ui(egui::vec2(width, strip), |ui| self.picture(ui));
                    egui::Frame::NONE
                        .fill(ctx.style().visuals.panel_fill)
                        .inner_margin(8.0)
                        .show(ui, |ui| self.phase_plane(ui));
                } else {
                    self.picture(ui);
                }
            });
        if self.playing && !self.painter.busy() {
            ctx.request_repaint();
        }
    }
}

/// Writes an egui image as an RGB PNG file.
pub fn save_png(path: &Path, image: &ColorImage) -> std::io::Result<()> {
    let [w, h] = image.size;
    let mut data = Vec::with_capacity(w * h * 3);
    for c in &image.pixels {
        data.extend_from_slice(&[c.r(), c.g(), c.b()]);
    }
    let file = std::io::BufWriter::new(std::fs::File::create(path)?);
    let mut enc = png::Encoder::new(file, w as u32, h as u32);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let mut writer = enc.write_header().map_err(std::io::Error::other)?;
    writer
        .write_image_data(&data)
        .map_err(std::io::Error::other)?;
    writer.finish().map_err(std::io::Error::other)
}

/// A plot of height `h` that the mouse cannot move or zoom (the side panel's plots follow the
/// run).
fn fixed_plot(id: &str, h: f32) -> Plot<'static> {
    Plot::new(id)
        .height(h)
        .allow_drag(false)
        .allow_zoom(false)
        .allow_scroll(false)
        .allow_boxed_zoom(false)
}

/// What the particles are called in dimension `D`: "rods", "discs" or "spheres".
fn particles<const D: usize>() -> &'static str {
    match D {
        1 => "rods",
        3 => "spheres",
        _ => "discs",
    }
}

/// One of [`particles`]: "rod", "disc" or "sphere".
fn particle<const D: usize>() -> &'static str {
    match D {
        1 => "rod",
        3 => "sphere",
        _ => "disc",
    }
}
