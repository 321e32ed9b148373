//! A run's checkpoint: the engine's state ([`edmd_core::Simulation::to_checkpoint`]) with what
//! the run keeps beside it, the format of the file it started from and the measurements under
//! way, so that `edmd run FILE.ckpt` and Python's pickles continue each other's runs.

use std::io::Write;
use std::path::Path;

use anyhow::Result;
use edmd_core::Simulation;
use edmd_io::princeton::ColumnOrder;
use edmd_io::Format;
use serde::{Deserialize, Serialize};

use crate::measure::{Measure, Measurements};
use crate::output::AtomicFile;
use crate::user_error;

/// What a checkpoint keeps besides the engine state: the format of the file the run started
/// from (the final state is written in it) and the measurements under way. `M` is
/// `&Measuring` when written and `Measuring` when read: serde writes both the same way.
#[derive(Serialize, Deserialize)]
struct CheckpointExtra<M> {
    format: String,
    measuring: Option<M>,
}

/// Measurements under way and their sampling schedule: samples at `start + k * every`. Kept
/// in checkpoints (by `edmd run` and by the Python package's pickles).
#[derive(Serialize, Deserialize)]
#[serde(bound = "")]
pub struct Measuring<const D: usize> {
    /// What is measured (sorted, each once).
    pub which: Vec<Measure>,
    /// Simulated time between samples.
    pub every: f64,
    /// When the measurements started.
    pub start: f64,
    /// Samples taken.
    pub samples: u64,
    /// The observers.
    pub obs: Measurements<D>,
}

/// [`Measuring`] as checkpoints kept it with earlier measurements `M` (which become today's).
#[derive(Deserialize)]
struct MeasuringBefore<M> {
    which: Vec<Measure>,
    every: f64,
    start: f64,
    samples: u64,
    obs: M,
}

/// The extra bytes of a checkpoint whose measurements are `M`, an earlier [`Measurements`],
/// read as today's.
fn read_extra_before<const D: usize, M>(extra: &[u8]) -> Option<CheckpointExtra<Measuring<D>>>
where
    M: for<'de> Deserialize<'de> + Into<Measurements<D>>,
{
    let e = postcard::from_bytes::<CheckpointExtra<MeasuringBefore<M>>>(extra).ok()?;
    Some(CheckpointExtra {
        format: e.format,
        measuring: e.measuring.map(|m| Measuring {
            which: m.which,
            every: m.every,
            start: m.start,
            samples: m.samples,
            obs: m.obs.into(),
        }),
    })
}

impl<const D: usize> Measuring<D> {
    /// Starts measuring `which` on `sim` now, a sample every `every`.
    pub fn new(sim: &Simulation<D>, which: &[Measure], every: f64) -> Self {
        let mut which = which.to_vec();
        which.sort();
        which.dedup();
        Measuring {
            obs: Measurements::new(sim, &which),
            which,
            every,
            start: sim.time(),
            samples: 0,
        }
    }

    /// Time of the next sample.
    pub fn next_sample(&self) -> f64 {
        self.start + (self.samples + 1) as f64 * self.every
    }

    /// Runs `sim` to time `t` with these measurements watching, taking the samples due on the
    /// way (at `start + k * every`, as `edmd run --measure` takes them). Looks at the stop
    /// flag ([`crate::stop::stop_requested`]) every [`crate::STOP_CHECK_EVENTS`] events:
    /// `Ok(false)` when a stop was requested before `t`, `Ok(true)` once at `t`. A run whose
    /// clock stops advancing is an error naming the discs.
    pub fn run_to(&mut self, sim: &mut Simulation<D>, t: f64) -> Result<bool> {
        loop {
            let next = self.next_sample();
            let to = if self.every > 0.0 && next <= t {
                next
            } else {
                t
            };
            if !crate::run_until_or_stop(sim, to, &mut self.obs)? {
                return Ok(false);
            }
            if to < t || (self.every > 0.0 && next == t) {
                self.obs.sample(sim);
                self.samples += 1;
            }
            if to >= t {
                return Ok(true);
            }
        }
    }

    /// Whether measurements read back from a checkpoint can go on with `sim`.
    pub fn fits(&self, sim: &Simulation<D>) -> bool {
        self.obs.fits(sim) && !self.which.is_empty() && self.every > 0.0
    }
}

/// The name a checkpoint keeps for the format of the file its run started from.
pub fn format_name(format: Format) -> &'static str {
    match format {
        Format::Course => "course",
        Format::Princeton(ColumnOrder::RadiusMass) => "princeton",
        Format::Princeton(ColumnOrder::MassRadius) => "princeton-mass-radius",
    }
}

/// The format and the measurements kept in a checkpoint's extra bytes; `None` when they cannot
/// be read.
pub fn read_extra<const D: usize>(extra: &[u8]) -> Option<(Format, Option<Measuring<D>>)> {
    // Each field is read in turn and postcard has no field names, so a checkpoint written
    // before a measurement was added ends early for today's layout and is read with its own.
    let extra = postcard::from_bytes::<CheckpointExtra<Measuring<D>>>(extra)
        .ok()
        // Written before the shear stress was measured.
        .or_else(|| read_extra_before::<D, crate::measure::MeasurementsBeforeShearStress<D>>(extra))
        // Written before the thermal conductivity was measured.
        .or_else(|| {
            read_extra_before::<D, crate::measure::MeasurementsBeforeConductivity<D>>(extra)
        })
        // Written before the viscosity was measured.
        .or_else(|| read_extra_before::<D, crate::measure::MeasurementsBeforeViscosity<D>>(extra))
        // Written before kinetics were measured.
        .or_else(|| read_extra_before::<D, crate::measure::MeasurementsBeforeKinetics<D>>(extra))
        // Written before energy and g(r) were measured.
        .or_else(|| read_extra_before::<D, crate::measure::MeasurementsBefore<D>>(extra))?;
    let format = match extra.format.as_str() {
        "course" => Format::Course,
        "princeton-mass-radius" => Format::Princeton(ColumnOrder::MassRadius),
        "princeton" => Format::Princeton(ColumnOrder::RadiusMass),
        _ => return None,
    };
    Some((format, extra.measuring))
}

/// The bytes of a checkpoint of `sim`, as `edmd run --checkpoint` writes them for a run that
/// started from a file of `format` with the measurements `measuring` under way (the Python
/// package pickles with these, so that either program continues the other's checkpoints).
pub fn checkpoint_bytes<const D: usize>(
    sim: &Simulation<D>,
    format: Format,
    measuring: Option<&Measuring<D>>,
) -> Result<Vec<u8>> {
    let extra = CheckpointExtra {
        format: format_name(format).to_string(),
        measuring: measuring.filter(|m| !m.which.is_empty()),
    };
    Ok(sim.to_checkpoint(&postcard::to_stdvec(&extra)?))
}

/// A simulation, the format of its run's file and the measurements under way, from checkpoint
/// bytes (as written by [`checkpoint_bytes`] or `edmd run --checkpoint`), or the reason they
/// cannot be read.
#[allow(clippy::type_complexity)]
pub fn from_checkpoint_bytes<const D: usize>(
    bytes: &[u8],
) -> Result<(Simulation<D>, Format, Option<Measuring<D>>), String> {
    let (sim, extra) = Simulation::<D>::from_checkpoint(bytes).map_err(|e| e.to_string())?;
    let Some((format, measuring)) = read_extra::<D>(&extra) else {
        return Err(unreadable_extra(&extra));
    };
    if measuring.as_ref().is_some_and(|m| !m.fits(&sim)) {
        return Err(unreadable_extra(&extra));
    }
    Ok((sim, format, measuring))
}

/// Why a checkpoint's own bytes after the engine's are not a run's: an experiment's
/// checkpoint is named (its experiment continues it), anything else is unreadable.
pub fn unreadable_extra(extra: &[u8]) -> String {
    // The experiments' checkpoints carry JSON whose `format` names them
    // (`edmd experiment hard-disc-transition 1`).
    let prefix = br#"{"format":"edmd experiment "#;
    if let Some(rest) = extra.strip_prefix(&prefix[..]) {
        let name: String = rest
            .iter()
            .take_while(|b| b.is_ascii_alphanumeric() || **b == b'-')
            .map(|&b| char::from(b))
            .collect();
        if !name.is_empty() {
            return format!(
                "checkpoint: a point of `edmd experiment {name}`, not a run's: that experiment continues it (edmd experiment {name} --resume --out-dir ITS_FOLDER)"
            );
        }
    }
    "checkpoint: the run's settings or measurements are missing or unreadable".into()
}

/// The names of measurements, as `--measure` takes them.
pub fn measure_names(which: &[Measure]) -> String {
    use clap::ValueEnum;
    which
        .iter()
        .filter_map(|m| m.to_possible_value().map(|v| v.get_name().to_string()))
        .collect::<Vec<_>>()
        .join(",")
}

/// Reads `path` as a checkpoint if it starts with the checkpoint magic number; `None` for any
/// other file (read as a data file then). A packing's checkpoint is refused by name.
pub fn read_checkpoint(path: &Path) -> Result<Option<Vec<u8>>> {
    if read_magic(path)?.is_some_and(|m| edmd_core::pack::is_pack_checkpoint(&m)) {
        return user_error(format!(
            "{}: a packing checkpoint (edmd pack continues it: edmd pack {} -o OUT), not a run's",
            path.display(),
            path.display()
        ));
    }
    read_file_starting(path, edmd_core::CHECKPOINT_MAGIC)
}

/// The first 8 bytes of a regular file (`None` for `-`, a device, a folder, a shorter file or
/// one that cannot be opened: those are left to the data file reader).
pub fn read_magic(path: &Path) -> Result<Option<[u8; 8]>> {
    use std::io::Read;
    if path == Path::new("-") || std::fs::metadata(path).map_or(true, |m| !m.is_file()) {
        return Ok(None);
    }
    let Ok(mut f) = std::fs::File::open(path) else {
        return Ok(None);
    };
    let mut start = [0u8; 8];
    Ok(f.read_exact(&mut start).is_ok().then_some(start))
}

/// Reads `path` whole if it is a regular file starting with `magic` (a checkpoint: at most
/// [`crate::input::MAX_FILE`] bytes); `None` for any other file.
pub fn read_file_starting(path: &Path, magic: &[u8; 8]) -> Result<Option<Vec<u8>>> {
    use std::io::Read;
    if read_magic(path)? != Some(*magic) {
        return Ok(None);
    }
    let f = std::fs::File::open(path)
        .or_else(|e| user_error(format!("{}: cannot read: {e}", path.display())))?;
    let mut bytes = Vec::new();
    f.take(crate::input::MAX_FILE as u64 + 1)
        .read_to_end(&mut bytes)
        .or_else(|e| user_error(format!("{}: cannot read: {e}", path.display())))?;
    if bytes.len() > crate::input::MAX_FILE {
        return user_error(format!(
            "{}: checkpoint: larger than the largest file read",
            path.display()
        ));
    }
    Ok(Some(bytes))
}

/// Writes a checkpoint of `sim` to `path`, replacing the previous one atomically (a kill at any
/// moment leaves the old one whole).
pub fn write_checkpoint(path: &Path, bytes: &[u8]) -> Result<()> {
    let mut f = AtomicFile::create(path)?;
    f.writer().write_all(bytes)?;
    f.commit()?;
    Ok(())
}

/// The most trajectory frames or measurement samples one run may take.
pub const MAX_STOPS: f64 = 1e6;

/// The most bytes a `--trajectory` may take (100 GB). A run longer than that can write its
/// trajectory in parts, a leg at a time, through checkpoints.
pub const MAX_TRAJECTORY_BYTES: f64 = 1e11;

/// Whether two paths name the same existing file.
pub fn same_file(a: &Path, b: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (std::fs::metadata(a), std::fs::metadata(b)) {
        (Ok(x), Ok(y)) => x.dev() == y.dev() && x.ino() == y.ino(),
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use edmd_core::setup::lattice_fluid;
    use edmd_core::{Boundary, Options};

    /// A checkpoint written before the viscosity was measured (its extra bytes end where
    /// today's `viscosity` would begin) is read back with the measurements it had.
    #[test]
    fn measurements_from_before_viscosity_read_back() {
        let (discs, bx) = lattice_fluid(64, 0.3, Boundary::Periodic, 1).unwrap();
        let mut sim = Simulation::new(&discs, bx, Options::default()).unwrap();
        let which = [Measure::Temperature, Measure::Pressure];
        let mut m = Measuring::new(&sim, &which, 0.5);
        assert!(m.run_to(&mut sim, 2.0).unwrap());
        let now = checkpoint_bytes(&sim, Format::Course, Some(&m)).unwrap();
        let (_, extra) = Simulation::<2>::from_checkpoint(&now).unwrap();
        // `viscosity`, `conductivity` and `shear_stress`, all `None`, are the last three
        // bytes, 0.
        assert_eq!(extra[extra.len() - 3..], [0, 0, 0]);
        let before = sim.to_checkpoint(&extra[..extra.len() - 3]);
        let (_, _, back) = from_checkpoint_bytes::<2>(&before).unwrap();
        let back = back.unwrap();
        assert_eq!((back.which, back.samples), (which.to_vec(), 4));
        assert_eq!(back.obs.results(&sim).0, m.obs.results(&sim).0);
    }

    /// A checkpoint written before kinetics were measured (its extra bytes end where today's
    /// `kinetics` would begin) is read back with the measurements it had.
    #[test]
    fn measurements_from_before_kinetics_read_back() {
        let (discs, bx) = lattice_fluid(64, 0.3, Boundary::Periodic, 1).unwrap();
        let mut sim = Simulation::new(&discs, bx, Options::default()).unwrap();
        let which = [Measure::Temperature, Measure::Rdf];
        let mut m = Measuring::new(&sim, &which, 0.5);
        assert!(m.run_to(&mut sim, 2.0).unwrap());
        let now = checkpoint_bytes(&sim, Format::Course, Some(&m)).unwrap();
        let (_, extra) = Simulation::<2>::from_checkpoint(&now).unwrap();
        // `kinetics`, `viscosity`, `conductivity` and `shear_stress`, all `None`, are the last
        // four bytes, 0.
        assert_eq!(extra[extra.len() - 4..], [0, 0, 0, 0]);
        let before = sim.to_checkpoint(&extra[..extra.len() - 4]);
        let (_, format, back) = from_checkpoint_bytes::<2>(&before).unwrap();
        let back = back.unwrap();
        assert_eq!(format, Format::Course);
        assert_eq!((back.which, back.samples), (which.to_vec(), 4));
        assert_eq!(back.obs.results(&sim).0, m.obs.results(&sim).0);
    }
}
