//! # edmd-py: the Python binding of edmd
//!
//! The compiled module `edmd._edmd` behind the Python package `edmd` (in `python/edmd`).
//! It is a thin layer: files are read by the CLI's own readers (`edmd_cli::input`), systems
//! made by `edmd gen`'s own function (`edmd_cli::commands::gen::make`), packings by `edmd
//! pack`'s (`edmd_cli::commands::pack::pack`), measurements taken by `edmd run --measure`'s
//! observers, so Python and the command line agree bit for bit. Long runs release the GIL and
//! go in chunks of about 50 ms, checking for Ctrl-C between chunks; where a run stops never
//! changes its trajectory, so the chunks give the uninterrupted run.

mod arrays;
mod gsd;
mod pack;
mod state;

use std::io::Write;
use std::path::{Path, PathBuf};

use edmd_cli::commands::measurements::Measure;
use edmd_core::{Boundary, CollisionRule, MultiContact, Options, OverlapPolicy, Simulation};
use edmd_io::princeton::ColumnOrder;
use edmd_io::Format;
use numpy::PyArray1;
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyTuple};

use state::{State, EVENT_CHUNK};

/// The most trajectory frames, callbacks or samples one run may take (as `edmd run`).
const MAX_STOPS: f64 = 1e6;

/// A simulation of either dimension.
enum Inner {
    Two(State<2>),
    Three(State<3>),
}

/// Runs `$body` with `$s` bound to the `State<D>` inside, whatever the dimension.
macro_rules! each {
    ($inner:expr, $s:ident => $body:expr) => {
        match $inner {
            Inner::Two($s) => $body,
            Inner::Three($s) => $body,
        }
    };
}

/// A user error (bad input, unreadable file): `ValueError` with the CLI's message.
fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// A `boundary=` argument: `None`, `'periodic'` or `'walls'`; `what` starts the error message.
fn parse_boundary(
    boundary: Option<&str>,
    what: &str,
) -> PyResult<Option<edmd_cli::args::BoundaryArg>> {
    use edmd_cli::args::BoundaryArg;
    match boundary {
        None => Ok(None),
        Some("periodic") => Ok(Some(BoundaryArg::Periodic)),
        Some("walls") => Ok(Some(BoundaryArg::Walls)),
        Some(b) => Err(value_error(format!(
            "{what}: expected 'periodic' or 'walls', got '{b}'"
        ))),
    }
}

/// An `anyhow` error from the CLI's functions: its message in one line, as `edmd` prints it.
fn cli_error(e: anyhow::Error) -> PyErr {
    PyValueError::new_err(format!("{e:#}").replace('\n', " "))
}

fn io_error(e: std::io::Error) -> PyErr {
    PyOSError::new_err(e.to_string())
}

use edmd_cli::commands::run::format_name;

fn format_from_name(name: &str) -> Option<Format> {
    match name {
        "course" => Some(Format::Course),
        "princeton" => Some(Format::Princeton(ColumnOrder::RadiusMass)),
        "princeton-mass-radius" => Some(Format::Princeton(ColumnOrder::MassRadius)),
        _ => None,
    }
}

fn parse_rule(rule: &str) -> PyResult<CollisionRule> {
    match rule {
        "elastic" => Ok(CollisionRule::Elastic),
        "swap" => Ok(CollisionRule::Swap),
        _ => Err(value_error(format!(
            "rule: expected 'elastic' or 'swap', got '{rule}'"
        ))),
    }
}

fn options(rule: &str, multi: bool, allow_overlaps: bool) -> PyResult<Options> {
    Ok(Options {
        rule: parse_rule(rule)?,
        overlaps: if allow_overlaps {
            OverlapPolicy::Allow
        } else {
            OverlapPolicy::Refuse
        },
        multi: multi.then(MultiContact::default),
    })
}

/// A simulation of a system read from a file, as `edmd run` builds it: with the CLI's messages,
/// and its clock at the time the file carries (`# edmd time T`).
fn built<const D: usize>(
    name: &str,
    sys: &edmd_io::LoadedSystem<D>,
    opts: Options,
) -> PyResult<Simulation<D>> {
    let mut sim = edmd_cli::input::build(name, sys, opts).map_err(cli_error)?;
    if sys.time != 0.0 {
        sim.start_at(sys.time)
            .map_err(|e| value_error(format!("{name}: {e}")))?;
    }
    Ok(sim)
}

fn boundary_name(b: Boundary) -> &'static str {
    match b {
        Boundary::Periodic => "periodic",
        Boundary::Walls => "walls",
    }
}

/// Checkpoint bytes with the format in the extra bytes, as `edmd run --checkpoint` writes them
/// (so `edmd run` continues a checkpoint written from Python, and the other way round).
fn checkpoint_bytes<const D: usize>(s: &State<D>) -> Vec<u8> {
    s.checkpoint()
}

fn from_checkpoint(bytes: &[u8], what: &str) -> PyResult<Inner> {
    fn load<const D: usize>(bytes: &[u8], what: &str) -> PyResult<State<D>> {
        State::from_checkpoint(bytes).map_err(|e| value_error(format!("{what}: {e}")))
    }
    match edmd_core::checkpoint_dim(bytes) {
        Ok(3) => Ok(Inner::Three(load::<3>(bytes, what)?)),
        Ok(_) => Ok(Inner::Two(load::<2>(bytes, what)?)),
        Err(e) => Err(value_error(format!("{what}: {e}"))),
    }
}

/// A trajectory being written during `run`.
enum Trajectory {
    Xyz(std::io::BufWriter<std::fs::File>),
    Gsd(gsd::Writer),
}

impl Trajectory {
    fn create(path: &Path) -> PyResult<Self> {
        let file = std::fs::File::create(path)
            .map_err(|e| value_error(format!("{}: cannot write: {e}", path.display())))?;
        Ok(match extension(path).as_deref() {
            Some("gsd") => Trajectory::Gsd(gsd::Writer::new(file).map_err(io_error)?),
            Some("xyz") | Some("extxyz") => Trajectory::Xyz(std::io::BufWriter::new(file)),
            _ => {
                return Err(value_error(format!(
                    "{}: trajectories are written as .xyz or .gsd files",
                    path.display()
                )))
            }
        })
    }

    fn frame(&mut self, inner: &Inner) -> PyResult<()> {
        each!(inner, s => match self {
            Trajectory::Xyz(w) => {
                edmd_io::xyz::write_frame(w, &s.sim.discs(), s.sim.sim_box(), s.sim.time())
                    .map_err(io_error)
            }
            Trajectory::Gsd(w) => w.frame(&s.sim).map_err(io_error),
        })
    }

    fn finish(self) -> PyResult<()> {
        match self {
            Trajectory::Xyz(mut w) => w.flush().map_err(io_error),
            Trajectory::Gsd(w) => w.finish().map(drop).map_err(io_error),
        }
    }
}

fn extension(path: &Path) -> Option<String> {
    path.extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
}

/// An exact event-driven simulation of hard discs (2D) or spheres (3D).
///
/// Make one with `Simulation.from_file`, `Simulation.from_arrays` or a generator in
/// `edmd.gen`, advance it with `run(until=T)` or `run(events=N)`, and read its state as numpy
/// arrays (`positions`, `velocities`, ...). Pickling and `copy.deepcopy` keep the exact state:
/// a restored simulation continues bit for bit like the original.
///
/// Example:
///
/// >>> import edmd
/// >>> sim = edmd.gen.fluid(n=100, packing=0.3, seed=1)
/// >>> sim.run(until=10.0)
/// >>> sim.positions.shape
/// (100, 2)
#[pyclass(module = "edmd", name = "Simulation")]
struct PySimulation {
    inner: Inner,
}

impl PySimulation {
    fn time(&self) -> f64 {
        each!(&self.inner, s => s.sim.time())
    }

    fn lengths(&self) -> Vec<f64> {
        each!(&self.inner, s => s.sim.sim_box().lengths.to_vec())
    }

    fn boundaries(&self) -> Vec<&'static str> {
        each!(&self.inner, s => s.sim.sim_box().boundaries.iter().map(|b| boundary_name(*b)).collect())
    }
}

#[pymethods]
impl PySimulation {
    /// Reads a data file, as `edmd run FILE` does: the course format, the Princeton format
    /// (with edmd's extension: 3D files, walls or periodic boundaries, barriers, species) or an
    /// `edmd run --checkpoint` file.
    ///
    /// Args:
    ///     path: the file.
    ///     format: "course" or "princeton"; detected when None.
    ///     columns: "radius-mass" (default) or "mass-radius" for Princeton files.
    ///     rule: "elastic" or "swap" (the course's rule); by default swap for course files (as
    ///         the course's `particles` and `edmd run` do), elastic for the others.
    ///     multi: multi-disc collisions (elastic rule only).
    ///     allow_overlaps: run overlapping input anyway (see `edmd run --allow-overlaps`).
    ///
    /// Raises:
    ///     ValueError: the file cannot be read or is wrong; the message names the line, as
    ///         `edmd run` does.
    ///
    /// >>> sim = edmd.Simulation.from_file("examples/data/gas-300.txt")
    #[staticmethod]
    #[pyo3(signature = (path, *, format=None, columns=None, rule=None, multi=false, allow_overlaps=false))]
    fn from_file(
        path: PathBuf,
        format: Option<&str>,
        columns: Option<&str>,
        rule: Option<&str>,
        multi: bool,
        allow_overlaps: bool,
    ) -> PyResult<Self> {
        let name = path.to_string_lossy().into_owned();
        // The file's own rule unless told: swap for course files.
        let opts = |format: Format| {
            let default = if format == Format::Course {
                "swap"
            } else {
                "elastic"
            };
            options(rule.unwrap_or(default), multi, allow_overlaps)
        };
        // The CLI's reader: only a file that starts with the magic number, and bounded in size.
        if let Some(bytes) = edmd_cli::commands::run::read_checkpoint(&path).map_err(cli_error)? {
            if format.is_some() || columns.is_some() || rule.is_some() || multi || allow_overlaps {
                return Err(value_error(format!(
                    "{name}: a checkpoint carries its run's options: drop format, columns, rule, multi and allow_overlaps"
                )));
            }
            return Ok(PySimulation {
                inner: from_checkpoint(&bytes, &name)?,
            });
        }
        let order = match columns {
            None | Some("radius-mass") => ColumnOrder::RadiusMass,
            Some("mass-radius") => ColumnOrder::MassRadius,
            Some(c) => {
                return Err(value_error(format!(
                    "columns: expected 'radius-mass' or 'mass-radius', got '{c}'"
                )))
            }
        };
        let format = match format {
            None => None,
            Some("course") => Some(Format::Course),
            Some("princeton") => Some(Format::Princeton(order)),
            Some(f) => {
                return Err(value_error(format!(
                    "format: expected 'course' or 'princeton', got '{f}'"
                )))
            }
        };
        let text = edmd_cli::input::read_text(&name).map_err(cli_error)?;
        let loaded = edmd_cli::input::load_any(&name, &text, format, order).map_err(cli_error)?;
        let inner = match loaded {
            edmd_io::AnyLoaded::Two(sys) => {
                if columns.is_some() && sys.format == Format::Course {
                    return Err(value_error(format!(
                        "{name}: columns applies to the Princeton format, and this is a course file (N, R, Lx Ly, then x y u v)"
                    )));
                }
                Inner::Two(State::new(
                    built(&name, &sys, opts(sys.format)?)?,
                    sys.format,
                ))
            }
            edmd_io::AnyLoaded::Three(sys) => Inner::Three(State::new(
                built(&name, &sys, opts(sys.format)?)?,
                sys.format,
            )),
        };
        Ok(PySimulation { inner })
    }

    /// Builds a simulation from arrays, at time 0.
    ///
    /// Args:
    ///     positions: (N, 2) discs or (N, 3) spheres.
    ///     velocities: the same shape.
    ///     radii: one radius, or N.
    ///     masses: one mass, or N; 1 when None.
    ///     box: the box lengths (Lx, Ly) or (Lx, Ly, Lz); the box spans [0, L) on each axis.
    ///     boundary: "periodic" or "walls", or one per axis.
    ///     species: N small non-negative integers (labels the engine carries along).
    ///     rule: "elastic" or "swap".
    ///     multi: multi-disc collisions.
    ///     allow_overlaps: accept overlapping discs and move discs outside walls inside.
    ///
    /// Raises:
    ///     ValueError: shapes that do not match, non-finite values, overlapping discs, discs
    ///         outside the box, a bad box.
    ///
    /// >>> import numpy as np
    /// >>> sim = edmd.Simulation.from_arrays([[2.0, 5.0], [8.0, 5.0]], [[1.0, 0.0], [-1.0, 0.0]],
    /// ...                                   radii=1.0, box=(10.0, 10.0), boundary="walls")
    /// >>> sim.run(until=2.5)
    /// >>> sim.stats["disc_disc"]
    /// 1
    #[staticmethod]
    #[pyo3(signature = (positions, velocities, radii, masses=None, r#box=None, boundary=None, species=None, rule="elastic", multi=false, allow_overlaps=false))]
    #[allow(clippy::too_many_arguments)]
    fn from_arrays(
        positions: &Bound<'_, PyAny>,
        velocities: &Bound<'_, PyAny>,
        radii: &Bound<'_, PyAny>,
        masses: Option<&Bound<'_, PyAny>>,
        r#box: Option<Vec<f64>>,
        boundary: Option<&Bound<'_, PyAny>>,
        species: Option<&Bound<'_, PyAny>>,
        rule: &str,
        multi: bool,
        allow_overlaps: bool,
    ) -> PyResult<Self> {
        let input = arrays::Input::new(
            positions, velocities, radii, masses, r#box, boundary, species,
        )?;
        let opts = options(rule, multi, allow_overlaps)?;
        let inner = match input.dim {
            3 => Inner::Three(State::new(
                input.build::<3>(opts)?,
                Format::Princeton(ColumnOrder::RadiusMass),
            )),
            _ => Inner::Two(State::new(
                input.build::<2>(opts)?,
                Format::Princeton(ColumnOrder::RadiusMass),
            )),
        };
        Ok(PySimulation { inner })
    }

    /// Advances the simulation, with the GIL released.
    ///
    /// Give exactly one of `until` (a time, at or after `time`) or `events` (a number of
    /// events: collisions, wall bounces and cell crossings). Ctrl-C stops the run within a
    /// fraction of a second with `KeyboardInterrupt`, leaving a consistent state at some time
    /// before `until`. Stopping never changes the trajectory: a run to T in pieces ends in
    /// exactly the state of one run to T, and in the state `edmd run --until T` writes.
    ///
    /// Args:
    ///     until: end time.
    ///     events: number of events to process.
    ///     trajectory: a file (".xyz" extended XYZ or ".gsd" HOOMD) to which a frame is
    ///         written at every multiple of `every` (needs `until`).
    ///     every: time between trajectory frames.
    ///     callback: called as `callback(sim)` at every multiple of `callback_every` after the
    ///         current time (needs `until`); an exception in it stops the run.
    ///     callback_every: time between callbacks.
    ///
    /// >>> sim.run(until=sim.time + 5.0, trajectory="t.gsd", every=0.5)
    #[pyo3(signature = (until=None, *, events=None, trajectory=None, every=None, callback=None, callback_every=None))]
    #[allow(clippy::too_many_arguments)]
    fn run(
        slf: &Bound<'_, Self>,
        until: Option<f64>,
        events: Option<u64>,
        trajectory: Option<PathBuf>,
        every: Option<f64>,
        callback: Option<Bound<'_, PyAny>>,
        callback_every: Option<f64>,
    ) -> PyResult<()> {
        let py = slf.py();
        let now = slf.borrow().time();
        match (until, events) {
            (Some(_), Some(_)) | (None, None) => {
                return Err(value_error("run: give either until or events"))
            }
            (None, Some(n)) => {
                if trajectory.is_some() || every.is_some() || callback.is_some() {
                    return Err(value_error(
                        "run: trajectory, every and callback need until (they are timed in simulated time)",
                    ));
                }
                return run_events(slf, n);
            }
            (Some(t), None) if !t.is_finite() => {
                return Err(value_error(format!("until: {t} is not a finite time")))
            }
            (Some(t), None) if t < now => {
                return Err(value_error(format!(
                    "until: {t} is before the current time t = {now}"
                )))
            }
            _ => {}
        }
        let until = until.expect("checked");
        let positive = |name: &str, dt: Option<f64>| -> PyResult<Option<f64>> {
            match dt {
                Some(d) if !(d.is_finite() && d > 0.0) => {
                    Err(value_error(format!("{name}: {d} is not a positive time")))
                }
                Some(d) if (until - now) / d > MAX_STOPS => Err(value_error(format!(
                    "{name}: {:.3e} stops to t = {until} is too many (at most {MAX_STOPS:.0})",
                    (until - now) / d
                ))),
                _ => Ok(dt),
            }
        };
        let every = positive("every", every)?;
        let callback_every = positive("callback_every", callback_every)?;
        if trajectory.is_some() != every.is_some() {
            return Err(value_error("run: trajectory and every go together"));
        }
        if callback.is_some() != callback_every.is_some() {
            return Err(value_error("run: callback and callback_every go together"));
        }
        if let Some(c) = &callback {
            if !c.is_callable() {
                return Err(value_error("callback: not callable"));
            }
        }
        let mut traj = match &trajectory {
            Some(p) => Some(Trajectory::create(p)?),
            None => None,
        };
        // Frames at whole multiples of `every` in absolute time (as `edmd run --every`),
        // callbacks at the multiples of `callback_every` after now.
        let mut frame_k = every.map_or(0.0, |dt| (now / dt).ceil());
        let mut call_k = callback_every.map_or(0.0, |dt| (now / dt).floor() + 1.0);
        let mut span = 0.0;
        loop {
            let next_frame = every.map(|dt| frame_k * dt).filter(|t| *t <= until);
            let next_call = callback_every.map(|dt| call_k * dt).filter(|t| *t <= until);
            let next_sample = each!(&slf.borrow().inner, s => s
                .measuring
                .as_ref()
                .map(|m| m.next_sample()))
            .filter(|t| *t <= until);
            let next = [next_frame, next_call, next_sample]
                .into_iter()
                .flatten()
                .fold(f64::INFINITY, f64::min);
            let last = next > until;
            let target = if last { until } else { next };
            advance(slf, target, &mut span)?;
            if last {
                break;
            }
            if next_frame == Some(next) {
                traj.as_mut()
                    .expect("frames with a trajectory")
                    .frame(&slf.borrow().inner)?;
                frame_k += 1.0;
            }
            if next_sample == Some(next) {
                each!(&mut slf.borrow_mut().inner, s => s.sample_if_due());
            }
            if next_call == Some(next) {
                callback
                    .as_ref()
                    .expect("calls with a callback")
                    .call1((slf,))?;
                call_k += 1.0;
            }
        }
        if let Some(t) = traj {
            t.finish()?;
        }
        let _ = py;
        Ok(())
    }

    /// Attaches measurements, sampled every `every` of simulated time during `run`.
    ///
    /// The names are those of `edmd run --measure`: "temperature", "pressure" (wall and
    /// virial, Z = PA/NkT with block errors), "collisions" (collision frequency, free paths
    /// and times), "speeds" (against the Maxwell-Boltzmann law), "msd", "species". Events are
    /// watched in Rust; samples are taken at `start + k * every` by `run(until=...)` (not by
    /// `run(events=...)`, which is not timed); `results()` gives what was measured. Attaching
    /// again starts afresh. Pickles and checkpoints keep the measurements under way.
    ///
    /// >>> sim.measure("pressure", "speeds", every=1.0)
    /// >>> sim.run(until=sim.time + 10.0)
    /// >>> sim.results()["pressure"]["Z"]["value"]
    #[pyo3(signature = (*names, every))]
    fn measure(&mut self, names: &Bound<'_, PyTuple>, every: f64) -> PyResult<()> {
        use clap::ValueEnum;
        if !(every.is_finite() && every > 0.0) {
            return Err(value_error(format!(
                "every: {every} is not a positive time"
            )));
        }
        let mut which = Vec::new();
        for n in names.iter() {
            let name: String = n.extract()?;
            let m = Measure::from_str(&name, true).map_err(|_| {
                value_error(format!(
                    "measure: unknown measurement '{name}' (one of: temperature, pressure, collisions, speeds, msd, species)"
                ))
            })?;
            which.push(m);
        }
        if which.is_empty() {
            return Err(value_error("measure: name at least one measurement"));
        }
        each!(&mut self.inner, s => s.measure(&which, every));
        Ok(())
    }

    /// What the attached measurements found: a dict with one summary per measurement (the
    /// same numbers as `edmd run --measure --json`, estimates as {"value", "error", "blocks"})
    /// and "tables": the time series and histograms as dicts of numpy arrays, keyed by the
    /// CSV file `edmd run` would write ("temperature", "pressure", "speeds", ...).
    fn results<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let Some((summary, tables)) = each!(&self.inner, s => s.results()) else {
            return Err(value_error(
                "results: no measurements attached (call measure first)",
            ));
        };
        let json = py.import("json")?;
        let out = json
            .call_method1("loads", (summary.to_string(),))?
            .cast_into::<PyDict>()?;
        let t = PyDict::new(py);
        for table in tables {
            let cols = PyDict::new(py);
            for (k, h) in table.header.iter().enumerate() {
                let col: Vec<f64> = table.rows.iter().map(|r| r[k]).collect();
                cols.set_item(h, PyArray1::from_vec(py, col))?;
            }
            t.set_item(table.file.trim_end_matches(".csv"), cols)?;
        }
        out.set_item("tables", t)?;
        Ok(out)
    }

    /// Writes the current state to a file.
    ///
    /// The format is `format` if given, else from the extension: ".xyz" (an extended XYZ
    /// frame), ".gsd" (a HOOMD GSD frame), ".ck" or ".checkpoint" (an exact checkpoint that
    /// `edmd run` and `Simulation.from_file` continue bit for bit), else the format the
    /// simulation was read in ("course" or "princeton"; "princeton" for arrays and
    /// generators). The file appears whole or not at all.
    ///
    /// >>> sim.write("state.txt")
    #[pyo3(signature = (path, *, format=None))]
    fn write(&self, path: PathBuf, format: Option<&str>) -> PyResult<()> {
        let kind = match format {
            Some(f) => f.to_string(),
            None => match extension(&path).as_deref() {
                Some("xyz") | Some("extxyz") => "xyz".into(),
                Some("gsd") => "gsd".into(),
                Some("ck") | Some("checkpoint") => "checkpoint".into(),
                _ => each!(&self.inner, s => format_name(s.format)).into(),
            },
        };
        let mut f = edmd_cli::output::AtomicFile::create(&path).map_err(cli_error)?;
        let w = f.writer();
        let written = each!(&self.inner, s => {
            let discs = s.sim.discs();
            match kind.as_str() {
                "xyz" => edmd_io::xyz::write_frame(w, &discs, s.sim.sim_box(), s.sim.time())
                    .map_err(io_error),
                "gsd" => gsd::Writer::to(std::io::Cursor::new(Vec::new()))
                    .and_then(|mut g| {
                        g.frame(&s.sim)?;
                        g.finish()
                    })
                    .and_then(|c| w.write_all(&c.into_inner()))
                    .map_err(io_error),
                "checkpoint" => w.write_all(&checkpoint_bytes(s)).map_err(io_error),
                other => match format_from_name(other) {
                    Some(Format::Course) if s.sim.sim_box().lengths.len() == 2 => {
                        let flat: Vec<edmd_core::Disc> = discs.iter().map(|d| d.with_dim()).collect();
                        let b = s.sim.sim_box();
                        let flat_box = edmd_core::SimBox {
                            lengths: [b.lengths[0], b.lengths[1]],
                            boundaries: [b.boundaries[0], b.boundaries[1]],
                        };
                        match edmd_io::course::fits(&flat, &flat_box, s.sim.barriers()) {
                            Ok(()) => edmd_io::course::write(w, &flat, &flat_box).map_err(io_error),
                            Err(why) => Err(value_error(format!(
                                "{}: cannot write the course format: {why}",
                                path.display()
                            ))),
                        }
                    }
                    Some(Format::Course) => Err(value_error(
                        "the course format holds 2D systems only",
                    )),
                    Some(fmt) => edmd_io::write(w, &discs, s.sim.sim_box(), s.sim.barriers(), fmt, s.sim.time())
                        .map_err(io_error),
                    None => Err(value_error(format!(
                        "format: expected 'princeton', 'princeton-mass-radius', 'course', 'xyz', 'gsd' or 'checkpoint', got '{other}'"
                    ))),
                },
            }
        });
        written?;
        f.commit().map_err(cli_error)
    }

    /// The exact state as bytes (an `edmd run --checkpoint` file's contents).
    fn checkpoint<'py>(&self, py: Python<'py>) -> Bound<'py, PyBytes> {
        let bytes = each!(&self.inner, s => checkpoint_bytes(s));
        PyBytes::new(py, &bytes)
    }

    /// A simulation continued from `checkpoint()` bytes.
    #[staticmethod]
    fn from_checkpoint(data: &[u8]) -> PyResult<Self> {
        Ok(PySimulation {
            inner: from_checkpoint(data, "checkpoint")?,
        })
    }

    /// Pickling keeps the exact state, measurements under way included.
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> PyResult<(Bound<'py, PyAny>, (Bound<'py, PyBytes>,))> {
        let py = slf.py();
        let restore = py.import("edmd._edmd")?.getattr("_restore")?;
        Ok((restore, (slf.borrow().checkpoint(py),)))
    }

    /// Positions at the current time, folded into the box on periodic axes: (N, dim) float64.
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        each!(&self.inner, s => arrays::matrix(py, &s.sim, |i| s.sim.position(i).0))
    }

    /// Positions not folded back into the box: the displacement since time 0 is
    /// `unwrapped_positions - initial positions`. (N, dim) float64.
    #[getter]
    fn unwrapped_positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        each!(&self.inner, s => arrays::matrix(py, &s.sim, |i| s.sim.unwrapped_position(i).0))
    }

    /// Velocities: (N, dim) float64. Assigning an array of that shape changes every velocity
    /// at the current time and schedules everything again.
    #[getter]
    fn velocities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        each!(&self.inner, s => arrays::matrix(py, &s.sim, |i| s.sim.velocity(i).0))
    }

    #[setter]
    fn set_velocities(&mut self, v: &Bound<'_, PyAny>) -> PyResult<()> {
        each!(&mut self.inner, s => arrays::set_velocities(&mut s.sim, v))
    }

    /// Radii: (N,) float64.
    #[getter]
    fn radii<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let v = each!(&self.inner, s => (0..s.sim.len()).map(|i| s.sim.radius(i)).collect());
        PyArray1::from_vec(py, v)
    }

    /// Masses: (N,) float64.
    #[getter]
    fn masses<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let v = each!(&self.inner, s => (0..s.sim.len()).map(|i| s.sim.mass(i)).collect());
        PyArray1::from_vec(py, v)
    }

    /// Species labels: (N,) uint16.
    #[getter]
    fn species<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<u16>> {
        let v = each!(&self.inner, s => (0..s.sim.len()).map(|i| s.sim.species(i)).collect());
        PyArray1::from_vec(py, v)
    }

    /// Current time.
    #[getter(time)]
    fn get_time(&self) -> f64 {
        self.time()
    }

    /// Box lengths, a tuple (Lx, Ly) or (Lx, Ly, Lz).
    #[getter(r#box)]
    fn get_box<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        PyTuple::new(py, self.lengths())
    }

    /// Boundary of each axis: a tuple of "periodic" or "walls".
    #[getter]
    fn boundary<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        PyTuple::new(py, self.boundaries())
    }

    /// 2 (discs) or 3 (spheres).
    #[getter]
    fn dim(&self) -> usize {
        match self.inner {
            Inner::Two(_) => 2,
            Inner::Three(_) => 3,
        }
    }

    /// Number of discs.
    #[getter]
    fn n(&self) -> usize {
        each!(&self.inner, s => s.sim.len())
    }

    fn __len__(&self) -> usize {
        self.n()
    }

    /// Total kinetic energy, sum m v^2 / 2.
    #[getter]
    fn kinetic_energy(&self) -> f64 {
        each!(&self.inner, s => s.sim.kinetic_energy())
    }

    /// Event counts so far: a dict with "disc_disc", "wall", "cell_crossing", "stale" and
    /// "barrier" (as `edmd run` reports them).
    #[getter]
    fn stats<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let st = each!(&self.inner, s => s.sim.stats());
        let d = PyDict::new(py);
        d.set_item("disc_disc", st.disc_disc)?;
        d.set_item("wall", st.wall)?;
        d.set_item("cell_crossing", st.cell_crossing)?;
        d.set_item("stale", st.stale)?;
        d.set_item("barrier", st.barrier)?;
        Ok(d)
    }

    fn __repr__(&self) -> String {
        let lengths: Vec<String> = self.lengths().iter().map(|l| format!("{l:?}")).collect();
        let boundaries: Vec<String> = self.boundaries().iter().map(|b| format!("'{b}'")).collect();
        format!(
            "Simulation(dim={}, n={}, time={:?}, box=({}), boundary=({}))",
            self.dim(),
            self.n(),
            self.time(),
            lengths.join(", "),
            boundaries.join(", ")
        )
    }
}

/// A `ValueError` naming the discs when the run's clock stopped advancing (the engine then
/// stays at that time: a box filled with touching discs, say).
fn stalled(slf: &Bound<'_, PySimulation>) -> PyResult<()> {
    match each!(&slf.borrow().inner, s => s.stalled()) {
        Some(why) => Err(value_error(why)),
        None => Ok(()),
    }
}

/// Runs to `t` in chunks with the GIL released, checking for Ctrl-C between them.
fn advance(slf: &Bound<'_, PySimulation>, t: f64, span: &mut f64) -> PyResult<()> {
    let py = slf.py();
    loop {
        let done = {
            let mut guard = slf.borrow_mut();
            let inner = &mut guard.inner;
            py.detach(|| each!(inner, s => s.chunk_until(t, span)))
        };
        stalled(slf)?;
        py.check_signals()?;
        if done {
            return Ok(());
        }
    }
}

/// `run(events=n)`: chunks of events with the GIL released, checking for Ctrl-C between them.
fn run_events(slf: &Bound<'_, PySimulation>, n: u64) -> PyResult<()> {
    let py = slf.py();
    let mut left = n;
    while left > 0 {
        let k = left.min(EVENT_CHUNK);
        let got = {
            let mut guard = slf.borrow_mut();
            let inner = &mut guard.inner;
            py.detach(|| each!(inner, s => s.run_events(k)))
        };
        stalled(slf)?;
        py.check_signals()?;
        if got < k {
            break;
        }
        left -= k;
    }
    Ok(())
}

/// Unpickles a simulation (see `Simulation.__reduce__`).
#[pyfunction]
fn _restore(data: &[u8]) -> PyResult<PySimulation> {
    PySimulation::from_checkpoint(data)
}

/// Makes a system as `edmd gen KIND` does (same checks, messages and seeds) and returns it as
/// a simulation. Called by the functions in `edmd.gen`.
#[pyfunction]
#[pyo3(signature = (kind, *, dim=2, seed=1, course=false, n=None, radius=None, speed=None, mass=None, kt=None, packing=None, boundary=None, angle=None, impact=None, region=None, big_radius=None, big_mass=None, size_ratio=None, fraction_large=None, spread=None, rule="elastic", multi=false))]
#[allow(clippy::too_many_arguments)]
fn _generate(
    kind: &str,
    dim: i64,
    seed: u64,
    course: bool,
    n: Option<i64>,
    radius: Option<f64>,
    speed: Option<f64>,
    mass: Option<f64>,
    kt: Option<f64>,
    packing: Option<f64>,
    boundary: Option<&str>,
    angle: Option<f64>,
    impact: Option<f64>,
    region: Option<f64>,
    big_radius: Option<f64>,
    big_mass: Option<f64>,
    size_ratio: Option<f64>,
    fraction_large: Option<f64>,
    spread: Option<f64>,
    rule: &str,
    multi: bool,
) -> PyResult<PySimulation> {
    use edmd_cli::commands::gen::{make, GenArgs, Generated};
    let dim = edmd_cli::args::parse_dim(&dim.to_string()).map_err(value_error)?;
    let boundary = parse_boundary(boundary, "boundary")?;
    let opts = options(rule, multi, false)?;
    let args = GenArgs {
        kind: kind.to_string(),
        output: String::new(),
        dim,
        seed,
        course,
        n,
        radius,
        speed,
        mass,
        kt,
        packing,
        boundary,
        angle,
        impact,
        region,
        big_radius,
        big_mass,
        size_ratio,
        fraction_large,
        spread,
    };
    match make(&args).map_err(cli_error)? {
        Generated::Two(system, format) => {
            let sim = Simulation::from_system(&system, opts)
                .map_err(|e| value_error(format!("gen {kind}: {e}")))?;
            Ok(PySimulation {
                inner: Inner::Two(State::new(sim, format)),
            })
        }
        Generated::Three(system) => {
            let sim = Simulation::from_system(&system, opts)
                .map_err(|e| value_error(format!("gen {kind}: {e}")))?;
            Ok(PySimulation {
                inner: Inner::Three(State::new(sim, Format::Princeton(ColumnOrder::RadiusMass))),
            })
        }
    }
}

/// The compiled part of the `edmd` package.
#[pymodule]
fn _edmd(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PySimulation>()?;
    m.add_function(wrap_pyfunction!(_restore, m)?)?;
    m.add_function(wrap_pyfunction!(_generate, m)?)?;
    m.add_function(wrap_pyfunction!(pack::pack, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
