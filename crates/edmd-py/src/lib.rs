//! # edmd-py: the Python binding of edmd
//!
//! The compiled module `edmd._edmd` behind the Python package `edmd` (in `python/edmd`).
//! It is a thin front door over the `edmd` library, as the command line is: files are read by
//! its readers (`edmd::input`), systems made by `edmd::gen::make`, packings by
//! `edmd::pack::pack`, measurements taken by `edmd::measure`'s observers and checkpoints made by
//! `edmd::checkpoint`, so Python and the command line agree bit for bit. Long runs release the GIL and
//! go in chunks of about 50 ms, checking for Ctrl-C between chunks; where a run stops never
//! changes its trajectory, so the chunks give the uninterrupted run.

mod args;
mod arrays;
mod gravity;
mod pack;
mod potential;
mod reactions;
mod restitution;
mod ring;
mod shear;
mod sheets;
mod state;

use std::io::Write;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

use edmd::measure::Measure;
use edmd::output::AtomicFile;
use edmd_core::{Boundary, CollisionRule, MultiContact, Options, OverlapPolicy, Simulation};
use edmd_io::princeton::ColumnOrder;
use edmd_io::Format;
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::{PyOSError, PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyTuple};

use args::num;
use state::{State, EVENT_CHUNK};

/// The most trajectory frames, callbacks or samples one run may take: `edmd run`'s limit.
use edmd::checkpoint::MAX_STOPS;

/// The largest trajectory file one run may write, as estimated before it starts (10 GB): a
/// typing slip in `every` or a huge system should be refused at once, not fill the disc.
const MAX_TRAJECTORY_BYTES: f64 = 1e10;

/// A simulation of any dimension.
enum Inner {
    One(State<1>),
    Two(State<2>),
    Three(State<3>),
}

/// Runs `$body` with `$s` bound to the `State<D>` inside, whatever the dimension.
macro_rules! each {
    ($inner:expr, $s:ident => $body:expr) => {
        match $inner {
            Inner::One($s) => $body,
            Inner::Two($s) => $body,
            Inner::Three($s) => $body,
        }
    };
}

/// A user error (bad input, unreadable file): `ValueError` with the CLI's message.
/// Numbers in the message are kept short (`1e300`, not 301 digits: see
/// [`args::shorten_numbers`]), whoever wrote it.
fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(args::shorten_numbers(&e.to_string()))
}

/// A `boundary=` argument: `None`, `'periodic'` or `'walls'`; `what` starts the error message.
fn parse_boundary(
    boundary: Option<&str>,
    what: &str,
) -> PyResult<Option<edmd::options::BoundaryArg>> {
    use edmd::options::BoundaryArg;
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
    value_error(format!("{e:#}").replace('\n', " "))
}

fn io_error(e: std::io::Error) -> PyErr {
    PyOSError::new_err(e.to_string())
}

/// Runs `f`, turning a panic (a defect in edmd, never the user's doing) into a `RuntimeError`
/// that says so, rather than the `PanicException` PyO3 would raise, which Python code does not
/// expect (it is not an `Exception`).
fn guarded<T>(what: &str, f: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(r) => r,
        Err(payload) => {
            let why = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown".into());
            Err(PyRuntimeError::new_err(format!(
                "{what}: internal error in edmd ({why}); please report it. The simulation may be \
                 left in an inconsistent state"
            )))
        }
    }
}

use edmd::checkpoint::format_name;

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
    seed: u64,
) -> PyResult<Simulation<D>> {
    edmd::input::build_seeded(name, sys, opts, seed).map_err(cli_error)
}

fn boundary_name(b: Boundary) -> &'static str {
    match b {
        Boundary::Periodic => "periodic",
        Boundary::Walls => "walls",
    }
}

/// Checkpoint bytes with the format in the extra bytes, as `edmd run --checkpoint` writes them
/// (so `edmd run` continues a checkpoint written from Python, and the other way round).
fn checkpoint_bytes<const D: usize>(s: &State<D>) -> PyResult<Vec<u8>> {
    s.checkpoint().map_err(PyRuntimeError::new_err)
}

fn from_checkpoint(bytes: &[u8], what: &str) -> PyResult<Inner> {
    fn load<const D: usize>(bytes: &[u8], what: &str) -> PyResult<State<D>> {
        State::from_checkpoint(bytes).map_err(|e| value_error(format!("{what}: {e}")))
    }
    match edmd_core::checkpoint_dim(bytes) {
        Ok(3) => Ok(Inner::Three(load::<3>(bytes, what)?)),
        Ok(1) => Ok(Inner::One(load::<1>(bytes, what)?)),
        Ok(_) => Ok(Inner::Two(load::<2>(bytes, what)?)),
        Err(e) => Err(value_error(format!("{what}: {e}"))),
    }
}

/// What a trajectory file holds, from its extension.
#[derive(Clone, Copy, PartialEq)]
enum TrajectoryKind {
    Xyz,
    Gsd,
}

fn trajectory_kind(path: &Path) -> PyResult<TrajectoryKind> {
    match extension(path).as_deref() {
        Some("gsd") => Ok(TrajectoryKind::Gsd),
        Some("xyz") | Some("extxyz") => Ok(TrajectoryKind::Xyz),
        _ => Err(value_error(format!(
            "trajectory: {}: trajectories are written as .xyz or .gsd files",
            path.display()
        ))),
    }
}

/// True for a path that exists and is neither a regular file nor a folder (a device, a FIFO):
/// `AtomicFile` writes those in place.
fn is_special(path: &Path) -> bool {
    std::fs::metadata(edmd::output::resolve_links(path)).is_ok_and(|m| !m.is_file() && !m.is_dir())
}

/// Refuses a trajectory that cannot be written or would be absurdly large, before anything is
/// created: the estimate is `frames` frames of the size of one frame of this system.
fn check_trajectory(path: &Path, kind: TrajectoryKind, frames: f64, inner: &Inner) -> PyResult<()> {
    edmd::output::check_file_destinations(&[("trajectory", path)]).map_err(cli_error)?;
    if kind == TrajectoryKind::Gsd && is_special(path) {
        return Err(value_error(format!(
            "trajectory: {}: a GSD trajectory needs a regular file (its index is written at the end); write .xyz to a device or a pipe",
            path.display()
        )));
    }
    let per_frame = each!(inner, s => frame_bytes(&s.sim, kind))?;
    let total = frames * per_frame;
    if total > MAX_TRAJECTORY_BYTES {
        return Err(value_error(format!(
            "trajectory: {}: {frames:.0} frames of about {per_frame:.0} bytes each make about {total:.3e} bytes, more than the {MAX_TRAJECTORY_BYTES:.0e} bytes (10 GB) a run may write: take a larger every or a shorter run",
            path.display()
        )));
    }
    Ok(())
}

/// The size of one trajectory frame of `sim`, in bytes: for extended XYZ, measured on the first
/// 100 discs and scaled to all (a frame of millions of discs is not written just to count it);
/// for GSD, the fixed sizes of the chunks (48 bytes a particle) and their index entries.
fn frame_bytes<const D: usize>(sim: &Simulation<D>, kind: TrajectoryKind) -> PyResult<f64> {
    let n = sim.len();
    Ok(match kind {
        TrajectoryKind::Gsd => 48.0 * n as f64 + 1024.0,
        TrajectoryKind::Xyz => {
            let k = n.min(100);
            let discs = sim.discs();
            let mut sample = Vec::new();
            edmd_io::xyz::write_frame(&mut sample, &discs[..k], sim.sim_box(), sim.time())
                .map_err(io_error)?;
            sample.len() as f64 * n.max(1) as f64 / k.max(1) as f64
        }
    })
}

/// A trajectory being written during `run`: under a temporary name beside the file, moved
/// into place by [`Trajectory::finish`], as the CLI writes its outputs (`AtomicFile`), so the
/// file named is replaced whole or not at all.
enum Trajectory {
    Xyz(AtomicFile),
    /// GSD files are written by path (`hoomd-gsd`), so its writer writes the temporary file.
    Gsd(Box<edmd_io::gsd::Writer>, AtomicFile, PathBuf),
}

/// A GSD error about the temporary file, said of the file the user named.
fn gsd_error(path: &Path, e: edmd_io::gsd::GsdError) -> PyErr {
    value_error(format!("{}: {}", path.display(), e.message))
}

impl Trajectory {
    /// Creates the temporary file; called only once every check of the run has passed.
    fn create(path: &Path, kind: TrajectoryKind) -> PyResult<Self> {
        let file = AtomicFile::create(path).map_err(cli_error)?;
        match kind {
            TrajectoryKind::Xyz => Ok(Trajectory::Xyz(file)),
            TrajectoryKind::Gsd => {
                let Some(tmp) = file.temp_path() else {
                    return Err(value_error(format!(
                        "trajectory: {}: a GSD trajectory needs a regular file",
                        path.display()
                    )));
                };
                let w = edmd_io::gsd::Writer::create(tmp, edmd_io::gsd::Precision::Float32)
                    .map_err(|e| gsd_error(path, e))?;
                Ok(Trajectory::Gsd(Box::new(w), file, path.to_path_buf()))
            }
        }
    }

    fn frame(&mut self, inner: &Inner) -> PyResult<()> {
        each!(inner, s => match self {
            Trajectory::Xyz(f) => {
                edmd_io::xyz::write_frame(f.writer(), &s.sim.discs(), s.sim.sim_box(), s.sim.time())
                    .map_err(io_error)
            }
            Trajectory::Gsd(w, _, path) => w.append_simulation(&s.sim).map_err(|e| gsd_error(path, e)),
        })
    }

    /// Completes the file and moves it into place.
    fn finish(self) -> PyResult<()> {
        match self {
            Trajectory::Xyz(f) => f.commit().map_err(cli_error),
            Trajectory::Gsd(w, f, path) => {
                w.finish().map_err(|e| gsd_error(&path, e))?;
                f.commit_existing().map_err(cli_error)
            }
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
/// Beyond hard cores: a stepped pair potential (square wells, shoulders, ramps of steps;
/// `from_arrays(potential=...)`, `edmd.gen.fluid(well=...)`, or a file's `# edmd potential`
/// lines), read back as `potential`, `potential_energy`, `shells` and `shell_counts`; an
/// Andersen heat bath, `set_thermostat(kT=..., rate=...)`; and reactive collisions, rules
/// `A + B -> C + D` that change the species of colliding discs (`set_reactions`,
/// `from_arrays(reactions=...)`, or a file's `# edmd reaction` lines), read back as
/// `reactions`, `species_counts`, `reaction_counts` and `reaction_heat`; and inelastic
/// collisions, a coefficient of normal restitution per pair of species and at the walls
/// (`set_restitution`, `from_arrays(restitution=...)`, `edmd.gen.fluid(restitution=...)`, or a
/// file's `# edmd restitution` lines), read back as `restitution` and `dissipated`; and a
/// uniform field, gravity along an axis with walls (`set_gravity`, `from_arrays(gravity=...)`,
/// `edmd.gen.fluid(gravity=...)`, or a file's `# edmd gravity` line), read back as `gravity`
/// and `field_energy`; and Lees-Edwards boundaries, simple shear flow along x with its
/// gradient along y (`set_shear`, `from_arrays(shear=...)`, `edmd.gen.fluid(shear=...)`, or a
/// file's `# edmd shear` line), read back as `shear`, `peculiar_velocities` and
/// `peculiar_kinetic_energy`.
///
/// Threads: a simulation is used by one thread at a time. While `run` is under way in one
/// thread, every use of the simulation from another thread (reading `positions`, pickling,
/// another `run`, ...) raises `RuntimeError` at once rather than waiting; a callback of the
/// run may read and change the simulation, but not `run` it. Separate simulations run in
/// separate threads in parallel (the GIL is released).
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

    fn running(&self) -> Option<std::thread::ThreadId> {
        each!(&self.inner, s => s.running)
    }

    fn dimension(&self) -> usize {
        match self.inner {
            Inner::One(_) => 1,
            Inner::Two(_) => 2,
            Inner::Three(_) => 3,
        }
    }

    fn len(&self) -> usize {
        each!(&self.inner, s => s.sim.len())
    }
}

/// The simulation to read, refused while a run is under way in another thread. Every method
/// takes the object through this (or [`get_mut`]) instead of PyO3's own borrow, whose failure
/// is a bare "Already mutably borrowed", and which would let another thread in between the
/// chunks of a run.
fn get<'py>(slf: &Bound<'py, PySimulation>) -> PyResult<PyRef<'py, PySimulation>> {
    let this = slf.try_borrow().map_err(|_| args::busy())?;
    match this.running() {
        Some(t) if t != std::thread::current().id() => Err(args::busy()),
        _ => Ok(this),
    }
}

/// The simulation to change, refused while a run is under way in another thread.
fn get_mut<'py>(slf: &Bound<'py, PySimulation>) -> PyResult<PyRefMut<'py, PySimulation>> {
    let this = slf.try_borrow_mut().map_err(|_| args::busy())?;
    match this.running() {
        Some(t) if t != std::thread::current().id() => Err(args::busy()),
        _ => Ok(this),
    }
}

/// A run under way: marks the simulation busy for other threads and for `run` called from
/// its callbacks, and clears the mark when the run ends, however it ends.
struct Running<'a, 'py>(&'a Bound<'py, PySimulation>);

impl<'a, 'py> Running<'a, 'py> {
    fn claim(slf: &'a Bound<'py, PySimulation>) -> PyResult<Self> {
        let mut this = get_mut(slf)?;
        if this.running().is_some() {
            // `get_mut` let it through, so the run under way is this thread's own: `run` was
            // called from one of its callbacks. Going on would run the simulation past the
            // outer run's end (a callback's `run(until=T + 500)` made `run(until=5)` end at
            // t = 501).
            return Err(PyRuntimeError::new_err(
                "run: called from a callback of this simulation's own run(), which is under way; a callback may read and change the simulation but not run it (return from the callback and let run() go on)",
            ));
        }
        let me = std::thread::current().id();
        each!(&mut this.inner, s => s.running = Some(me));
        Ok(Running(slf))
    }
}

impl Drop for Running<'_, '_> {
    fn drop(&mut self) {
        // Every borrow of the run has ended by now, so this borrow succeeds.
        if let Ok(mut this) = self.0.try_borrow_mut() {
            each!(&mut this.inner, s => s.running = None);
        }
    }
}

/// The run's own borrows (the run holds the busy mark, so no other thread gets this far).
fn borrow<'py>(slf: &Bound<'py, PySimulation>) -> PyResult<PyRef<'py, PySimulation>> {
    slf.try_borrow().map_err(|_| args::busy())
}

fn borrow_mut<'py>(slf: &Bound<'py, PySimulation>) -> PyResult<PyRefMut<'py, PySimulation>> {
    slf.try_borrow_mut().map_err(|_| args::busy())
}

#[pymethods]
impl PySimulation {
    /// Reads a data file, as `edmd run FILE` does: the course format, the Princeton format
    /// (with edmd's extension: 3D files, walls or periodic boundaries, barriers, species,
    /// stepped potentials from `# edmd potential` lines, reaction rules from `# edmd reaction`
    /// lines, inelastic collisions from `# edmd restitution` lines, a field from a
    /// `# edmd gravity` line), a GSD file of the HOOMD
    /// schema (HOOMD-blue's, the `gsd` package's or edmd's own: a periodic box unless edmd
    /// wrote walls; positions and velocities to float32 precision, exact for files edmd wrote
    /// with `write`) or an `edmd run --checkpoint` file.
    ///
    /// Args:
    ///     path: the file.
    ///     frame: the frame of a GSD file, from 0 (negative from the end; the last when None).
    ///     format: "course" or "princeton"; detected when None.
    ///     columns: "radius-mass" (default) or "mass-radius" for Princeton files.
    ///     rule: "elastic" or "swap" (the course's rule); by default swap for course files (as
    ///         the course's `particles` and `edmd run` do), elastic for the others.
    ///     multi: multi-disc collisions (elastic rule only); False when None.
    ///     allow_overlaps: run overlapping input anyway (see `edmd run --allow-overlaps`);
    ///         False when None.
    ///     seed: the seed of the draws of the file's reaction rules, a whole number from 0 to
    ///         2^64 - 1 (1 when None, as `edmd run` without `--seed`).
    ///
    /// Raises:
    ///     ValueError: the file cannot be read or is wrong; the message names the line, as
    ///         `edmd run` does.
    ///
    /// >>> sim = edmd.Simulation.from_file("examples/data/gas-300.txt")
    #[staticmethod]
    #[pyo3(signature = (path, *, frame=None, format=None, columns=None, rule=None, multi=None, allow_overlaps=None, seed=None))]
    #[allow(clippy::too_many_arguments)]
    fn from_file(
        path: &Bound<'_, PyAny>,
        frame: Option<&Bound<'_, PyAny>>,
        format: Option<&Bound<'_, PyAny>>,
        columns: Option<&Bound<'_, PyAny>>,
        rule: Option<&Bound<'_, PyAny>>,
        multi: Option<&Bound<'_, PyAny>>,
        allow_overlaps: Option<&Bound<'_, PyAny>>,
        seed: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let path = args::path(path, "path")?;
        let frame = args::opt_frame(frame, "frame")?;
        let format = args::opt_text(format, "format")?;
        let columns = args::opt_text(columns, "columns")?;
        let rule = args::opt_text(rule, "rule")?;
        let multi = args::opt_flag(multi, "multi")?;
        let allow_overlaps = args::opt_flag(allow_overlaps, "allow_overlaps")?;
        let seed = seed
            .filter(|s| !s.is_none())
            .map(|s| args::count(s, "seed"))
            .transpose()?;
        guarded("from_file", || {
            Self::read_file(
                path,
                frame,
                format.as_deref(),
                columns.as_deref(),
                rule.as_deref(),
                multi,
                allow_overlaps,
                seed,
            )
        })
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
    ///     rule: "elastic" (when None) or "swap".
    ///     multi: multi-disc collisions (False when None).
    ///     allow_overlaps: accept overlapping discs and move discs outside walls inside (False
    ///         when None).
    ///     potential: a stepped pair potential (None: hard cores alone), as a dict mapping a
    ///         pair of species `(a, b)` to its steps, innermost first: a list of
    ///         `(radius, energy)` pairs, or `{"core": c, "steps": [...]}` where `core`, if
    ///         given, must be the contact distance (sum of the radii) of every pair of discs of
    ///         those species. `radius` is a distance between centres, outside the hard core;
    ///         `energy` is the change of the pair's potential energy when it moves inward
    ///         across the step: `{(0, 0): [(1.5, -1.0)]}` is a square well of depth 1 out to
    ///         1.5, `{(0, 0): [(1.5, 1.0)]}` a shoulder of height 1. Pairs not named are hard
    ///         cores only. Needs the elastic rule and binary collisions (no `multi`).
    ///     reactions: reaction rules (None: none), as `set_reactions` takes them: a list of
    ///         rules, each `"A + B -> C + D"` (optionally followed by `activation E`,
    ///         `probability P`, `heat Q`) or a dict `{"reactants": (A, B), "products": (C, D),
    ///         "activation": E, "probability": P, "heat": Q}`, with the seed 1; or the dict
    ///         `{"rules": [...], "seed": S, "colours": {species: (r, g, b)}}` that
    ///         `Simulation.reactions` gives back. Needs the elastic rule, binary collisions
    ///         and no stepped potential.
    ///     restitution: inelastic collisions (None: elastic), as `set_restitution` takes
    ///         them: a coefficient of normal restitution e in [0, 1] for every pair, or a dict
    ///         `{"all": LAW, "pairs": {(a, b): LAW}, "walls": e, "tc": t}` (every key
    ///         optional), a LAW being a coefficient or `{"bridges": v_c}`. Needs the elastic
    ///         rule, binary collisions, no stepped potential and no reaction rules.
    ///     gravity: a uniform field (None: none), as `set_gravity` takes it: the acceleration
    ///         g along the last axis (y in 2D, z in 3D; negative pulls towards 0), or the dict
    ///         `{"axis": k, "g": g}` that `Simulation.gravity` gives. The axis must have walls.
    ///         Needs binary collisions and no stepped potential; inelastic collisions in a
    ///         field need the TC model (a restitution with "tc" > 0).
    ///     shear: Lees-Edwards boundaries (None: none), as `set_shear` takes them: the shear
    ///         rate (from an offset of 0), or the tuple `(rate, offset)` that
    ///         `Simulation.shear` gives. The velocities are taken as given (add
    ///         `rate * (y - L_y / 2)` to the x velocities to start on the streaming profile).
    ///         Needs periodic x and y, binary collisions, no stepped potential and no field.
    ///     ring: a patch of a planetary ring (None: none), as `set_ring` takes it: the orbital
    ///         frequency omega. The velocities are taken as given (add
    ///         `-1.5 * omega * (y - L_y / 2)` to the x velocities to start on the Keplerian
    ///         flow). Needs periodic x and y (and walls along z in 3D), binary collisions, no
    ///         stepped potential, no field and no `shear` (the ring shears at -1.5 omega
    ///         itself).
    ///     self_gravity: one-dimensional self-gravity (None: none), as `set_self_gravity`
    ///         takes it: the coupling C, each rod pulled by C times the mass on its right less
    ///         the mass on its left (self-gravitating sheets). 1D only (positions of shape
    ///         (N, 1)), the line with walls; needs the elastic rule, binary collisions, no
    ///         stepped potential, reaction rules, restitution or field.
    ///
    /// Raises:
    ///     TypeError: an argument that is not numbers (strings, complex numbers, booleans,
    ///         None), naming the argument.
    ///     ValueError: shapes that do not match, non-finite values, a kinetic energy that
    ///         overflows, overlapping discs, discs outside the box, a bad box, a potential
    ///         whose steps are not in increasing radius, lie inside the hard core, or name a
    ///         species no disc has (the message starts "potential:"), reaction rules that
    ///         cannot be (the message starts "reactions:"), restitution that cannot be (the
    ///         message starts "restitution:"), a field that cannot be (the message starts
    ///         "gravity"), shear that cannot be (the message starts "shear"), a ring that
    ///         cannot be (the message starts "ring"), self-gravity that cannot be (the
    ///         message starts "self_gravity").
    ///
    /// >>> import numpy as np
    /// >>> sim = edmd.Simulation.from_arrays([[2.0, 5.0], [8.0, 5.0]], [[1.0, 0.0], [-1.0, 0.0]],
    /// ...                                   radii=1.0, box=(10.0, 10.0), boundary="walls")
    /// >>> sim.run(until=2.5)
    /// >>> sim.stats["disc_disc"]
    /// 1
    /// >>> well = edmd.Simulation.from_arrays([[5.0, 10.0], [8.0, 10.0]], [[0.5, 0.0], [-0.5, 0.0]],
    /// ...                                    radii=0.5, box=(20.0, 20.0),
    /// ...                                    potential={(0, 0): [(1.5, -1.0)]})
    /// >>> pair = edmd.Simulation.from_arrays([[2.0, 5.0], [8.0, 5.0]], [[1.0, 0.0], [-1.0, 0.0]],
    /// ...                                    radii=1.0, box=(10.0, 10.0), species=[0, 1],
    /// ...                                    reactions=["0 + 1 -> 2 + 2 activation 0.5"])
    /// >>> soft = edmd.Simulation.from_arrays([[2.0, 5.0], [8.0, 5.0]], [[1.0, 0.0], [-1.0, 0.0]],
    /// ...                                    radii=1.0, box=(10.0, 10.0), restitution=0.5)
    /// >>> drop = edmd.Simulation.from_arrays([[5.0, 8.0]], [[0.0, 0.0]], radii=0.5,
    /// ...                                    box=(10.0, 10.0), boundary="walls", gravity=-1.0)
    /// >>> flow = edmd.Simulation.from_arrays([[5.0, 2.0], [5.0, 8.0]], [[-0.3, 0.0], [0.3, 0.0]],
    /// ...                                    radii=0.5, box=(10.0, 10.0), shear=0.1)
    #[staticmethod]
    #[pyo3(signature = (positions, velocities, radii, masses=None, r#box=None, boundary=None, species=None, rule=None, multi=None, allow_overlaps=None, potential=None, reactions=None, restitution=None, gravity=None, shear=None, ring=None, self_gravity=None))]
    #[allow(clippy::too_many_arguments)]
    fn from_arrays(
        positions: &Bound<'_, PyAny>,
        velocities: &Bound<'_, PyAny>,
        radii: &Bound<'_, PyAny>,
        masses: Option<&Bound<'_, PyAny>>,
        r#box: Option<&Bound<'_, PyAny>>,
        boundary: Option<&Bound<'_, PyAny>>,
        species: Option<&Bound<'_, PyAny>>,
        rule: Option<&Bound<'_, PyAny>>,
        multi: Option<&Bound<'_, PyAny>>,
        allow_overlaps: Option<&Bound<'_, PyAny>>,
        potential: Option<&Bound<'_, PyAny>>,
        reactions: Option<&Bound<'_, PyAny>>,
        restitution: Option<&Bound<'_, PyAny>>,
        gravity: Option<&Bound<'_, PyAny>>,
        shear: Option<&Bound<'_, PyAny>>,
        ring: Option<&Bound<'_, PyAny>>,
        self_gravity: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let input = arrays::Input::new(
            positions, velocities, radii, masses, r#box, boundary, species, potential,
        )?;
        let opts = options(
            args::opt_text(rule, "rule")?
                .as_deref()
                .unwrap_or("elastic"),
            args::opt_flag(multi, "multi")?,
            args::opt_flag(allow_overlaps, "allow_overlaps")?,
        )?;
        let reactions = match reactions {
            Some(r) => reactions::parse(r, "reactions")?,
            None => None,
        };
        let restitution = match restitution {
            Some(r) => restitution::parse(r, "restitution")?,
            None => None,
        };
        let field = match gravity {
            Some(g) => gravity::parse(g)?,
            None => None,
        };
        let sliding = match shear {
            Some(s) => shear::parse(s)?,
            None => None,
        };
        let patch = match ring {
            Some(r) => ring::parse(r, "ring")?,
            None => None,
        };
        if patch.is_some() && sliding.is_some() {
            return Err(value_error(
                "ring: does not go with shear (the ring shears at -1.5 omega itself)",
            ));
        }
        let sheets = match self_gravity {
            Some(g) => sheets::parse(g, "self_gravity")?,
            None => None,
        };
        /// The simulation of the arrays, with the rules, the field, the restitution, the
        /// shear, the ring and the self-gravity (in the order `edmd run` sets a file's).
        #[allow(clippy::too_many_arguments)]
        fn made<const D: usize>(
            input: &arrays::Input,
            opts: Options,
            reactions: Option<edmd_core::Reactions>,
            field: Option<gravity::Field>,
            restitution: Option<edmd_core::Restitution>,
            sliding: Option<shear::Sliding>,
            patch: Option<edmd_core::Ring>,
            sheets: Option<edmd_core::SelfGravity>,
        ) -> PyResult<State<D>> {
            let mut sim = shear::build::<D>(input, opts, sliding)?;
            reactions::apply(&mut sim, reactions, "reactions")?;
            gravity::apply(&mut sim, field)?;
            restitution::apply(&mut sim, restitution, "restitution")?;
            shear::apply(&mut sim, sliding)?;
            ring::apply(&mut sim, patch, "ring")?;
            sheets::apply(&mut sim, sheets, "self_gravity")?;
            Ok(State::new(sim, Format::Princeton(ColumnOrder::RadiusMass)))
        }
        guarded("from_arrays", || {
            let inner = match input.dim {
                3 => Inner::Three(made(
                    &input,
                    opts,
                    reactions,
                    field,
                    restitution,
                    sliding,
                    patch,
                    sheets,
                )?),
                1 => Inner::One(made(
                    &input,
                    opts,
                    reactions,
                    field,
                    restitution,
                    sliding,
                    patch,
                    sheets,
                )?),
                _ => Inner::Two(made(
                    &input,
                    opts,
                    reactions,
                    field,
                    restitution,
                    sliding,
                    patch,
                    sheets,
                )?),
            };
            Ok(PySimulation { inner })
        })
    }

    /// Advances the simulation, with the GIL released.
    ///
    /// Give exactly one of `until` (a time, at or after `time`) or `events` (a number of
    /// events: collisions, wall bounces, cell crossings, barrier events, the steps of a
    /// stepped potential and thermostat redraws, as `stats` counts them; stale events are
    /// not counted). Ctrl-C stops the run within a
    /// fraction of a second with `KeyboardInterrupt`, leaving a consistent state at some time
    /// before `until`. Stopping never changes the trajectory: a run to T in pieces ends in
    /// exactly the state of one run to T, and in the state `edmd run --until T` writes.
    ///
    /// Every argument is checked before anything is run or written: a refused call leaves
    /// the simulation and every file as they were. As with `edmd run`, a run takes at most
    /// 1000000 trajectory frames, callbacks and measurement samples each, and a trajectory
    /// estimated at more than 10 GB is refused.
    ///
    /// Args:
    ///     until: end time.
    ///     events: number of events to process.
    ///     trajectory: a file (".xyz" extended XYZ or ".gsd" HOOMD) to which a frame is
    ///         written at every multiple of `every` (needs `until`). It is written under a
    ///         temporary name and moved into place when the run ends (as `edmd run` writes its
    ///         files); a run stopped early (Ctrl-C, an exception in the callback) still moves
    ///         the frames written so far into place.
    ///     every: time between trajectory frames.
    ///     callback: called as `callback(sim)` at every multiple of `callback_every` after the
    ///         current time (needs `until`); an exception in it stops the run. It may read and
    ///         change `sim` (its velocities, its measurements), but calling `sim.run` from it
    ///         raises `RuntimeError`.
    ///     callback_every: time between callbacks.
    ///
    /// Raises:
    ///     TypeError, ValueError: a bad argument, named in the message.
    ///     RuntimeError: the simulation is running already (in another thread, or this is a
    ///         call from the run's own callback).
    ///
    /// >>> sim.run(until=sim.time + 5.0, trajectory="t.gsd", every=0.5)
    #[pyo3(signature = (until=None, *, events=None, trajectory=None, every=None, callback=None, callback_every=None))]
    #[allow(clippy::too_many_arguments)]
    fn run(
        slf: &Bound<'_, Self>,
        until: Option<&Bound<'_, PyAny>>,
        events: Option<&Bound<'_, PyAny>>,
        trajectory: Option<&Bound<'_, PyAny>>,
        every: Option<&Bound<'_, PyAny>>,
        callback: Option<Bound<'_, PyAny>>,
        callback_every: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let until = until.map(|u| args::real(u, "until")).transpose()?;
        let trajectory = trajectory
            .map(|p| args::path(p, "trajectory"))
            .transpose()?;
        let events = events.map(|e| args::count(e, "events")).transpose()?;
        let every = every.map(|e| args::real(e, "every")).transpose()?;
        let callback_every = callback_every
            .map(|e| args::real(e, "callback_every"))
            .transpose()?;
        let now = get(slf)?.time();
        let until = match (until, events) {
            (Some(_), Some(_)) | (None, None) => {
                return Err(value_error("run: give either until or events"))
            }
            (None, Some(n)) => {
                if trajectory.is_some()
                    || every.is_some()
                    || callback.is_some()
                    || callback_every.is_some()
                {
                    return Err(value_error(
                        "run: trajectory, every, callback and callback_every need until (they are timed in simulated time)",
                    ));
                }
                let _running = Running::claim(slf)?;
                return guarded("run", || run_events(slf, n));
            }
            (Some(t), None) if !t.is_finite() => {
                return Err(value_error(format!(
                    "until: {} is not a finite time",
                    num(t)
                )))
            }
            (Some(t), None) if t < now => {
                return Err(value_error(format!(
                    "until: {} is before the current time t = {}",
                    num(t),
                    num(now)
                )))
            }
            (Some(t), None) => {
                // The same limit `edmd run --until` has: beyond it floating-point times are
                // too far apart to place a disc at contact.
                each!(&get(slf)?.inner, s => s.sim.check_clock(t))
                    .map_err(|e| value_error(format!("until: {e}")))?;
                t
            }
        };
        let positive = |name: &str, dt: Option<f64>, what: &str| -> PyResult<Option<f64>> {
            match dt {
                Some(d) if !(d.is_finite() && d > 0.0) => Err(value_error(format!(
                    "{name}: {} is not a positive time",
                    num(d)
                ))),
                Some(d) if (until - now) / d > MAX_STOPS => Err(value_error(format!(
                    "{name}: {} {what} from t = {} to {} is too many (at most {MAX_STOPS:.0}, as edmd run): {name} must be >= {:e}",
                    format_args!("{:.3e}", (until - now) / d),
                    num(now),
                    num(until),
                    (until - now) / MAX_STOPS
                ))),
                _ => Ok(dt),
            }
        };
        let every = positive("every", every, "trajectory frames")?;
        let callback_every = positive("callback_every", callback_every, "callbacks")?;
        if trajectory.is_some() != every.is_some() {
            return Err(value_error("run: trajectory and every go together"));
        }
        if callback.is_some() != callback_every.is_some() {
            return Err(value_error("run: callback and callback_every go together"));
        }
        if let Some(c) = &callback {
            if !c.is_callable() {
                return Err(PyTypeError::new_err(format!(
                    "callback: expected a function, got {}",
                    args::type_name(c)
                )));
            }
        }
        {
            let this = get(slf)?;
            // The sample limit of `edmd run --sample-every`, with its rule and numbers.
            if let Some(dt) = each!(&this.inner, s => s.measuring.as_ref().map(|m| m.every)) {
                if (until - now) / dt > MAX_STOPS {
                    return Err(value_error(format!(
                        "measure(every={}): {:.3e} samples from t = {} to {} is too many (at most {MAX_STOPS:.0}, as edmd run): every must be >= {:e}",
                        num(dt),
                        (until - now) / dt,
                        num(now),
                        num(until),
                        (until - now) / MAX_STOPS
                    )));
                }
            }
        }
        // The trajectory's checks, all before the file is created.
        let kind = trajectory.as_deref().map(trajectory_kind).transpose()?;
        if let (Some(path), Some(kind), Some(dt)) = (trajectory.as_deref(), kind, every) {
            // Frames at the multiples of `every` from now to `until`, both included.
            let frames = ((until / dt).floor() - (now / dt).ceil() + 1.0).max(0.0);
            check_trajectory(path, kind, frames, &get(slf)?.inner)?;
        }
        let running = Running::claim(slf)?;
        let mut traj = match (&trajectory, kind) {
            (Some(p), Some(kind)) => Some(Trajectory::create(p, kind)?),
            _ => None,
        };
        let result = guarded("run", || {
            run_until(
                slf,
                now,
                until,
                every,
                callback_every,
                callback.as_ref(),
                &mut traj,
            )
        });
        // The frames written so far go into place even when the run stopped early (Ctrl-C,
        // an exception in the callback): they are the trajectory to the state the simulation
        // is left in. A trajectory that failed to write was dropped (its temporary file
        // removed).
        let finished = traj.map_or(Ok(()), Trajectory::finish);
        drop(running);
        result.and(finished)
    }

    /// Attaches measurements, sampled every `every` of simulated time during `run`.
    ///
    /// The names are those of `edmd run --measure`: "temperature", "pressure" (wall and
    /// virial, Z = PA/NkT with block errors), "collisions" (collision frequency, free paths
    /// and times), "speeds" (against the Maxwell-Boltzmann law), "msd", "species", "energy"
    /// (kinetic, potential and total energy per particle; with a thermostat, the heat
    /// capacity), "rdf" (the radial distribution function g(r)), "kinetics" (the number of
    /// discs of each species over time, and each reaction rule's reactions and rate constant
    /// k, reactions per unit volume and time = k n_A n_B, k n_A^2 / 2 for like reactants, with
    /// its block error), "viscosity" and "conductivity" (the shear viscosity and the thermal
    /// conductivity by the Einstein-Helfand route, with block errors and Enskog's values;
    /// periodic boxes only, and equal hard particles for the conductivity), "shear-stress"
    /// (the shear stress P_xy of a sheared run and its viscosity -P_xy / gamma, in blocks at
    /// the samples, with block errors; needs shear). Events are watched
    /// in Rust; samples are taken at `start + k * every`
    /// by `run(until=...)` (not by `run(events=...)`, which is not timed); `results()` gives
    /// what was measured. Attaching again starts afresh. Pickles and checkpoints keep the
    /// measurements under way. As with `edmd run --sample-every`, a `run` that would take more
    /// than 1000000 samples is refused.
    ///
    /// >>> sim.measure("pressure", "speeds", every=1.0)
    /// >>> sim.run(until=sim.time + 10.0)
    /// >>> sim.results()["pressure"]["Z"]["value"]
    /// >>> sim.measure("kinetics", every=0.5)   # with reaction rules set
    /// >>> sim.run(until=sim.time + 10.0)
    /// >>> sim.results()["tables"]["kinetics"]["species0"]   # species 0 over time
    #[pyo3(signature = (*names, every))]
    fn measure(
        slf: &Bound<'_, Self>,
        names: &Bound<'_, PyTuple>,
        every: &Bound<'_, PyAny>,
    ) -> PyResult<()> {
        use clap::ValueEnum;
        let every = args::real(every, "every")?;
        if !(every.is_finite() && every > 0.0) {
            return Err(value_error(format!(
                "every: {} is not a positive time",
                num(every)
            )));
        }
        let mut which = Vec::new();
        for n in names.iter() {
            let name: String = n.extract().map_err(|_| {
                PyTypeError::new_err(format!(
                    "measure: expected measurement names (str), got {}",
                    args::type_name(&n)
                ))
            })?;
            let m = Measure::from_str(&name, true).map_err(|_| {
                let known: Vec<String> = Measure::value_variants()
                    .iter()
                    .filter_map(|v| v.to_possible_value())
                    .map(|v| v.get_name().to_string())
                    .collect();
                value_error(format!(
                    "measure: unknown measurement '{name}' (one of: {})",
                    known.join(", ")
                ))
            })?;
            which.push(m);
        }
        if which.is_empty() {
            return Err(value_error("measure: name at least one measurement"));
        }
        let mut this = get_mut(slf)?;
        guarded("measure", || {
            each!(&mut this.inner, s => {
                edmd::measure::Measurements::check(&s.sim, &which).map_err(|e| {
                    value_error(format!("measure: {}", e.to_string().trim_start_matches("--measure ")))
                })?;
                s.measure(&which, every);
                Ok(())
            })
        })
    }

    /// What the attached measurements found: a dict with one summary per measurement (the
    /// same numbers as `edmd run --measure --json`, estimates as {"value", "error", "blocks"})
    /// and "tables": the time series and histograms as dicts of numpy arrays, keyed by the
    /// CSV file `edmd run` would write ("temperature", "pressure", "speeds", "energy", "rdf",
    /// ...).
    fn results<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyDict>> {
        let py = slf.py();
        let this = get(slf)?;
        let Some((summary, tables)) =
            guarded("results", || Ok(each!(&this.inner, s => s.results())))?
        else {
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
    /// generators). The file appears whole or not at all: it is written under a temporary
    /// name and moved into place, as `edmd run` writes, and a refused call (a bad format, a
    /// system the course format cannot hold, a folder) leaves every file as it was.
    ///
    /// A stepped potential, reaction rules, restitution and a field are written with the
    /// state in Princeton files (`# edmd potential`, `# edmd reaction`, `# edmd restitution`
    /// and `# edmd gravity` lines, as `edmd run` writes them) and in checkpoints, so
    /// `from_file` reads them back (a
    /// Princeton file holds the rules and the restitution, not the seed of the rules' draws,
    /// the counts, the energy dissipated so far or the TC model's clock: a checkpoint holds
    /// all); XYZ and GSD frames hold none of them, and writing a state that has one as XYZ,
    /// GSD or the course format is refused.
    ///
    /// >>> sim.write("state.txt")
    #[pyo3(signature = (path, *, format=None))]
    fn write(
        slf: &Bound<'_, Self>,
        path: &Bound<'_, PyAny>,
        format: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let path = args::path(path, "path")?;
        let format = args::opt_text(format, "format")?;
        let this = get(slf)?;
        let kind = match format {
            Some(f) => f,
            None => match extension(&path).as_deref() {
                Some("xyz") | Some("extxyz") => "xyz".into(),
                Some("gsd") => "gsd".into(),
                Some("ck") | Some("checkpoint") => "checkpoint".into(),
                _ => each!(&this.inner, s => format_name(s.format)).into(),
            },
        };
        // The whole file is made in memory first, so that every refusal comes before the
        // file system is touched.
        let bytes = guarded("write", || render(&this.inner, &kind, &path))?;
        edmd::output::check_file_destinations(&[("path", &path)]).map_err(cli_error)?;
        let mut f = AtomicFile::create(&path).map_err(cli_error)?;
        f.writer().write_all(&bytes).map_err(io_error)?;
        f.commit().map_err(cli_error)
    }

    /// The exact state as bytes (an `edmd run --checkpoint` file's contents).
    fn checkpoint<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyBytes>> {
        let this = get(slf)?;
        let bytes = guarded(
            "checkpoint",
            || each!(&this.inner, s => checkpoint_bytes(s)),
        )?;
        Ok(PyBytes::new(slf.py(), &bytes))
    }

    /// A simulation continued from `checkpoint()` bytes.
    #[staticmethod]
    fn from_checkpoint(data: &Bound<'_, PyAny>) -> PyResult<Self> {
        let data: &[u8] = data.extract().map_err(|_| {
            PyTypeError::new_err(format!(
                "data: expected bytes (from checkpoint()), got {}",
                args::type_name(data)
            ))
        })?;
        guarded("from_checkpoint", || {
            Ok(PySimulation {
                inner: from_checkpoint(data, "data")?,
            })
        })
    }

    /// Pickling keeps the exact state, measurements under way included.
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> PyResult<(Bound<'py, PyAny>, (Bound<'py, PyBytes>,))> {
        let py = slf.py();
        let restore = py.import("edmd._edmd")?.getattr("_restore")?;
        Ok((restore, (Self::checkpoint(slf)?,)))
    }

    /// Positions at the current time, folded into the box on periodic axes: (N, dim) float64.
    #[getter]
    fn positions<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyAny>> {
        let this = get(slf)?;
        guarded(
            "positions",
            || each!(&this.inner, s => arrays::matrix(slf.py(), &s.sim, |i| s.sim.position(i).0)),
        )
    }

    /// Positions not folded back into the box: the displacement since time 0 is
    /// `unwrapped_positions - initial positions`. (N, dim) float64.
    #[getter]
    fn unwrapped_positions<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyAny>> {
        let this = get(slf)?;
        guarded(
            "unwrapped_positions",
            || each!(&this.inner, s => arrays::matrix(slf.py(), &s.sim, |i| s.sim.unwrapped_position(i).0)),
        )
    }

    /// Velocities: (N, dim) float64. Assigning an array of that shape changes every velocity
    /// at the current time and schedules everything again; the new velocities are checked as
    /// `from_arrays` checks them (finite, with a finite kinetic energy), and a refused array
    /// raises ValueError and changes nothing.
    #[getter]
    fn velocities<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyAny>> {
        let this = get(slf)?;
        guarded(
            "velocities",
            || each!(&this.inner, s => arrays::matrix(slf.py(), &s.sim, |i| s.sim.velocity(i).0)),
        )
    }

    #[setter]
    fn set_velocities(slf: &Bound<'_, Self>, v: Option<&Bound<'_, PyAny>>) -> PyResult<()> {
        let Some(v) = v else {
            return Err(PyTypeError::new_err(
                "velocities: cannot be deleted; assign an (N, dim) array",
            ));
        };
        let mut this = get_mut(slf)?;
        guarded(
            "velocities",
            || each!(&mut this.inner, s => arrays::set_velocities(&mut s.sim, v)),
        )
    }

    /// Radii: (N,) float64.
    #[getter]
    fn radii<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let this = get(slf)?;
        let v = each!(&this.inner, s => (0..s.sim.len()).map(|i| s.sim.radius(i)).collect());
        Ok(PyArray1::from_vec(slf.py(), v))
    }

    /// Masses: (N,) float64.
    #[getter]
    fn masses<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let this = get(slf)?;
        let v = each!(&this.inner, s => (0..s.sim.len()).map(|i| s.sim.mass(i)).collect());
        Ok(PyArray1::from_vec(slf.py(), v))
    }

    /// Species labels: (N,) uint16.
    #[getter]
    fn species<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray1<u16>>> {
        let this = get(slf)?;
        let v = each!(&this.inner, s => (0..s.sim.len()).map(|i| s.sim.species(i)).collect());
        Ok(PyArray1::from_vec(slf.py(), v))
    }

    /// Current time.
    #[getter(time)]
    fn get_time(slf: &Bound<'_, Self>) -> PyResult<f64> {
        Ok(get(slf)?.time())
    }

    /// Box lengths, a tuple (Lx, Ly) or (Lx, Ly, Lz).
    #[getter(r#box)]
    fn get_box<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyTuple>> {
        PyTuple::new(slf.py(), get(slf)?.lengths())
    }

    /// Boundary of each axis: a tuple of "periodic" or "walls".
    #[getter]
    fn boundary<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyTuple>> {
        PyTuple::new(slf.py(), get(slf)?.boundaries())
    }

    /// 2 (discs) or 3 (spheres).
    #[getter]
    fn dim(slf: &Bound<'_, Self>) -> PyResult<usize> {
        Ok(get(slf)?.dimension())
    }

    /// Number of discs.
    #[getter]
    fn n(slf: &Bound<'_, Self>) -> PyResult<usize> {
        Ok(get(slf)?.len())
    }

    fn __len__(slf: &Bound<'_, Self>) -> PyResult<usize> {
        Ok(get(slf)?.len())
    }

    /// Total kinetic energy, sum m v^2 / 2.
    #[getter]
    fn kinetic_energy(slf: &Bound<'_, Self>) -> PyResult<f64> {
        Ok(each!(&get(slf)?.inner, s => s.sim.kinetic_energy()))
    }

    /// Event counts so far: a dict with "disc_disc", "wall", "cell_crossing", "stale",
    /// "barrier" (as `edmd run` reports them), "step" (crossings of and bounces off the steps
    /// of a stepped potential; hard-core collisions count in "disc_disc"), "thermostat"
    /// (velocities redrawn by the thermostat), "neighbour_list" (under a stepped potential,
    /// whose discs have no cell crossings: neighbour lists made again) and "reaction"
    /// (reactive collisions, counted in "disc_disc" too).
    #[getter]
    fn stats<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyDict>> {
        let st = each!(&get(slf)?.inner, s => s.sim.stats());
        let d = PyDict::new(slf.py());
        d.set_item("disc_disc", st.disc_disc)?;
        d.set_item("wall", st.wall)?;
        d.set_item("cell_crossing", st.cell_crossing)?;
        d.set_item("stale", st.stale)?;
        d.set_item("barrier", st.barrier)?;
        d.set_item("step", st.step)?;
        d.set_item("thermostat", st.thermostat)?;
        d.set_item("neighbour_list", st.neighbour_list)?;
        d.set_item("reaction", st.reaction)?;
        Ok(d)
    }

    /// The stepped pair potential, as `from_arrays` takes it: a dict mapping each pair of
    /// species `(a, b)` that has steps to its steps, a list of `(radius, energy)` innermost
    /// first; None for hard cores alone.
    #[getter]
    fn potential<'py>(slf: &Bound<'py, Self>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let this = get(slf)?;
        each!(&this.inner, s => s.sim.potential().map(|p| potential::to_dict(slf.py(), p)))
            .transpose()
    }

    /// Total potential energy: that of the stepped potential, the sum over pairs of the
    /// energy of the shell each is in, plus that of the field, `field_energy` (0.0 for hard
    /// cores without a field). `kinetic_energy + potential_energy` is conserved (without a
    /// thermostat, reactions' heat or restitution).
    #[getter]
    fn potential_energy(slf: &Bound<'_, Self>) -> PyResult<f64> {
        Ok(each!(&get(slf)?.inner, s => s.sim.potential_energy()))
    }

    /// The pairs inside at least one step of the potential: an (k, 3) int64 array of rows
    /// `(i, j, shell)`, `i < j`, sorted, where `shell` is the number of the pair's steps it is
    /// inside (1 for a pair in a single square well). Empty for hard cores.
    #[getter]
    fn shells<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyAny>> {
        let this = get(slf)?;
        let list = each!(&this.inner, s => s.sim.shells());
        let k = list.len();
        let flat: Vec<i64> = list
            .iter()
            .flat_map(|&(i, j, sh)| [i as i64, j as i64, i64::from(sh)])
            .collect();
        Ok(PyArray1::from_vec(slf.py(), flat)
            .reshape([k, 3])?
            .into_any())
    }

    /// How many pairs are in each shell: a dict {shell: number of pairs}, shells from 1 up
    /// (only those holding a pair; empty for hard cores). For a square well, `{1: bonds}`.
    #[getter]
    fn shell_counts<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyDict>> {
        let this = get(slf)?;
        let list = each!(&this.inner, s => s.sim.shells());
        let mut counts = std::collections::BTreeMap::<u8, u64>::new();
        for (_, _, sh) in list {
            *counts.entry(sh).or_default() += 1;
        }
        let d = PyDict::new(slf.py());
        for (sh, c) in counts {
            d.set_item(sh, c)?;
        }
        Ok(d)
    }

    /// The heat bath: None (energy is conserved), or a dict {"kT", "rate", "seed"} for the
    /// Andersen thermostat set by `set_thermostat` (`sim.set_thermostat(**sim.thermostat)`
    /// sets it again).
    #[getter]
    fn thermostat<'py>(slf: &Bound<'py, Self>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(a) = each!(&get(slf)?.inner, s => s.sim.thermostat()) else {
            return Ok(None);
        };
        let d = PyDict::new(slf.py());
        d.set_item("kT", a.kt)?;
        d.set_item("rate", a.rate)?;
        d.set_item("seed", a.seed)?;
        Ok(Some(d))
    }

    /// Puts the particles in contact with an Andersen heat bath from now on, as
    /// `edmd run --thermostat andersen --kT T --rate NU --seed S` does: each particle's
    /// velocity is redrawn from the Maxwell-Boltzmann distribution at `kT` at the times of a
    /// Poisson process of `rate` redraws per particle per unit time. `set_thermostat(None)`
    /// removes the bath (energy is conserved again). The redraws are seeded by `seed` alone:
    /// a run gives the same redraws however it is sliced, and pickles and checkpoints carry
    /// the bath, so a restored simulation continues bit for bit. Redraws are counted in
    /// `stats["thermostat"]`.
    ///
    /// Args:
    ///     kT: the bath's temperature (energy units), a finite number > 0; None removes it.
    ///     rate: redraws per particle per unit time, a finite number > 0 (needed with kT).
    ///     seed: the seed of the redraws, a whole number from 0 to 2^64 - 1 (1 when None).
    ///
    /// >>> sim.set_thermostat(kT=1.5, rate=0.5)
    /// >>> sim.set_thermostat(None)
    #[pyo3(signature = (kT=None, *, rate=None, seed=None))]
    #[allow(non_snake_case)]
    fn set_thermostat(
        slf: &Bound<'_, Self>,
        kT: Option<&Bound<'_, PyAny>>,
        rate: Option<&Bound<'_, PyAny>>,
        seed: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        fn present<'a, 'py>(o: Option<&'a Bound<'py, PyAny>>) -> Option<&'a Bound<'py, PyAny>> {
            o.filter(|o| !o.is_none())
        }
        let bath = match present(kT) {
            None => {
                if present(rate).is_some() || present(seed).is_some() {
                    return Err(value_error(
                        "set_thermostat: rate and seed go with kT (set_thermostat(None) removes the thermostat)",
                    ));
                }
                None
            }
            Some(k) => {
                let kt = args::real(k, "kT")?;
                if !(kt.is_finite() && kt > 0.0) {
                    return Err(value_error(format!(
                        "kT: {} is not a finite number > 0",
                        num(kt)
                    )));
                }
                let Some(r) = present(rate) else {
                    return Err(value_error(
                        "rate: give the redraw rate (redraws per particle per unit time) with kT",
                    ));
                };
                let rate = args::real(r, "rate")?;
                if !(rate.is_finite() && rate > 0.0) {
                    return Err(value_error(format!(
                        "rate: {} is not a finite number > 0",
                        num(rate)
                    )));
                }
                let seed = present(seed)
                    .map(|s| args::count(s, "seed"))
                    .transpose()?
                    .unwrap_or(1);
                Some(edmd_core::Andersen { kt, rate, seed })
            }
        };
        let mut this = get_mut(slf)?;
        guarded("set_thermostat", || {
            each!(&mut this.inner, s => s.sim.set_thermostat(bath)).map_err(value_error)
        })
    }

    /// The reaction rules: None (collisions are elastic), or a dict {"rules", "seed",
    /// "colours"} as `set_reactions` takes it (`sim.set_reactions(**sim.reactions)` sets them
    /// again): "rules" a list of dicts {"reactants": (A, B), "products": (C, D),
    /// "activation", "probability", "heat"}, "seed" the seed of the draws, "colours" a dict
    /// {species: (r, g, b)} of the colour a disc takes on becoming each species the rules make.
    #[getter]
    fn reactions<'py>(slf: &Bound<'py, Self>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let this = get(slf)?;
        each!(&this.inner, s => s.sim.reactions().map(|r| reactions::to_dict(slf.py(), r)))
            .transpose()
    }

    /// Makes collisions reactive from now on, as a file's `# edmd reaction` lines do: a rule
    /// `A + B -> C + D` applies when a disc of species A collides with one of species B and the
    /// kinetic energy of their relative motion along the line of centres, `mu v_n^2 / 2`, is at
    /// least the activation energy; it then happens with its probability: the disc of A becomes
    /// C, the one of B becomes D, and the heat is released into their normal relative motion
    /// (momentum is kept; negative heat is absorbed from it, and a collision that cannot pay
    /// it stays elastic). Species differ in label (and colour) only: a disc keeps its mass and
    /// radius. `set_reactions(None)` makes collisions elastic again. Setting rules starts
    /// `reaction_counts` and `reaction_heat` again from 0; if the "kinetics" measurement is
    /// attached and the reactions change, the attached measurements start again from now too,
    /// as `measure` with the same names would (kinetics measures the rules in force). Pickles
    /// and checkpoints carry the rules, the counts and the heat, so a restored simulation
    /// continues bit for bit.
    ///
    /// Args:
    ///     rules: a list of rules, each a str `"A + B -> C + D"` optionally followed by
    ///         `activation E`, `probability P` and `heat Q` (the text of a `# edmd reaction`
    ///         line), or a dict {"reactants": (A, B), "products": (C, D), "activation": E,
    ///         "probability": P, "heat": Q}; unless given, the activation is 0, the
    ///         probability 1 and the heat 0. Species are whole numbers from 0 to 255; each
    ///         reactant must be a species some disc is or some rule makes, and each pair of
    ///         species has at most one rule (`A + B` and `B + A` are one pair). None removes
    ///         the rules.
    ///     seed: the seed of the draws of rules whose probability is below 1 (and of which of
    ///         two like reactants becomes which product), a whole number from 0 to 2^64 - 1
    ///         (1 when None, as `edmd run` without `--seed`). The draws depend on the seed and
    ///         the colliding discs alone, so a run gives the same reactions however it is
    ///         sliced.
    ///     colours: {species: (r, g, b)}, the colour a disc takes on becoming a species (in
    ///         written files and the viewer); a species made by a rule and not named takes the
    ///         colour of the first disc of that species, else one of ten distinct colours.
    ///
    /// Raises:
    ///     TypeError, ValueError: a bad argument, named in the message (negative activation,
    ///         probability outside [0, 1], non-finite numbers, unknown species, two rules for
    ///         one pair); rules with a stepped potential, multi-disc collisions or the swap
    ///         rule. A refused call changes nothing.
    ///
    /// >>> sim.set_reactions(["0 + 1 -> 1 + 1 activation 1.0 probability 0.5"], seed=3)
    /// >>> sim.set_reactions([{"reactants": (0, 0), "products": (1, 2), "heat": -0.5}])
    /// >>> sim.set_reactions(None)
    #[pyo3(signature = (rules, *, seed=None, colours=None))]
    fn set_reactions(
        slf: &Bound<'_, Self>,
        rules: &Bound<'_, PyAny>,
        seed: Option<&Bound<'_, PyAny>>,
        colours: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let reactions = reactions::from_parts(rules, seed, colours, ["rules", "seed", "colours"])?;
        let mut this = get_mut(slf)?;
        guarded("set_reactions", || {
            each!(&mut this.inner, s => {
                reactions::apply(&mut s.sim, reactions, "rules")?;
                // A kinetics measurement counts the reactions of the rules it started
                // with: under other rules its counts would go wrong, so the measurements
                // start again from now.
                if let Some(m) = s.measuring.as_ref().filter(|m| !m.fits(&s.sim)) {
                    let (which, every) = (m.which.clone(), m.every);
                    s.measure(&which, every);
                }
                Ok(())
            })
        })
    }

    /// Reactions so far, per rule of `reactions["rules"]` (since the rules were set): (k,)
    /// int64; empty without rules.
    #[getter]
    fn reaction_counts<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray1<i64>>> {
        let this = get(slf)?;
        let v: Vec<i64> =
            each!(&this.inner, s => s.sim.reaction_counts().iter().map(|&c| c as i64).collect());
        Ok(PyArray1::from_vec(slf.py(), v))
    }

    /// Heat released by the reactions so far (the sum of their rules' heats; 0.0 without
    /// rules): `kinetic_energy - reaction_heat` is conserved, to rounding (without a
    /// thermostat or a stepped potential).
    #[getter]
    fn reaction_heat(slf: &Bound<'_, Self>) -> PyResult<f64> {
        Ok(each!(&get(slf)?.inner, s => s.sim.reaction_heat()))
    }

    /// The inelastic collisions: None (collisions are elastic), or the dict
    /// {"all", "pairs", "walls", "tc"} in full, as `set_restitution` takes it
    /// (`sim.set_restitution(sim.restitution)` sets it again): "all" the law of every pair of
    /// species not in "pairs", "pairs" a dict {(a, b): law}, "walls" the walls' coefficient,
    /// "tc" the TC model's time; a law is a float e, or {"bridges": v_c}.
    #[getter]
    fn restitution<'py>(slf: &Bound<'py, Self>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let this = get(slf)?;
        each!(&this.inner, s => s.sim.restitution().map(|r| restitution::to_dict(slf.py(), r)))
            .transpose()
    }

    /// Makes collisions inelastic from now on, as a file's `# edmd restitution` lines do: at a
    /// collision the normal relative velocity v_n becomes -e v_n (momentum kept; tangential
    /// velocities unchanged, as for smooth discs), and the pair loses
    /// `(1 - e^2) mu v_n^2 / 2` of kinetic energy (`mu` the reduced mass), added up in
    /// `dissipated`. A disc at a wall leaves with its normal velocity reversed and multiplied
    /// by the walls' coefficient. `e` is a constant, or Bridges, Hatzes and Lin's law for ice
    /// (Nature 309, 333 (1984)), `e(v_n) = min(1, (v_n / v_c)^-0.234)`: elastic below the
    /// speed v_c. A cluster of
    /// inelastic discs can collapse (infinitely many collisions in a finite time, which stops
    /// the clock); the TC model of Luding and McNamara (Granular Matter 1, 113 (1998)) keeps
    /// that from happening: a collision less than `tc` after either disc's previous one (with
    /// a disc or a wall) is elastic. `set_restitution(None)` (or a restitution with every
    /// coefficient 1) makes collisions elastic again. Setting it starts `dissipated` again
    /// from 0 and the TC model's clock with no disc having collided. Pickles and checkpoints
    /// carry the restitution, the energy lost and the TC model's clock, so a restored
    /// simulation continues bit for bit.
    ///
    /// Args:
    ///     restitution: None (elastic); a coefficient e in [0, 1] for every pair of species
    ///         (elastic walls, no TC model); or a dict {"all": LAW, "pairs": {(a, b): LAW,
    ///         ...}, "walls": e, "tc": t}, every key optional (by default "all" 1.0, no
    ///         pairs, "walls" 1.0, "tc" 0.0: the TC model off), a LAW being a coefficient
    ///         e in [0, 1] or {"bridges": v_c} (v_c > 0). Pairs of species are whole numbers
    ///         from 0 to 255; (a, b) and (b, a) are one pair, given once.
    ///
    /// Raises:
    ///     TypeError, ValueError: a bad argument, named in the message with the key
    ///         ("restitution['pairs'][(0, 1)]: ..."): a coefficient outside [0, 1], v_c not
    ///         > 0, a negative tc, numbers that are not finite, a pair given twice;
    ///         restitution with a stepped potential, reaction rules, multi-disc collisions or
    ///         the swap rule. A refused call changes nothing.
    ///
    /// >>> sim.set_restitution(0.9)
    /// >>> sim.set_restitution({"all": 0.9, "pairs": {(0, 1): {"bridges": 0.1}},
    /// ...                      "walls": 0.5, "tc": 1e-4})
    /// >>> sim.run(until=sim.time + 10.0)
    /// >>> sim.kinetic_energy + sim.dissipated   # conserved, to rounding
    /// >>> sim.set_restitution(None)
    #[pyo3(signature = (restitution))]
    fn set_restitution(slf: &Bound<'_, Self>, restitution: &Bound<'_, PyAny>) -> PyResult<()> {
        let restitution = restitution::parse(restitution, "restitution")?;
        let mut this = get_mut(slf)?;
        guarded(
            "set_restitution",
            || each!(&mut this.inner, s => restitution::apply(&mut s.sim, restitution, "restitution")),
        )
    }

    /// Kinetic energy lost in inelastic collisions since the restitution was set (0.0 when
    /// collisions are elastic): `kinetic_energy + dissipated` is conserved, to rounding
    /// (without a thermostat).
    #[getter]
    fn dissipated(slf: &Bound<'_, Self>) -> PyResult<f64> {
        Ok(each!(&get(slf)?.inner, s => s.sim.dissipated()))
    }

    /// The uniform field: None (discs fly straight), or the dict {"axis": k, "g": g}
    /// (`axis` 0 for x, 1 for y, 2 for z; `g` the acceleration along it, negative towards 0),
    /// as `set_gravity` and `from_arrays(gravity=...)` take it (`sim.set_gravity(**sim.gravity)`
    /// sets it again).
    #[getter]
    fn gravity<'py>(slf: &Bound<'py, Self>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let this = get(slf)?;
        each!(&this.inner, s => s.sim.gravity().map(|f| gravity::to_dict(slf.py(), f))).transpose()
    }

    /// Puts the discs in a uniform field from now on, as a file's `# edmd gravity` line does:
    /// each disc's velocity along `axis` grows by `g` per unit time, so that between events
    /// discs fly on parabolas, and the field's potential energy `-sum m g x` (`x` the
    /// coordinate along the axis, from the wall at 0) is `field_energy`, counted in
    /// `potential_energy`: `kinetic_energy + potential_energy` is conserved. The discs'
    /// velocities now are kept; `set_gravity(None)` removes the field (discs fly straight on
    /// from their velocities then). Pickles and checkpoints carry the field, so a restored
    /// simulation continues bit for bit.
    ///
    /// Args:
    ///     g: the acceleration, a finite number other than 0 (negative pulls towards 0,
    ///         "down"); None removes the field; or the dict {"axis": k, "g": g} that
    ///         `Simulation.gravity` gives (then no `axis` beside it).
    ///     axis: 0, 1, 2 or "x", "y", "z"; the last axis (y in 2D, z in 3D) when None. It
    ///         must have walls: along a periodic axis a disc would fall for ever.
    ///
    /// Raises:
    ///     TypeError, ValueError: a bad argument, named in the message ("g: ...",
    ///         "axis: ..."): g not a finite number other than 0, an axis the simulation does
    ///         not have or that is periodic; a field with a stepped potential, barriers or
    ///         multi-disc collisions, or with inelastic collisions without the TC model ("tc"
    ///         > 0) or with walls of coefficient 0. A refused call changes nothing.
    ///
    /// >>> sim.set_gravity(-9.81)              # along y in 2D, z in 3D
    /// >>> sim.set_gravity(-1.0, axis="x")
    /// >>> sim.gravity
    /// {'axis': 0, 'g': -1.0}
    /// >>> sim.kinetic_energy + sim.potential_energy   # conserved
    /// >>> sim.set_gravity(None)
    #[pyo3(signature = (g, *, axis=None))]
    fn set_gravity(
        slf: &Bound<'_, Self>,
        g: &Bound<'_, PyAny>,
        axis: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let field = gravity::from_arguments(g, axis)?;
        let mut this = get_mut(slf)?;
        guarded(
            "set_gravity",
            || each!(&mut this.inner, s => gravity::apply(&mut s.sim, field)),
        )
    }

    /// The field's potential energy now, `-sum m g x` over the discs (`x` the coordinate along
    /// the field's axis, from the wall at 0); 0.0 without a field. It is part of
    /// `potential_energy`.
    #[getter]
    fn field_energy(slf: &Bound<'_, Self>) -> PyResult<f64> {
        Ok(each!(&get(slf)?.inner, s => s.sim.field_energy()))
    }

    /// Lees-Edwards boundaries: None (plain boundaries), or the tuple (rate, offset): the
    /// shear rate du_x/dy and the images' offset along x now, in [0, L_x), as `set_shear` and
    /// `from_arrays(shear=...)` take it (`sim.set_shear(*sim.shear)` changes nothing).
    #[getter]
    fn shear<'py>(slf: &Bound<'py, Self>) -> PyResult<Option<Bound<'py, PyTuple>>> {
        let this = get(slf)?;
        each!(&this.inner, s => s.sim.shear().map(|x| shear::to_tuple(slf.py(), x))).transpose()
    }

    /// Shears the system from now on with Lees-Edwards boundaries, as a file's `# edmd shear`
    /// line does: the images across y slide along x at `rate * L_y` (those above shifted by
    /// `offset`), so that the streaming velocity is `rate * (y - L_y / 2)` along x. A disc
    /// leaving through the top comes back through the bottom with its x shifted by the offset
    /// and its x velocity by `-rate * L_y`. The velocities now are kept: to start in steady
    /// flow add `rate * (y - L_y / 2)` to each x velocity (`edmd.gen.fluid(shear=...)` does).
    /// The thermostat (`set_thermostat`) then draws about the streaming profile, and
    /// `peculiar_velocities`, `peculiar_kinetic_energy` are taken relative to it. Pickles and
    /// checkpoints carry the shear and its offset, so a restored simulation continues bit for
    /// bit.
    ///
    /// Args:
    ///     rate: the shear rate, a finite number (negative: the flow the other way; 0: the
    ///         plain periodic run); None removes the shear; or the tuple (rate, offset) that
    ///         `Simulation.shear` gives (then no `offset` beside it).
    ///     offset: the images' offset along x now, in [0, L_x); when None, the current offset
    ///         if sheared already, else 0.
    ///
    /// Raises:
    ///     TypeError, ValueError: a bad argument, named in the message ("rate: ...",
    ///         "offset: ..."): not a finite number, an offset outside [0, L_x); shear with
    ///         walls on x or y, a stepped potential, a field, barriers or multi-disc
    ///         collisions, or at an offset where the slid images overlap discs. A refused call
    ///         changes nothing.
    ///
    /// >>> sim = edmd.gen.fluid(n=400, packing=0.3, seed=1)
    /// >>> sim.set_shear(0.1)
    /// >>> sim.shear
    /// (0.1, 0.0)
    /// >>> sim.set_shear(None)
    #[pyo3(signature = (rate, offset=None))]
    fn set_shear(
        slf: &Bound<'_, Self>,
        rate: &Bound<'_, PyAny>,
        offset: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let sliding = shear::from_arguments(rate, offset)?;
        let mut this = get_mut(slf)?;
        guarded(
            "set_shear",
            || each!(&mut this.inner, s => shear::apply(&mut s.sim, sliding)),
        )
    }

    /// A patch of a planetary ring: None (none), or its orbital frequency omega, as `set_ring`
    /// and `from_arrays(ring=...)` take it (`sim.set_ring(sim.ring)` changes nothing).
    #[getter]
    fn ring(slf: &Bound<'_, Self>) -> PyResult<Option<f64>> {
        Ok(each!(&get(slf)?.inner, s => s.sim.ring().map(|r| r.omega)))
    }

    /// Makes the system a patch of a planetary ring from now on, as a file's `# edmd ring`
    /// line does (the shearing sheet): x along the orbit, y radial, z vertical (3D), measured
    /// from the box's centre; the particles fly under Hill's equations at orbital frequency
    /// `omega`, and the images across y slide along x at the Keplerian shear rate
    /// `-1.5 * omega` (`shear` is then `(-1.5 * omega, offset)`, the offset kept if the system
    /// was sheared already, else 0). The velocities now are kept: to start on the Keplerian
    /// flow add `-1.5 * omega * (y - L_y / 2)` to each x velocity (`edmd.gen.ring` does).
    /// `peculiar_velocities` and `peculiar_kinetic_energy` are then taken relative to that
    /// flow, and `ring_energy` (the tidal and vertical potential) is part of
    /// `potential_energy`. Inelastic particles with a constant coefficient need the TC model
    /// (`set_restitution({"all": e, "tc": t})`, t > 0) or a cold patch collapses; Bridges'
    /// law needs none. Pickles and checkpoints carry the ring, so a restored simulation
    /// continues bit for bit.
    ///
    /// Args:
    ///     omega: the orbital frequency, a finite number above 0; None takes the ring (and its
    ///         shear) away.
    ///
    /// Raises:
    ///     TypeError, ValueError: a bad argument, named in the message ("omega: ..."): not a
    ///         finite number above 0; a ring in 1D, without periodic x and y, with periodic z
    ///         (3D), beside a field, a stepped potential, barriers or multi-disc collisions;
    ///         another frequency while a ring is set (set_ring(None) first). A refused call
    ///         changes nothing.
    ///
    /// >>> sim = edmd.gen.ring(n=300, seed=1)
    /// >>> sim.ring
    /// 1.0
    /// >>> sim.set_ring(None)
    /// >>> sim.set_ring(1.0)
    #[pyo3(signature = (omega))]
    fn set_ring(slf: &Bound<'_, Self>, omega: &Bound<'_, PyAny>) -> PyResult<()> {
        let patch = ring::parse(omega, "omega")?;
        let mut this = get_mut(slf)?;
        guarded(
            "set_ring",
            || each!(&mut this.inner, s => ring::apply(&mut s.sim, patch, "omega")),
        )
    }

    /// The ring's potential energy now, `sum m (-1.5 omega^2 y^2 + omega^2 z^2 / 2)` with y
    /// and z from the patch's centre (0.0 without a ring): the tidal and vertical potential of
    /// Hill's equations. It is part of `potential_energy`.
    #[getter]
    fn ring_energy(slf: &Bound<'_, Self>) -> PyResult<f64> {
        Ok(each!(&get(slf)?.inner, s => s.sim.ring_energy()))
    }

    /// One-dimensional self-gravity: None (none), or its coupling, as `set_self_gravity` and
    /// `from_arrays(self_gravity=...)` take it (`sim.set_self_gravity(sim.self_gravity)`
    /// changes nothing).
    #[getter]
    fn self_gravity(slf: &Bound<'_, Self>) -> PyResult<Option<f64>> {
        Ok(each!(&get(slf)?.inner, s => s.sim.self_gravity().map(|g| g.coupling)))
    }

    /// Puts the rods of a 1D system under one-dimensional self-gravity from now on, as a
    /// file's `# edmd self-gravity C` line does: each rod of mass m is accelerated by
    /// `coupling * (M_right - M_left)`, the masses on its two sides, as parallel sheets of
    /// mass are (`coupling` is 2 pi G per unit area). Rods keep their order, so each one's
    /// rank, taken now, fixes its acceleration; equal rods exchange velocities at a collision,
    /// which is the sheets passing through each other. `self_gravity_energy` (the sheets'
    /// `U = sum over pairs coupling m_i m_j |y_i - y_j|`) is part of `potential_energy`, and
    /// the virial theorem reads `2 <K> = <U>`. Pickles and checkpoints carry it, so a restored
    /// simulation continues bit for bit.
    ///
    /// Args:
    ///     coupling: a finite number above 0; None takes the self-gravity away.
    ///
    /// Raises:
    ///     TypeError, ValueError: a bad argument, named in the message ("coupling: ..."): not
    ///         a finite number above 0; self-gravity in 2D or 3D, on a periodic line, beside a
    ///         field, a stepped potential, reaction rules, restitution, multi-disc collisions
    ///         or the swap rule. A refused call changes nothing.
    ///
    /// >>> sim = edmd.gen.sheets(n=200, seed=1)
    /// >>> sim.self_gravity
    /// 0.005
    /// >>> sim.set_self_gravity(None)
    /// >>> sim.set_self_gravity(0.005)
    #[pyo3(signature = (coupling))]
    fn set_self_gravity(slf: &Bound<'_, Self>, coupling: &Bound<'_, PyAny>) -> PyResult<()> {
        let gravity = sheets::parse(coupling, "coupling")?;
        let mut this = get_mut(slf)?;
        guarded(
            "set_self_gravity",
            || each!(&mut this.inner, s => sheets::apply(&mut s.sim, gravity, "coupling")),
        )
    }

    /// The sheets' potential energy now, `sum over pairs coupling m_i m_j |y_i - y_j|` with
    /// `y` the sheets' positions (`sheet_positions()`); 0.0 without self-gravity. It is part
    /// of `potential_energy`.
    #[getter]
    fn self_gravity_energy(slf: &Bound<'_, Self>) -> PyResult<f64> {
        Ok(each!(&get(slf)?.inner, s => s.sim.self_gravity_energy()))
    }

    /// The positions of the sheets the rods stand for now: each rod's position less the
    /// contact distances of the rods to its left, so that touching rods are sheets at one
    /// place; an (N,) float64 array in input order, or None without self-gravity.
    ///
    /// >>> sim = edmd.gen.sheets(n=200, seed=1)
    /// >>> sim.sheet_positions().shape
    /// (200,)
    fn sheet_positions<'py>(slf: &Bound<'py, Self>) -> PyResult<Option<Bound<'py, PyArray1<f64>>>> {
        let this = get(slf)?;
        let y = each!(&this.inner, s => s.sim.sheet_positions());
        Ok(y.map(|y| PyArray1::from_vec(slf.py(), y)))
    }

    /// Velocities relative to the streaming profile, `v - (rate * (y - L_y / 2), 0)`: (N, dim)
    /// float64; the velocities themselves without shear.
    #[getter]
    fn peculiar_velocities<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyAny>> {
        let this = get(slf)?;
        guarded(
            "peculiar_velocities",
            || each!(&this.inner, s => arrays::matrix(slf.py(), &s.sim, |i| s.sim.peculiar_velocity(i).0)),
        )
    }

    /// Kinetic energy of the velocities relative to the streaming profile,
    /// sum m |v - u(y)|^2 / 2 (`kinetic_energy` without shear): the temperature of a sheared
    /// fluid is 2 * peculiar_kinetic_energy / (dim * n).
    #[getter]
    fn peculiar_kinetic_energy(slf: &Bound<'_, Self>) -> PyResult<f64> {
        Ok(each!(&get(slf)?.inner, s => s.sim.peculiar_kinetic_energy()))
    }

    /// How many discs are of each species now: an int64 array indexed by species, from 0 to
    /// the largest species a disc is or a rule names (so a product not made yet counts 0).
    #[getter]
    fn species_counts<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray1<i64>>> {
        let this = get(slf)?;
        let v = each!(&this.inner, s => species_counts(&s.sim));
        Ok(PyArray1::from_vec(slf.py(), v))
    }

    fn __repr__(slf: &Bound<'_, Self>) -> PyResult<String> {
        let this = get(slf)?;
        let lengths: Vec<String> = this.lengths().iter().map(|l| num(*l)).collect();
        let boundaries: Vec<String> = this.boundaries().iter().map(|b| format!("'{b}'")).collect();
        Ok(format!(
            "Simulation(dim={}, n={}, time={}, box=({}), boundary=({}))",
            this.dimension(),
            this.len(),
            num(this.time()),
            lengths.join(", "),
            boundaries.join(", ")
        ))
    }
}

/// Discs of each species, indexed by species, up to the largest species a disc is or a rule
/// names (the width of the engine's `Kinetics` counts).
fn species_counts<const D: usize>(sim: &Simulation<D>) -> Vec<i64> {
    let named = sim.reactions().map_or(0, |r| {
        r.rules
            .iter()
            .flat_map(|r| [r.reactants.0, r.reactants.1, r.products.0, r.products.1])
            .map(|s| usize::from(s) + 1)
            .max()
            .unwrap_or(0)
    });
    let width = (0..sim.len())
        .map(|i| usize::from(sim.species(i)) + 1)
        .max()
        .unwrap_or(0)
        .max(named);
    let mut counts = vec![0i64; width];
    for i in 0..sim.len() {
        counts[usize::from(sim.species(i))] += 1;
    }
    counts
}

impl PySimulation {
    /// `from_file`'s work.
    #[allow(clippy::too_many_arguments)]
    fn read_file(
        path: PathBuf,
        frame: Option<i64>,
        format: Option<&str>,
        columns: Option<&str>,
        rule: Option<&str>,
        multi: bool,
        allow_overlaps: bool,
        seed: Option<u64>,
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
        if let Some(bytes) = edmd::checkpoint::read_checkpoint(&path).map_err(cli_error)? {
            if frame.is_some()
                || format.is_some()
                || columns.is_some()
                || rule.is_some()
                || multi
                || allow_overlaps
                || seed.is_some()
            {
                return Err(value_error(format!(
                    "{name}: a checkpoint carries its run's options: drop frame, format, columns, rule, multi, allow_overlaps and seed"
                )));
            }
            return Ok(PySimulation {
                inner: from_checkpoint(&bytes, &name)?,
            });
        }
        let seed = seed.unwrap_or(edmd::input::DEFAULT_SEED);
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
        let loaded = edmd::input::read_any(&name, format, order, frame).map_err(cli_error)?;
        let inner = match loaded {
            edmd_io::AnyLoaded::Two(sys) => {
                if columns.is_some() && sys.format == Format::Course {
                    return Err(value_error(format!(
                        "{name}: columns applies to the Princeton format, and this is a course file (N, R, Lx Ly, then x y u v)"
                    )));
                }
                Inner::Two(State::new(
                    built(&name, &sys, opts(sys.format)?, seed)?,
                    sys.format,
                ))
            }
            edmd_io::AnyLoaded::Three(sys) => Inner::Three(State::new(
                built(&name, &sys, opts(sys.format)?, seed)?,
                sys.format,
            )),
            edmd_io::AnyLoaded::One(sys) => Inner::One(State::new(
                built(&name, &sys, opts(sys.format)?, seed)?,
                sys.format,
            )),
        };
        Ok(PySimulation { inner })
    }
}

/// What `sim` has beyond hard cores that only the Princeton format and checkpoints hold, in
/// words for messages (the first of them); `None` for hard cores alone.
fn beyond_hard_cores<const D: usize>(sim: &Simulation<D>) -> Option<&'static str> {
    if sim.ring().is_some() {
        Some("the ring patch")
    } else if sim.self_gravity().is_some() {
        Some("the self-gravity")
    } else if sim.is_stepped() {
        Some("the stepped potential")
    } else if sim.reactions().is_some() {
        Some("the reaction rules")
    } else if sim.restitution().is_some() {
        Some("the restitution")
    } else if sim.gravity().is_some() {
        Some("the field")
    } else if sim.shear().is_some() {
        Some("the shear")
    } else {
        None
    }
}

/// The bytes of the file `write` makes: the state in format `kind`.
fn render(inner: &Inner, kind: &str, path: &Path) -> PyResult<Vec<u8>> {
    let mut w = Vec::new();
    each!(inner, s => {
        let discs = s.sim.discs();
        match kind {
            "gsd" | "xyz" if beyond_hard_cores(&s.sim).is_some() => {
                let what = beyond_hard_cores(&s.sim).unwrap_or_default();
                return Err(value_error(format!(
                    "{}: cannot write the state as {kind}: it has no place for {what} (write the Princeton format, or a checkpoint)",
                    path.display()
                )));
            }
            "xyz" => edmd_io::xyz::write_frame(&mut w, &discs, s.sim.sim_box(), s.sim.time())
                .map_err(io_error)?,
            "gsd" => {
                // hoomd-gsd writes files by path: the frame goes to a scratch file, whose
                // bytes are then written like every other format's. Exact: edmd reads its own
                // state back bit for bit (float64 copies beside HOOMD's float32 chunks).
                let dir = tempfile::tempdir().map_err(io_error)?;
                let scratch = dir.path().join("state.gsd");
                let mut g = edmd_io::gsd::Writer::create(&scratch, edmd_io::gsd::Precision::Exact)
                    .map_err(|e| gsd_error(path, e))?;
                g.append_simulation(&s.sim).map_err(|e| gsd_error(path, e))?;
                g.finish().map_err(|e| gsd_error(path, e))?;
                w = std::fs::read(&scratch).map_err(io_error)?;
            }
            "checkpoint" => w = checkpoint_bytes(s)?,
            other => match format_from_name(other) {
                Some(Format::Course) if beyond_hard_cores(&s.sim).is_some() => {
                    return Err(value_error(format!(
                        "{}: cannot write the course format: it has no place for {} (write the Princeton format, or a checkpoint)",
                        path.display(),
                        beyond_hard_cores(&s.sim).unwrap_or_default()
                    )))
                }
                Some(Format::Course) if s.sim.sim_box().lengths.len() == 2 => {
                    let flat: Vec<edmd_core::Disc> = discs.iter().map(|d| d.with_dim()).collect();
                    let b = s.sim.sim_box();
                    let flat_box = edmd_core::SimBox {
                        lengths: std::array::from_fn(|a| b.lengths[a]),
                        boundaries: std::array::from_fn(|a| b.boundaries[a]),
                    };
                    match edmd_io::course::fits(&flat, &flat_box, s.sim.barriers()) {
                        Ok(()) => edmd_io::course::write(&mut w, &flat, &flat_box).map_err(io_error)?,
                        Err(why) => {
                            return Err(value_error(format!(
                                "{}: cannot write the course format: {why}",
                                path.display()
                            )))
                        }
                    }
                }
                Some(Format::Course) => {
                    return Err(value_error(format!(
                        "format: the course format holds 2D systems only, not {}D",
                        s.sim.sim_box().lengths.len()
                    )))
                }
                // The stepped potential, the reaction rules and the restitution, if any, as
                // `# edmd potential`, `# edmd reaction` and `# edmd restitution` lines (as
                // `edmd run` writes its output).
                Some(fmt) => {
                    let hard = edmd_core::Potential::default();
                    let interactions = edmd_io::Interactions {
                        potential: s.sim.potential().unwrap_or(&hard),
                        reactions: s.sim.reactions().map_or(&[], |r| &r.rules),
                        restitution: s.sim.restitution(),
                        gravity: s.sim.gravity(),
                        shear: s.sim.shear(),
                        self_gravity: s.sim.self_gravity(),
                    };
                    edmd_io::write_full_ring(&mut w, &discs, s.sim.sim_box(), s.sim.barriers(), interactions, s.sim.ring(), fmt, s.sim.time())
                        .map_err(io_error)?
                }
                None => {
                    return Err(value_error(format!(
                        "format: expected 'princeton', 'princeton-mass-radius', 'course', 'xyz', 'gsd' or 'checkpoint', got '{other}'"
                    )))
                }
            },
        }
    });
    Ok(w)
}

/// The loop of `run(until=...)`: chunks to the next frame, sample or callback, each written,
/// taken or called there, then on to `until`. A trajectory that fails to write is dropped (its
/// temporary file removed) before the error is returned.
#[allow(clippy::too_many_arguments)]
fn run_until(
    slf: &Bound<'_, PySimulation>,
    now: f64,
    until: f64,
    every: Option<f64>,
    callback_every: Option<f64>,
    callback: Option<&Bound<'_, PyAny>>,
    traj: &mut Option<Trajectory>,
) -> PyResult<()> {
    // Frames at whole multiples of `every` in absolute time (as `edmd run --every`),
    // callbacks at the multiples of `callback_every` after now.
    let mut frame_k = every.map_or(0.0, |dt| (now / dt).ceil());
    let mut call_k = callback_every.map_or(0.0, |dt| (now / dt).floor() + 1.0);
    let mut span = 0.0;
    loop {
        let next_frame = every.map(|dt| frame_k * dt).filter(|t| *t <= until);
        let next_call = callback_every.map(|dt| call_k * dt).filter(|t| *t <= until);
        let next_sample = each!(&borrow(slf)?.inner, s => s
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
            return Ok(());
        }
        if next_frame == Some(next) {
            if let Some(t) = traj.as_mut() {
                if let Err(e) = t.frame(&borrow(slf)?.inner) {
                    *traj = None;
                    return Err(e);
                }
            }
            frame_k += 1.0;
        }
        if next_sample == Some(next) {
            each!(&mut borrow_mut(slf)?.inner, s => s.sample_if_due());
        }
        if next_call == Some(next) {
            if let Some(c) = callback {
                c.call1((slf,))?;
            }
            call_k += 1.0;
        }
    }
}

/// A `ValueError` naming the discs when the run's clock stopped advancing (the engine then
/// stays at that time: a box filled with touching discs, say).
fn stalled(slf: &Bound<'_, PySimulation>) -> PyResult<()> {
    match each!(&borrow(slf)?.inner, s => s.stalled()) {
        Some(why) => Err(value_error(why)),
        None => Ok(()),
    }
}

/// Runs to `t` in chunks with the GIL released, checking for Ctrl-C between them.
fn advance(slf: &Bound<'_, PySimulation>, t: f64, span: &mut f64) -> PyResult<()> {
    let py = slf.py();
    loop {
        let done = {
            let mut guard = borrow_mut(slf)?;
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
            let mut guard = borrow_mut(slf)?;
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
fn _restore(data: &Bound<'_, PyAny>) -> PyResult<PySimulation> {
    PySimulation::from_checkpoint(data)
}

/// Makes a system as `edmd gen KIND` does (same checks, messages and seeds) and returns it as
/// a simulation. Called by the functions in `edmd.gen`.
#[pyfunction]
#[pyo3(signature = (kind, *, dim=2, seed=1, course=false, n=None, radius=None, speed=None, mass=None, kt=None, packing=None, boundary=None, angle=None, impact=None, region=None, big_radius=None, big_mass=None, size_ratio=None, fraction_large=None, spread=None, well=None, shoulder=None, depth=None, rule="elastic", multi=false, species=None, reactions=None, restitution=None, gravity=None, shear=None, tau=None, omega=None, dispersion=None, height=None, width=None, coupling=None))]
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
    well: Option<f64>,
    shoulder: Option<f64>,
    depth: Option<f64>,
    rule: &str,
    multi: bool,
    species: Option<&Bound<'_, PyAny>>,
    reactions: Option<&Bound<'_, PyAny>>,
    restitution: Option<&Bound<'_, PyAny>>,
    gravity: Option<f64>,
    shear: Option<f64>,
    tau: Option<f64>,
    omega: Option<f64>,
    dispersion: Option<f64>,
    height: Option<f64>,
    width: Option<f64>,
    coupling: Option<f64>,
) -> PyResult<PySimulation> {
    use edmd::gen::{make_with, ChemistryArgs, GenArgs, Generated};
    let dim = edmd::options::parse_dim_with_rods(&dim.to_string())
        .map_err(|e| value_error(format!("dim: {e}")))?;
    let boundary = parse_boundary(boundary, "boundary")?;
    let opts = options(rule, multi, false)?;
    // `edmd gen --species F0,F1,... --reaction RULE ...`: the fractions and the rules' texts
    // are given to the command's own function, which checks them as it checks its options.
    let fractions = species
        .filter(|s| !s.is_none())
        .map(|s| arrays::float_vector(s, "species", "the number fractions of species 0, 1, ..."))
        .transpose()?;
    let reactions = match reactions {
        Some(r) => reactions::parse(r, "reactions")?,
        None => None,
    };
    // `edmd gen --restitution TEXT ...`: the texts of the restitution's directives, checked
    // beside the other options by the command's own function.
    let restitution_texts = match restitution {
        Some(r) => restitution::parse(r, "restitution")?
            .as_ref()
            .map_or_else(Vec::new, restitution::directives),
        None => Vec::new(),
    };
    let chemistry = ChemistryArgs {
        species: fractions.map(|f| {
            f.iter()
                .map(|x| format!("{x:?}"))
                .collect::<Vec<_>>()
                .join(",")
        }),
        reaction: reactions.as_ref().map_or_else(Vec::new, |r| {
            r.rules.iter().map(edmd_io::reaction::text).collect()
        }),
    };
    let args = GenArgs {
        kind: kind.to_string(),
        output: String::new(),
        dim: Some(dim),
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
        well,
        shoulder,
        depth,
        gravity,
        shear,
        tau,
        omega,
        dispersion,
        height,
        width,
        coupling,
    };
    // `edmd gen`'s messages, with the Python argument names instead of its flags.
    let message = |e: anyhow::Error| {
        let mut m = format!("{e:#}")
            .replace('\n', " ")
            .replace("--restitution", "restitution")
            .replace("--reaction", "reactions");
        for flag in [
            "fraction-large",
            "size-ratio",
            "big-radius",
            "big-mass",
            "radius",
            "speed",
            "mass",
            "kt",
            "packing",
            "boundary",
            "angle",
            "impact",
            "region",
            "spread",
            "shoulder",
            "well",
            "depth",
            "gravity",
            "shear",
            "course",
            "tau",
            "omega",
            "dispersion",
            "height",
            "width",
            "coupling",
            "seed",
            "species",
            "dim",
            "n",
        ] {
            m = m.replace(&format!("--{flag}"), &flag.replace('-', "_"));
        }
        // The range of a well or shoulder is named in words only.
        if m.contains("the range must be") {
            if let Some(name) = [("well", well), ("shoulder", shoulder)]
                .iter()
                .find_map(|(name, v)| v.map(|_| *name))
            {
                m = format!("{name}: {m}");
            }
        }
        value_error(m)
    };
    /// The simulation of a generated system, with the potential `--well` or `--shoulder`
    /// asks for (as `edmd run` builds the file `edmd gen` writes).
    fn build<const D: usize>(
        system: &edmd_core::System<D>,
        potential: &edmd_core::Potential,
        opts: Options,
        kind: &str,
    ) -> PyResult<Simulation<D>> {
        if potential.is_hard() {
            Simulation::from_system(system, opts)
        } else {
            Simulation::with_potential_at(
                &system.discs,
                system.sim_box,
                &system.barriers,
                potential,
                opts,
                0.0,
            )
        }
        .map_err(|e| value_error(format!("gen {kind}: {e}")))
    }
    /// [`build`] with the rules, the field, the restitution and the shear, as `edmd run` sets
    /// those of the file `edmd gen` writes (in that order: restitution in a field is refused
    /// without the TC model).
    #[allow(clippy::too_many_arguments)]
    fn reactive<const D: usize>(
        system: &edmd_core::System<D>,
        potential: &edmd_core::Potential,
        opts: Options,
        kind: &str,
        reactions: Option<edmd_core::Reactions>,
        field: Option<edmd_core::Gravity>,
        restitution: Option<edmd_core::Restitution>,
        sliding: Option<edmd_core::Shear>,
        patch: Option<edmd_core::Ring>,
        sheets: Option<edmd_core::SelfGravity>,
    ) -> PyResult<Simulation<D>> {
        let mut sim = build(system, potential, opts, kind)?;
        reactions::apply(&mut sim, reactions, "reactions")?;
        gravity::apply(&mut sim, field.map(|f| gravity::Field::of(f, "gravity")))?;
        restitution::apply(&mut sim, restitution, "restitution")?;
        shear::apply(&mut sim, sliding.map(|s| shear::Sliding::of(s, "shear")))?;
        ring::apply(&mut sim, patch, "omega")?;
        sheets::apply(&mut sim, sheets, "coupling")?;
        Ok(sim)
    }
    guarded("gen", || {
        let restitution =
            edmd::gen::restitution_of(&args, &chemistry, &restitution_texts).map_err(message)?;
        let (generated, _) = make_with(&args, &chemistry).map_err(message)?;
        let potential = args.potential_of(&generated).map_err(message)?;
        let field = edmd::gen::gravity_of(&args, &generated).map_err(message)?;
        let sliding = edmd::gen::shear_of(&args, &generated).map_err(message)?;
        let patch = edmd::gen::ring_of(&args).map_err(message)?;
        if let (Some(_), Some(r)) = (patch, &restitution) {
            edmd::gen::check_ring_restitution(r, kind).map_err(message)?;
        }
        let sheets = edmd::gen::self_gravity_of(&args).map_err(message)?;
        edmd::gen::check_self_gravity_with(&args, restitution.is_some(), reactions.is_some())
            .map_err(message)?;
        match generated {
            Generated::Two(_, Format::Course) if !potential.is_hard() => Err(value_error(format!(
                "gen {kind}: the course format has no place for a potential (course with well or shoulder)"
            ))),
            Generated::Two(system, format) => Ok(PySimulation {
                inner: Inner::Two(State::new(
                    reactive(&system, &potential, opts, kind, reactions, field, restitution, sliding, patch, sheets)?,
                    format,
                )),
            }),
            Generated::Three(system) => Ok(PySimulation {
                inner: Inner::Three(State::new(
                    reactive(&system, &potential, opts, kind, reactions, field, restitution, sliding, patch, sheets)?,
                    Format::Princeton(ColumnOrder::RadiusMass),
                )),
            }),
            Generated::One(system) => Ok(PySimulation {
                inner: Inner::One(State::new(
                    reactive(&system, &potential, opts, kind, reactions, field, restitution, sliding, patch, sheets)?,
                    Format::Princeton(ColumnOrder::RadiusMass),
                )),
            }),
        }
    })
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
