//! `edmd.pack`: the compression of `edmd pack`, by the library function the command calls
//! (`edmd::pack::pack`), so the Python packing is the command's bit for bit.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use edmd::pack::{pack as cli_pack, read_pack_checkpoint, Given, PackArgs, Packed, Start};
use edmd::MAX_N;
use edmd_core::pack::Status;
use edmd_core::{Options, Simulation};
use edmd_io::princeton::ColumnOrder;
use edmd_io::Format;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use crate::state::State;
use crate::{parse_boundary, value_error, Inner, PySimulation};

/// How often the compression looks for Ctrl-C (it is asked every 65 536 events, a few
/// milliseconds, and takes the GIL to look only this often).
const SIGNAL_EVERY: Duration = Duration::from_millis(50);

/// The command's message with the Python argument names instead of its flags.
fn message(e: anyhow::Error) -> PyErr {
    let mut m = format!("{e:#}").replace('\n', " ");
    for (flag, name) in [
        ("a FILE to start from", "a start (a Simulation)"),
        ("--growth-rate", "growth_rate"),
        ("--fraction-large", "fraction_large"),
        ("--size-ratio", "size_ratio"),
        ("--polydispersity", "polydispersity"),
        ("--pressure", "pressure"),
        ("--packing", "packing"),
        ("--boundary", "boundary"),
        ("--dim", "dim"),
        ("--n", "n"),
        ("--seed", "seed"),
        ("--checkpoint", "checkpoint"),
    ] {
        m = m.replace(flag, name);
    }
    value_error(m)
}

fn simulation<const D: usize>(packing: &edmd_core::pack::Packing<D>) -> PyResult<State<D>> {
    let sim = Simulation::new(&packing.discs, packing.sim_box, Options::default())
        .map_err(|e| value_error(format!("pack: the packing does not run: {e}")))?;
    Ok(State::new(sim, Format::Princeton(ColumnOrder::RadiusMass)))
}

/// Compresses hard discs or spheres to a jammed packing (Lubachevsky-Stillinger), or to a
/// packing fraction below jamming, as `edmd pack` does: the same options, checks and seeds give
/// the same packing bit for bit (the file `edmd pack -o FILE` writes).
///
/// The diameters grow at a common rate while the particles collide, with velocities rescaled
/// to an rms speed of 1 every 10 collisions per particle. The compression runs with the GIL
/// released; Ctrl-C stops it with `KeyboardInterrupt` within a fraction of a second, whatever
/// the number of particles (with `checkpoint`, the last velocity rescaling's state is written
/// there first, so that `resume` continues it bit for bit).
///
/// A long compression can be checkpointed and continued, bit for bit, as with
/// `edmd pack --checkpoint`: `checkpoint=PATH` writes its whole state there (replaced
/// atomically) every `checkpoint_every` wall-clock seconds and when Ctrl-C stops it, and
/// `resume=PATH` continues from such a file (written by Python or by `edmd pack`) to the packing
/// and summary of the compression never stopped.
///
/// Args:
///     n: number of particles of a random start.
///     dim: 2 (discs) or 3 (spheres) for a random start; 3 when None.
///     growth_rate: G in (0, 1]: the largest diameter grows as dD/dt = G v_rms. Slower
///         growth gives denser packings. 0.02 when None.
///     pressure: stop when the reduced pressure PV/(NkT) passes this (above 1); 1e12 when
///         None.
///     packing: stop exactly at this packing fraction (below jamming: dense fluids, glasses).
///     size_ratio: bidisperse random start: diameter ratio large/small.
///     fraction_large: bidisperse: number fraction of large particles (0.5 when None).
///     polydispersity: diameters uniform with this relative standard deviation (mean 1).
///     boundary: "periodic" (default) or "walls", for a random start.
///     seed: the same seed gives the same packing; 1 when None.
///     start: a Simulation to compress from its current positions, radii (the initial sizes,
///         which all grow by one factor), masses and velocities (thermal ones from `seed` if
///         all are at rest), instead of a random start. Not with n, dim, size_ratio,
///         fraction_large, polydispersity or boundary.
///     checkpoint: a file to write checkpoints of the compression to.
///     checkpoint_every: wall-clock seconds between checkpoints, each taken at the first
///         velocity rescaling after the interval (0: at every rescaling); 600 when None.
///     resume: a packing checkpoint file to continue, instead of a start. Every option that
///         decides the compression (n, dim, the sizes, boundary, growth_rate, pressure,
///         packing, seed) comes from it: given again, it must have the value it carries.
///
/// Returns:
///     (sim, summary): the packing as a Simulation at time 0 ready to run (elastic
///     collisions), and a dict with what `edmd pack --json` prints: "packing_fraction",
///     "reduced_pressure" (None if none was measured), "stop" ("pressure", "converged" or
///     "packing"), "rattlers", "mean_contacts" (per non-rattler; None if all rattle),
///     "gap_tolerance", "min_gap", "collisions", "wall_collisions", "rescales",
///     "wall_seconds", "collisions_per_second", "dim", "n", "growth_rate", "seed".
///
/// Raises:
///     ValueError: bad options, with one message naming them.
///     KeyboardInterrupt: Ctrl-C during the compression.
///
/// >>> sim, summary = edmd.pack(n=200, dim=3, pressure=1e6, seed=1)
/// >>> summary["packing_fraction"]
/// >>> sim.run(until=1.0)
#[pyfunction]
#[pyo3(signature = (n=None, *, dim=None, growth_rate=None, pressure=None, packing=None, size_ratio=None, fraction_large=None, polydispersity=None, boundary=None, seed=None, start=None, checkpoint=None, checkpoint_every=None, resume=None))]
#[allow(clippy::too_many_arguments)]
pub fn pack<'py>(
    py: Python<'py>,
    n: Option<i128>,
    dim: Option<i128>,
    growth_rate: Option<f64>,
    pressure: Option<f64>,
    packing: Option<f64>,
    size_ratio: Option<f64>,
    fraction_large: Option<f64>,
    polydispersity: Option<f64>,
    boundary: Option<&str>,
    seed: Option<i128>,
    start: Option<PyRef<'py, PySimulation>>,
    checkpoint: Option<PathBuf>,
    checkpoint_every: Option<f64>,
    resume: Option<PathBuf>,
) -> PyResult<Bound<'py, PyTuple>> {
    let n = match n {
        None => None,
        Some(k) if (2..=MAX_N as i128).contains(&k) => Some(k as usize),
        Some(k) => {
            return Err(value_error(format!(
                "pack: n must be from 2 to {MAX_N}, found {k}"
            )))
        }
    };
    let dim = match dim {
        None => None,
        Some(d @ (2 | 3)) => Some(d as usize),
        Some(d) => return Err(value_error(format!("pack: dim must be 2 or 3, found {d}"))),
    };
    let seed = seed
        .map(|seed| {
            u64::try_from(seed).map_err(|_| {
                value_error(format!(
                    "pack: seed must be a whole number from 0 to 2^64 - 1, found {seed}"
                ))
            })
        })
        .transpose()?;
    if let Some(s) = checkpoint_every {
        if s.is_nan() || s < 0.0 {
            return Err(value_error(format!(
                "pack: checkpoint_every must be a number of seconds >= 0, found {s}"
            )));
        }
        if checkpoint.is_none() {
            return Err(value_error("pack: checkpoint_every goes with checkpoint"));
        }
    }
    if resume.is_some() && start.is_some() {
        return Err(value_error(
            "pack: give a start or a checkpoint to resume, not both",
        ));
    }
    let boundary = parse_boundary(boundary, "pack: boundary")?;
    let args = PackArgs {
        file: None,
        output: String::new(),
        // A random start is 3D unless told (the command's default is 2D).
        dim: if start.is_none() && resume.is_none() {
            dim.or(Some(3))
        } else {
            dim
        },
        n,
        size_ratio,
        fraction_large,
        polydispersity,
        growth_rate,
        pressure,
        packing,
        boundary,
        seed,
        json: false,
        checkpoint,
        checkpoint_every,
    };
    let resumed = match &resume {
        Some(path) => match read_pack_checkpoint(path).map_err(message)? {
            Some(bytes) => Some(bytes),
            None => {
                return Err(value_error(format!(
                    "{}: not an edmd packing checkpoint (no EDMDPACK magic number)",
                    path.display()
                )))
            }
        },
        None => None,
    };
    let resume_name = resume
        .as_ref()
        .map(|p| p.display().to_string())
        .unwrap_or_default();
    if let Some(Inner::One(_)) = start.as_ref().map(|s| &s.inner) {
        return Err(value_error(
            "start: rods on a line (1D) are not packed: edmd.gen.fluid(dim=1, packing=ETA) makes a line of any packing below 1",
        ));
    }
    let given = start.map(|s| {
        let (start, barriers, stepped) = match &s.inner {
            Inner::One(_) => unreachable!("refused above"),
            Inner::Two(s) => (
                Start::Two(s.sim.discs(), *s.sim.sim_box()),
                !s.sim.barriers().is_empty(),
                s.sim.is_stepped(),
            ),
            Inner::Three(s) => (
                Start::Three(s.sim.discs(), *s.sim.sim_box()),
                !s.sim.barriers().is_empty(),
                s.sim.is_stepped(),
            ),
        };
        Given {
            name: "start",
            what: "start",
            start,
            barriers,
            stepped,
            lines: Vec::new(),
        }
    });
    let given = match resumed {
        Some(bytes) => Some(Given {
            name: &resume_name,
            what: &resume_name,
            start: Start::Checkpoint(bytes),
            barriers: false,
            stepped: false,
            lines: Vec::new(),
        }),
        None => given,
    };
    // Ctrl-C: the compression asks every few milliseconds whether to stop; every
    // SIGNAL_EVERY it looks at Python's signals (with the GIL taken for a moment) and stops
    // when one raised.
    let mut interrupt: Option<PyErr> = None;
    let packed = py.detach(|| {
        let mut last = Instant::now();
        let stop = || {
            if interrupt.is_some() {
                return true;
            }
            if last.elapsed() < SIGNAL_EVERY {
                return false;
            }
            last = Instant::now();
            match Python::attach(|py| py.check_signals()) {
                Ok(()) => false,
                Err(e) => {
                    interrupt = Some(e);
                    true
                }
            }
        };
        cli_pack(&args, given, stop, |_: &Status| true)
    });
    if let Some(e) = interrupt {
        return Err(e);
    }
    let packed = packed.map_err(message)?;
    let summary =
        serde_json::to_value(packed.summary()).map_err(|e| value_error(format!("pack: {e}")))?;
    let inner = match &packed {
        Packed::Two(p, _) => Inner::Two(simulation(p)?),
        Packed::Three(p, _) => Inner::Three(simulation(p)?),
    };
    let mut summary = summary;
    if let Some(map) = summary.as_object_mut() {
        map.remove("output");
    }
    let dict = py
        .import("json")?
        .call_method1("loads", (summary.to_string(),))?
        .cast_into::<PyDict>()?;
    let sim = Bound::new(py, PySimulation { inner })?;
    PyTuple::new(py, [sim.into_any(), dict.into_any()])
}
