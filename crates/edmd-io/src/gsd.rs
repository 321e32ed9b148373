//! HOOMD GSD files, read and written through the Glotzer group's `hoomd-gsd` crate.
//!
//! GSD (<https://gsd.readthedocs.io>) stores frames of named 2D arrays ("chunks"); the HOOMD
//! schema names them (`particles/position`, `configuration/box`, ...). A frame written here is
//! read by HOOMD-blue, the `gsd` Python package, OVITO and VMD, and a frame they wrote is read
//! here, so a system prepared or equilibrated with HOOMD-blue continues in edmd.
//!
//! # How the conventions map
//! | edmd | GSD (HOOMD schema 1.4) |
//! |---|---|
//! | box `[0, L)` per axis | `configuration/box` `[Lx, Ly, Lz, 0, 0, 0]`, centred on the origin: `x_hoomd = x - L/2`, in the half-open `[-L/2, L/2)` after rounding to float32 |
//! | 2D | `configuration/dimensions` = 2 and `Lz = 0` (a frame is read as 2D when either says so) |
//! | position, velocity | `particles/position`, `particles/velocity`, float32 `N x 3` (z = 0 in 2D) |
//! | radius | `particles/diameter` = 2 r, float32 |
//! | mass | `particles/mass`, float32 |
//! | species | `particles/typeid` (uint32), `particles/types` `"A"`, `"B"`, ..., `"T26"`, ... |
//! | unwrapped position `u = x + n L` | `particles/image` `n`, int32 `N x 3` |
//! | time | `log/edmd/time`, float64 (0 when absent); `configuration/step` is the count of disc-disc collisions |
//! | walls | `log/edmd/walls`, uint8 per axis x y z (HOOMD boxes are periodic on every axis: a file without it is read as periodic) |
//! | colour | `log/edmd/colour`, uint8 `N x 3`, written only when some disc is not black |
//!
//! No charge is written (HOOMD's default, 0, applies).
//!
//! # Precision
//! HOOMD's chunks are float32. A round trip edmd -> GSD -> edmd through them alone
//! ([`Precision::Float32`]) keeps each position within `L * 2^-24` of where it was on an axis
//! of length `L` (half from rounding `x - L/2` to float32, half from rounding `L`), within
//! `L * 2^-23` where a point on a walled axis rounded onto the box's far face was moved back in
//! by one float32 step, and on a periodic axis the same place up to a whole box (the image
//! count read says so); each velocity, radius, mass and box length is kept to float32
//! (relative `2^-24`); species, walls, colours and the time are exact. Rounding to float32 can
//! make touching discs overlap by about `2^-24` of their contact distance.
//!
//! [`Precision::Exact`] also writes float64 copies as `log/edmd/box` (3), `log/edmd/position` and
//! `log/edmd/velocity` (`N x 3`), and `log/edmd/radius` and `log/edmd/mass` (`N`) when some
//! value is not a float32, so that edmd reads its own files back bit for bit: 48 more bytes a
//! particle (56 with radii, 64 with radii and masses), about twice the 48 of the float32 chunks
//! (measured: 10 frames of 10^4 discs of radius 0.01 take 48.1 bytes a particle and frame in
//! float32, 104.1 exact). A copy is used
//! only when it agrees with the float32 chunk it copies, so a file whose positions were changed
//! by another program is read from the changed float32 values (with a note saying so).
//!
//! # Reading
//! [`read_frame`] reads frame `k` (negative counts from the end, as in Python). A chunk absent
//! from the frame is taken from frame 0, and failing that has the schema's default (velocity
//! 0, mass 1, diameter 1, typeid 0, image 0, box `[1, 1, 1, 0, 0, 0]`), as HOOMD and the `gsd`
//! package read it; a frame with particles needs `particles/position`. Tilted (triclinic) boxes
//! are refused. edmd's own `log/edmd/*` chunks are read from the frame itself (the walls also
//! from frame 0).
//!
//! Every problem gives a [`GsdError`]: one line naming the file and what is wrong. `hoomd-gsd`
//! checks only some of a file's index and asserts on the rest (it panics on a truncated or
//! corrupted file), so the header, name list and every index entry are checked here first; see
//! [`read_frame`].

use std::fmt;
use std::io::{Read, Seek, SeekFrom};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;
use std::time::{Duration, Instant};

use edmd_core::{Boundary, Disc, SimBox, Simulation, Vector};
use hoomd_gsd::file_layer::{GsdFile, Mode, Type};

use crate::princeton::ColumnOrder;
use crate::{AnyLoaded, Format, LoadedSystem};

/// The first 8 bytes of every GSD file (the magic number `0x65DF65DF65DF65DF`, little-endian).
pub const MAGIC: [u8; 8] = [0xDF, 0x65, 0xDF, 0x65, 0xDF, 0x65, 0xDF, 0x65];

/// True when `start` (the first bytes of a file) begins with the GSD magic number: how a
/// loader tells a GSD file from a text one whatever its name.
pub fn is_gsd(start: &[u8]) -> bool {
    start.starts_with(&MAGIC)
}

/// A GSD file that cannot be read or written.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GsdError {
    /// The file, as given.
    pub path: String,
    /// What is wrong, in words, on one line.
    pub message: String,
}

impl fmt::Display for GsdError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.path, self.message)
    }
}

impl std::error::Error for GsdError {}

fn error(path: &Path, message: impl Into<String>) -> GsdError {
    // One line whatever the message: the CLI prints it as is.
    let message: String = message.into();
    GsdError {
        path: path.display().to_string(),
        message: message.replace(['\n', '\r'], " "),
    }
}

/// An error and its sources, as one line (`hoomd-gsd`'s errors say the detail in a source).
fn chain(e: &dyn std::error::Error) -> String {
    let mut s = e.to_string();
    let mut source = e.source();
    while let Some(inner) = source {
        s.push_str(": ");
        s.push_str(&inner.to_string());
        source = inner.source();
    }
    s
}

// ------------------------------------------------------------------------------------------
// Writing

/// Which chunks a frame carries.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Precision {
    /// HOOMD's float32 chunks only (48 bytes a particle): what HOOMD and the `gsd` package
    /// read; a round trip keeps values to float32 (see the module doc).
    #[default]
    Float32,
    /// The float32 chunks and float64 copies in `log/edmd/`, so that edmd reads the state back
    /// exactly (about twice the size).
    Exact,
}

/// One frame to write: discs (their positions in the box `[0, L)`), the box, optionally the
/// image counts (unwrapped position = position + image * L; zeros without them), the time and
/// HOOMD's step.
#[derive(Clone, Copy, Debug)]
pub struct State<'a, const D: usize> {
    /// The discs.
    pub discs: &'a [Disc<D>],
    /// The box.
    pub sim_box: &'a SimBox<D>,
    /// Image counts per disc and axis, or `None` for all zero.
    pub images: Option<&'a [[i64; D]]>,
    /// The time the state is at.
    pub time: f64,
    /// `configuration/step`.
    pub step: u64,
}

/// Appends frames to a GSD file in the HOOMD schema. The file is complete after each frame
/// once [`Writer::finish`] (or drop, which ignores errors) has run; frames are also made
/// durable every 10 s of writing, so a run cut short keeps most of its frames.
pub struct Writer {
    file: GsdFile,
    path: std::path::PathBuf,
    precision: Precision,
    last_sync: Instant,
}

/// How often the index is written out during a long trajectory (as `hoomd-gsd`'s own
/// `HoomdGsdFile` does): without it nothing would be readable until the end.
const SYNC_EVERY: Duration = Duration::from_secs(10);

/// Width of a type name row, with the NUL: "T65535" is the longest name edmd writes.
const TYPE_NAME_WIDTH: usize = 8;

impl Writer {
    /// Creates (or truncates) the file at `path` and writes its header.
    pub fn create(path: impl AsRef<Path>, precision: Precision) -> Result<Self, GsdError> {
        let path = path.as_ref();
        if path.is_dir() {
            return Err(error(path, "cannot write: is a folder"));
        }
        let application = concat!("edmd ", env!("CARGO_PKG_VERSION"));
        let file = GsdFile::create(path, application, "hoomd", (1, 4))
            .map_err(|e| error(path, format!("cannot write: {}", chain(&e))))?;
        Ok(Writer {
            file,
            path: path.to_path_buf(),
            precision,
            last_sync: Instant::now(),
        })
    }

    /// Appends the simulation's current state: positions in the box, the image counts of
    /// its unwrapped positions, the time, and the disc-disc collision count as the step.
    pub fn append_simulation<const D: usize>(
        &mut self,
        sim: &Simulation<D>,
    ) -> Result<(), GsdError> {
        let b = sim.sim_box();
        let discs = sim.discs();
        let images: Vec<[i64; D]> = (0..sim.len())
            .map(|i| {
                let (p, u) = (sim.position(i), sim.unwrapped_position(i));
                std::array::from_fn(|a| ((u[a] - p[a]) / b.lengths[a]).round() as i64)
            })
            .collect();
        self.append(&State {
            discs: &discs,
            sim_box: b,
            images: Some(&images),
            time: sim.time(),
            step: sim.stats().disc_disc,
        })
    }

    /// Appends one frame.
    pub fn append<const D: usize>(&mut self, state: &State<'_, D>) -> Result<(), GsdError> {
        let path = self.path.clone();
        let fail = |what: String| error(&path, what);
        if D != 2 && D != 3 {
            return Err(fail(dimension_refusal(D)));
        }
        let (discs, b) = (state.discs, state.sim_box);
        let n = discs.len();
        let n32 = u32::try_from(n).map_err(|_| {
            fail(format!(
                "cannot write {n} discs: GSD counts them in 32 bits"
            ))
        })?;
        if let Some(images) = state.images {
            if images.len() != n {
                return Err(fail(format!("{} image counts for {n} discs", images.len())));
            }
        }
        let mut l32 = [0f32; 3];
        for a in 0..D {
            l32[a] = b.lengths[a] as f32;
            if !(l32[a].is_finite() && l32[a] > 0.0) {
                return Err(fail(format!(
                    "box length {} is not a positive float32",
                    b.lengths[a]
                )));
            }
        }
        let mut pos = Vec::with_capacity(n);
        let mut vel = Vec::with_capacity(n);
        let mut image = Vec::with_capacity(n);
        for (i, d) in discs.iter().enumerate() {
            let (mut p, mut v, mut m) = ([0f32; 3], [0f32; 3], [0i32; 3]);
            for a in 0..D {
                let (x, shift) =
                    in_hoomd_box(d.pos[a] - 0.5 * b.lengths[a], l32[a], b.is_periodic(a));
                let img = state.images.map_or(0, |im| im[i][a]) + i64::from(shift);
                p[a] = x;
                v[a] = d.vel[a] as f32;
                m[a] = i32::try_from(img).map_err(|_| {
                    fail(format!(
                        "disc {i} is {img} boxes away: more than int32 images"
                    ))
                })?;
            }
            pos.push(p);
            vel.push(v);
            image.push(m);
        }
        let exact = self.precision == Precision::Exact;
        let not_f32 = |x: f64| f64::from(x as f32) != x;
        let colour = discs.iter().any(|d| d.colour != [0, 0, 0]);
        let types = discs
            .iter()
            .map(|d| d.species)
            .max()
            .map_or(1, |m| m as usize + 1);
        let f = &mut self.file;
        let w = |r: Result<(), hoomd_gsd::file_layer::WriteError>| {
            r.map_err(|e| error(&path, format!("cannot write: {}", chain(&e))))
        };
        w(f.write_scalars("configuration/step", [state.step]))?;
        w(f.write_scalars("configuration/dimensions", [D as u8]))?;
        w(f.write_scalars("configuration/box", [l32[0], l32[1], l32[2], 0.0, 0.0, 0.0]))?;
        w(f.write_scalars("particles/N", [n32]))?;
        w(f.write_arrays("particles/position", pos))?;
        w(f.write_arrays("particles/velocity", vel))?;
        w(f.write_scalars(
            "particles/diameter",
            discs.iter().map(|d| (2.0 * d.radius) as f32),
        ))?;
        w(f.write_scalars("particles/mass", discs.iter().map(|d| d.mass as f32)))?;
        w(f.write_scalars(
            "particles/typeid",
            discs.iter().map(|d| u32::from(d.species)),
        ))?;
        w(f.write_arrays("particles/types", (0..types).map(type_name)))?;
        w(f.write_arrays("particles/image", image))?;
        let walls: [u8; 3] = std::array::from_fn(|a| u8::from(a < D && !b.is_periodic(a)));
        w(f.write_scalars("log/edmd/walls", walls))?;
        w(f.write_scalars("log/edmd/time", [state.time]))?;
        if colour {
            w(f.write_arrays("log/edmd/colour", discs.iter().map(|d| d.colour)))?;
        }
        if exact {
            let pad = |v: Vector<D>| -> [f64; 3] {
                std::array::from_fn(|a| if a < D { v[a] } else { 0.0 })
            };
            let lengths: [f64; 3] = std::array::from_fn(|a| if a < D { b.lengths[a] } else { 0.0 });
            w(f.write_scalars("log/edmd/box", lengths))?;
            w(f.write_arrays("log/edmd/position", discs.iter().map(|d| pad(d.pos))))?;
            w(f.write_arrays("log/edmd/velocity", discs.iter().map(|d| pad(d.vel))))?;
            if discs.iter().any(|d| not_f32(2.0 * d.radius)) {
                w(f.write_scalars("log/edmd/radius", discs.iter().map(|d| d.radius)))?;
            }
            if discs.iter().any(|d| not_f32(d.mass)) {
                w(f.write_scalars("log/edmd/mass", discs.iter().map(|d| d.mass)))?;
            }
        }
        f.end_frame()
            .map_err(|e| error(&path, format!("cannot write: {}", chain(&e))))?;
        if self.last_sync.elapsed() >= SYNC_EVERY {
            self.sync()?;
        }
        Ok(())
    }

    fn sync(&mut self) -> Result<(), GsdError> {
        self.last_sync = Instant::now();
        self.file
            .sync_all()
            .map_err(|e| error(&self.path, format!("cannot write: {}", chain(&e))))
    }

    /// Writes out every frame and the index, and closes the file.
    pub fn finish(mut self) -> Result<(), GsdError> {
        self.sync()
    }
}

/// Why a system of dimension `dim` (not 2 or 3) has no GSD frame: HOOMD's schema holds 2D and
/// 3D boxes only.
pub fn dimension_refusal(dim: usize) -> String {
    format!(
        "GSD (HOOMD's schema) holds 2D and 3D systems only, not {dim}D{}; write the Princeton format or .xyz",
        if dim == 1 { " (rods on a line)" } else { "" }
    )
}

/// Writes one frame to a new file at `path` (replacing one that is there): a state to continue
/// from (take [`Precision::Exact`] for edmd to read it back exactly).
pub fn write_file<const D: usize>(
    path: impl AsRef<Path>,
    discs: &[Disc<D>],
    sim_box: &SimBox<D>,
    time: f64,
    precision: Precision,
) -> Result<(), GsdError> {
    if D != 2 && D != 3 {
        return Err(error(path.as_ref(), dimension_refusal(D)));
    }
    let mut w = Writer::create(path, precision)?;
    w.append(&State {
        discs,
        sim_box,
        images: None,
        time,
        step: 0,
    })?;
    w.finish()
}

/// Type `t`'s name, NUL-padded: "A" to "Z", then "T26", "T27", ...
fn type_name(t: usize) -> [i8; TYPE_NAME_WIDTH] {
    let name = if t < 26 {
        ((b'A' + t as u8) as char).to_string()
    } else {
        format!("T{t}")
    };
    let mut row = [0i8; TYPE_NAME_WIDTH];
    for (r, c) in row.iter_mut().zip(name.bytes().take(TYPE_NAME_WIDTH - 1)) {
        *r = c as i8;
    }
    row
}

/// A centred coordinate `x` rounded to float32 and put in HOOMD's half-open box
/// `[-l/2, l/2)` of float32 length `l`, with the change to the image flag it took (+1 or -1
/// when wrapped across a periodic axis). A position just below `L` rounds up to `+l/2`, which
/// HOOMD reads as outside its box; and `l` is itself rounded, so either end can be missed by an
/// ulp. On a periodic axis the point is wrapped to the other side (the same place, one image
/// on). On a walled axis wrapping would move it through the wall, so it is put at the nearest
/// float32 inside instead: a move of one ulp, no more than the rounding to float32 itself.
fn in_hoomd_box(x: f64, l: f32, periodic: bool) -> (f32, i32) {
    let half = 0.5 * l;
    let x = x as f32;
    if x >= half {
        if periodic {
            // `x - l` rounds too; it is at least `-half` since `x >= half`.
            ((x - l).max(-half), 1)
        } else {
            // The largest float32 below `half` (positive, so one step down in its bits).
            (f32::from_bits(half.to_bits() - 1), 0)
        }
    } else if x < -half {
        if periodic {
            let w = x + l;
            (if w >= half { -half } else { w }, -1)
        } else {
            (-half, 0)
        }
    } else {
        (x, 0)
    }
}

// ------------------------------------------------------------------------------------------
// Reading

/// A frame read from a GSD file.
#[derive(Clone, Debug, PartialEq)]
pub struct GsdFrame {
    /// The system, in the dimension the frame has. Its `format` is
    /// `Format::Princeton(ColumnOrder::RadiusMass)`, the format edmd writes a state in when none
    /// is asked for, and `lines[i]` is `i + 1`, the particle's 1-based index in the frame (a
    /// GSD file has no lines).
    pub system: AnyLoaded,
    /// The frame read, counted from 0.
    pub frame: u64,
    /// The number of frames in the file.
    pub frames: u64,
    /// HOOMD's `configuration/step` (0 when absent).
    pub step: u64,
    /// `particles/image` per particle (x y z), as read from the positions in the box; on
    /// periodic axes the unwrapped position is `position + image * L`.
    pub images: Vec<[i32; 3]>,
    /// True when the float64 copies edmd writes with [`Precision::Exact`] were read (the
    /// values are then exactly those written); false when the float32 chunks were.
    pub exact: bool,
    /// Things worth telling the user that are not errors, one line each (the file name is not
    /// in them).
    pub notes: Vec<String>,
}

/// Reads frame `frame` of the GSD file at `path` in the dimension it has (see [`read_frame`]).
pub fn read_any(path: impl AsRef<Path>, frame: i64) -> Result<AnyLoaded, GsdError> {
    read_frame(path, frame).map(|f| f.system)
}

/// The number of frames in the GSD file at `path` (after the same checks as [`read_frame`]).
pub fn frame_count(path: impl AsRef<Path>) -> Result<u64, GsdError> {
    let path = path.as_ref();
    check_file(path)
        .map(|i| i.frames)
        .map_err(|m| error(path, m))
}

/// Reads frame `frame` (0 is the first, -1 the last) of the GSD file at `path`, which must
/// have the HOOMD schema (written by HOOMD-blue, the `gsd` Python package or edmd). Positions
/// are moved from HOOMD's centred box into edmd's `[0, L)` (wrapped there on periodic axes,
/// the image counts adjusted), the radius is half the diameter, the species the typeid.
///
/// Every malformed file gives an error naming the file and the problem: not a regular file,
/// empty, not GSD, another schema, truncated or corrupt (header, name list or index pointing
/// outside the file, index out of order), a frame out of range, a chunk of the wrong type or
/// shape, particle counts that disagree, numbers that are not finite, box lengths that are not
/// positive, a tilted box. `hoomd-gsd` memory-maps the file and asserts (panics) on some
/// corrupt index entries, and only checks those its binary search visits; so all of that is
/// checked here, from the file itself, before `hoomd-gsd` opens it. A file changed on disk
/// between the two is caught by `catch_unwind` (as an error, not a panic); one truncated by
/// another program while it is mapped can still end the process with SIGBUS, as with any
/// memory-mapped reader.
pub fn read_frame(path: impl AsRef<Path>, frame: i64) -> Result<GsdFrame, GsdError> {
    let path = path.as_ref();
    let index = check_file(path).map_err(|m| error(path, m))?;
    let frames = index.frames;
    if frames == 0 {
        return Err(error(path, "the file has no frames"));
    }
    let k = if frame < 0 {
        i128::from(frames) + i128::from(frame)
    } else {
        i128::from(frame)
    };
    if k < 0 || k >= i128::from(frames) {
        return Err(error(
            path,
            format!(
                "frame {frame} is out of range: the file has {frames} frame(s), 0 to {} (or -{frames} to -1 from the end)",
                frames - 1
            ),
        ));
    }
    let k = k as u64;
    // Last resort only: `check_file` has checked everything `hoomd-gsd` asserts on, so a panic
    // here means the file changed since (or a bug in that check); either way the user gets an
    // error naming the file rather than a crash.
    let read = catch_unwind(AssertUnwindSafe(|| -> Result<GsdFrame, String> {
        let gsd = GsdFile::open(path, Mode::Read).map_err(|e| chain(&e))?;
        if gsd.n_frames() != frames {
            return Err("the file changed while being read".into());
        }
        read_open(&gsd, &index, k)
    }));
    match read {
        Ok(r) => r.map_err(|m| error(path, format!("frame {k}: {m}"))),
        Err(_) => Err(error(
            path,
            "the GSD reader failed on this file (corrupt, or changed while being read)",
        )),
    }
}

/// One index entry, as in the file.
#[derive(Clone, Copy, Debug)]
struct Entry {
    frame: u64,
    rows: u64,
    location: u64,
    cols: u32,
    id: u16,
    kind: u8,
}

/// What `check_file` learnt: the chunk names (by id) and the index entries in use, sorted by
/// (frame, id).
struct Index {
    names: Vec<String>,
    entries: Vec<Entry>,
    frames: u64,
}

impl Index {
    fn find(&self, frame: u64, name: &str) -> Option<Entry> {
        let id = self.names.iter().position(|n| n == name)? as u16;
        self.entries
            .binary_search_by(|e| (e.frame, e.id).cmp(&(frame, id)))
            .ok()
            .map(|k| self.entries[k])
    }
}

/// GSD type codes and names.
fn kind_name(kind: u8) -> &'static str {
    match kind {
        1 => "uint8",
        2 => "uint16",
        3 => "uint32",
        4 => "uint64",
        5 => "int8",
        6 => "int16",
        7 => "int32",
        8 => "int64",
        9 => "float32",
        10 => "float64",
        11 => "character",
        _ => "an unknown type",
    }
}

fn kind_size(kind: u8) -> Option<u64> {
    match kind {
        1 | 5 | 11 => Some(1),
        2 | 6 => Some(2),
        3 | 7 | 9 => Some(4),
        4 | 8 | 10 => Some(8),
        _ => None,
    }
}

const HEADER: u64 = 256;
const NAME_BLOCK: u64 = 64;
const ENTRY: u64 = 32;

fn le_u64(b: &[u8], at: usize) -> u64 {
    let mut w = [0u8; 8];
    w.copy_from_slice(&b[at..at + 8]);
    u64::from_le_bytes(w)
}

fn le_u32(b: &[u8], at: usize) -> u32 {
    let mut w = [0u8; 4];
    w.copy_from_slice(&b[at..at + 4]);
    u32::from_le_bytes(w)
}

/// Text up to the first NUL (or the end).
fn c_str(b: &[u8]) -> Result<&str, std::str::Utf8Error> {
    let end = b.iter().position(|&c| c == 0).unwrap_or(b.len());
    std::str::from_utf8(&b[..end])
}

/// Checks the header, name list and every index entry of the file at `path` against the
/// file's length, with the same rules as `hoomd-gsd` (GSD file layer 2.x, HOOMD schema 1.x),
/// so that `hoomd-gsd` then meets no entry it would assert on.
fn check_file(path: &Path) -> Result<Index, String> {
    let meta = std::fs::metadata(path).map_err(|e| format!("cannot read: {e}"))?;
    if meta.is_dir() {
        return Err("cannot read: is a folder, not a GSD file".into());
    }
    if !meta.is_file() {
        // A FIFO would block `hoomd-gsd`'s open, and a device cannot be memory-mapped.
        return Err("cannot read: not a regular file (a GSD file is read in place)".into());
    }
    let mut file = std::fs::File::open(path).map_err(|e| format!("cannot read: {e}"))?;
    let len = file
        .seek(SeekFrom::End(0))
        .map_err(|e| format!("cannot read: {e}"))?;
    if len == 0 {
        return Err("the file is empty, not a GSD file".into());
    }
    let mut read_at = |at: u64, size: u64| -> Result<Vec<u8>, String> {
        let mut b = vec![0u8; size as usize];
        file.seek(SeekFrom::Start(at))
            .and_then(|_| file.read_exact(&mut b))
            .map_err(|e| format!("cannot read: {e}"))?;
        Ok(b)
    };
    let head = read_at(0, HEADER.min(len))?;
    if !is_gsd(&head) {
        return Err("not a GSD file (it does not start with the GSD magic number)".into());
    }
    if len < HEADER {
        return Err(format!(
            "truncated GSD file: {len} bytes, less than the 256-byte header"
        ));
    }
    let (index_at, index_n) = (le_u64(&head, 8), le_u64(&head, 16));
    let (names_at, names_n) = (le_u64(&head, 24), le_u64(&head, 32));
    let schema_version = le_u32(&head, 40);
    let version = le_u32(&head, 44);
    let (major, minor) = (version >> 16, version & 0xffff);
    if major != 2 {
        return Err(format!(
            "GSD file layer version {major}.{minor} is not supported (2.x is read; a 1.x file, from HOOMD-blue 2 or gsd 1, can be rewritten with the gsd Python package 2 or later)"
        ));
    }
    c_str(&head[48..]).map_err(|_| "the header's application name is not text (corrupt)")?;
    // `hoomd-gsd` reads the schema name from bytes 112 to 178.
    let schema = c_str(&head[112..178]).map_err(|_| "the header's schema name is not text")?;
    if schema != "hoomd" {
        return Err(format!(
            "the GSD schema is '{schema}', not 'hoomd': not a HOOMD trajectory"
        ));
    }
    let (s_major, s_minor) = (schema_version >> 16, schema_version & 0xffff);
    // 2.x (the `gsd` package since 4.0) differs from 1.x only in allowing float64 chunks.
    if s_major != 1 && s_major != 2 {
        return Err(format!(
            "HOOMD schema version {s_major}.{s_minor} is not supported (1.x and 2.x are read)"
        ));
    }
    let truncated = |what: &str| {
        format!("truncated or corrupt GSD file: its {what} lies beyond its end ({len} bytes)")
    };
    let index_end = index_n
        .checked_mul(ENTRY)
        .and_then(|b| b.checked_add(index_at))
        .filter(|&end| end <= len && index_n > 0)
        .ok_or_else(|| truncated("index"))?;
    let names_end = names_n
        .checked_mul(NAME_BLOCK)
        .and_then(|b| b.checked_add(names_at))
        .filter(|&end| end <= len && names_n > 0)
        .ok_or_else(|| truncated("chunk name list"))?;
    let name_bytes = read_at(names_at, names_end - names_at)?;
    if name_bytes.last() != Some(&0) {
        return Err("corrupt GSD file: the chunk name list does not end in a NUL".into());
    }
    let mut names: Vec<String> = Vec::new();
    let mut rest = &name_bytes[..];
    while rest.first().is_some_and(|&c| c != 0) {
        let name = c_str(rest).map_err(|_| "corrupt GSD file: a chunk name is not text")?;
        if names.iter().any(|n| n == name) {
            return Err(format!(
                "corrupt GSD file: chunk name '{name}' appears twice"
            ));
        }
        if names.len() >= usize::from(u16::MAX) {
            return Err("corrupt GSD file: more than 65535 chunk names".into());
        }
        rest = &rest[(name.len() + 1).min(rest.len())..];
        names.push(name.to_string());
    }
    let index_bytes = read_at(index_at, index_end - index_at)?;
    let mut entries: Vec<Entry> = Vec::new();
    let mut ended = false;
    for (k, e) in index_bytes.chunks_exact(ENTRY as usize).enumerate() {
        let entry = Entry {
            frame: le_u64(e, 0),
            rows: le_u64(e, 8),
            location: le_u64(e, 16),
            cols: le_u32(e, 24),
            id: u16::from_le_bytes([e[28], e[29]]),
            kind: e[30],
        };
        let flags = e[31];
        if entry.location == 0 {
            ended = true;
            continue;
        }
        let bad = |why: String| format!("corrupt GSD file: index entry {k} {why}");
        if ended {
            return Err(bad("follows the end of the index".into()));
        }
        let size =
            kind_size(entry.kind).ok_or_else(|| bad(format!("has type code {}", entry.kind)))?;
        let end = entry
            .rows
            .checked_mul(u64::from(entry.cols))
            .and_then(|n| n.checked_mul(size))
            .and_then(|b| b.checked_add(entry.location));
        if end.is_none_or(|end| end > len) {
            return Err(bad(format!(
                "points beyond the end of the file ({len} bytes): truncated or corrupt"
            )));
        }
        if entry.frame >= index_n {
            return Err(bad(format!(
                "has frame {}, past the index's size",
                entry.frame
            )));
        }
        if usize::from(entry.id) >= names.len() {
            return Err(bad(format!(
                "names chunk {}, not in the name list",
                entry.id
            )));
        }
        if flags != 0 {
            return Err(bad(format!("has flags {flags} (0 expected)")));
        }
        if let Some(p) = entries.last() {
            if (p.frame, p.id) >= (entry.frame, entry.id) {
                return Err(bad("is out of order (by frame, then chunk)".into()));
            }
        }
        entries.push(entry);
    }
    let frames = entries.last().map_or(0, |e| e.frame + 1);
    Ok(Index {
        names,
        entries,
        frames,
    })
}

/// The GSD types read here, with their codes.
trait Kind: Type + Copy {
    const KIND: u8;
}
impl Kind for u8 {
    const KIND: u8 = 1;
}
impl Kind for u32 {
    const KIND: u8 = 3;
}
impl Kind for u64 {
    const KIND: u8 = 4;
}
impl Kind for i32 {
    const KIND: u8 = 7;
}
impl Kind for f32 {
    const KIND: u8 = 9;
}
impl Kind for f64 {
    const KIND: u8 = 10;
}

/// Reads chunks of frame `frame` through `hoomd-gsd`, after `check_file`.
struct Chunks<'a> {
    gsd: &'a GsdFile,
    index: &'a Index,
    frame: u64,
}

impl Chunks<'_> {
    /// Where `name` is: in the frame, else (with `fallback`, the schema's rule for
    /// `configuration/` and `particles/` chunks) in frame 0.
    fn locate(&self, name: &str, fallback: bool) -> Option<(u64, Entry)> {
        if let Some(e) = self.index.find(self.frame, name) {
            return Some((self.frame, e));
        }
        if fallback && self.frame != 0 {
            return self.index.find(0, name).map(|e| (0, e));
        }
        None
    }

    /// The chunk as `rows` (any when `None`) rows of `M` values of type `T`, or `None` when it
    /// is absent.
    fn read<T: Kind, const M: usize>(
        &self,
        name: &str,
        fallback: bool,
        rows: Option<u64>,
    ) -> Result<Option<Vec<[T; M]>>, String> {
        let Some((frame, e)) = self.locate(name, fallback) else {
            return Ok(None);
        };
        if e.kind != T::KIND || e.cols as usize != M {
            return Err(format!(
                "{name} is {} with {} column(s); the HOOMD schema has {} with {M}",
                kind_name(e.kind),
                e.cols,
                kind_name(T::KIND)
            ));
        }
        if let Some(n) = rows {
            if e.rows != n {
                return Err(format!(
                    "{name} has {} row(s) but particles/N is {n}",
                    e.rows
                ));
            }
        }
        // `check_file` made sure that the key exists, so `hoomd-gsd`'s binary search (which
        // underflows looking for a key before the first entry) finds it.
        let values: Vec<[T; M]> = if M == 1 {
            self.gsd
                .iter_scalars::<T>(frame, name)
                .map_err(|e| chain(&e))?
                .map(|x| [x; M])
                .collect()
        } else {
            self.gsd
                .iter_arrays::<T, M>(frame, name)
                .map_err(|e| chain(&e))?
                .collect()
        };
        Ok(Some(values))
    }

    /// A chunk of floating-point values, float32 (schema 1.x and the default) or float64
    /// (schema 2.x written with double precision), as float64.
    fn floats<const M: usize>(
        &self,
        name: &str,
        fallback: bool,
        rows: Option<u64>,
    ) -> Result<Option<Vec<[f64; M]>>, String> {
        let Some((_, e)) = self.locate(name, fallback) else {
            return Ok(None);
        };
        let v = match e.kind {
            10 => self.read::<f64, M>(name, fallback, rows)?,
            9 => self
                .read::<f32, M>(name, fallback, rows)?
                .map(|v| v.iter().map(|r| r.map(f64::from)).collect()),
            k => {
                return Err(format!(
                    "{name} is {}; the HOOMD schema has float32 (or float64)",
                    kind_name(k)
                ))
            }
        };
        if let Some(v) = &v {
            if let Some(k) = v.iter().flatten().position(|x| !x.is_finite()) {
                let x = v[k / M][k % M];
                return Err(if name.starts_with("particles/") {
                    format!(
                        "{name}: particle {} has a value that is not finite ({x})",
                        k / M
                    )
                } else {
                    format!("{name}: value {k} is not finite ({x})")
                });
            }
        }
        Ok(v)
    }

    /// A scalar chunk's one value.
    fn one<T: Kind>(&self, name: &str, fallback: bool) -> Result<Option<T>, String> {
        Ok(self.read::<T, 1>(name, fallback, Some(1))?.map(|v| v[0][0]))
    }
}

fn read_open(gsd: &GsdFile, index: &Index, frame: u64) -> Result<GsdFrame, String> {
    let c = Chunks { gsd, index, frame };
    let mut notes = Vec::new();
    let step = c.one::<u64>("configuration/step", false)?.unwrap_or(0);
    let dims = c.one::<u8>("configuration/dimensions", true)?;
    if let Some(d) = dims {
        if d != 2 && d != 3 {
            return Err(format!("configuration/dimensions is {d} (2 or 3 expected)"));
        }
    }
    let bx: [f64; 6] = match c.floats::<1>("configuration/box", true, Some(6))? {
        Some(v) => std::array::from_fn(|k| v[k][0]),
        None => [1.0, 1.0, 1.0, 0.0, 0.0, 0.0],
    };
    let two_d = dims == Some(2) || bx[2] == 0.0;
    let dim = if two_d { 2 } else { 3 };
    for (a, l) in bx[..dim].iter().enumerate() {
        if *l <= 0.0 {
            return Err(format!(
                "the box's {} length is {l}: box lengths must be > 0",
                ["x", "y", "z"][a]
            ));
        }
    }
    let tilts = if two_d { &bx[3..4] } else { &bx[3..6] };
    if tilts.iter().any(|t| *t != 0.0) {
        return Err(format!(
            "the box is tilted (xy xz yz = {} {} {}): edmd's box is rectangular",
            bx[3], bx[4], bx[5]
        ));
    }
    let n = u64::from(c.one::<u32>("particles/N", true)?.unwrap_or(0));
    let rows = Some(n);
    // Per-particle chunks come from frame 0 only when it has as many particles (as the `gsd`
    // package reads them); otherwise they take the default.
    let n0 = match c.index.find(0, "particles/N") {
        Some(_) => Chunks { frame: 0, ..c }
            .one::<u32>("particles/N", false)?
            .map_or(0, u64::from),
        None => 0,
    };
    let pf = n0 == n;
    let position = match c.floats::<3>("particles/position", pf, rows)? {
        Some(p) => p,
        None if n == 0 => Vec::new(),
        None => {
            return Err(format!(
                "particles/N is {n} but there is no particles/position chunk"
            ))
        }
    };
    let velocity = c
        .floats::<3>("particles/velocity", pf, rows)?
        .unwrap_or_else(|| vec![[0.0; 3]; n as usize]);
    let mass = c
        .floats::<1>("particles/mass", pf, rows)?
        .unwrap_or_else(|| vec![[1.0]; n as usize]);
    let diameter = c
        .floats::<1>("particles/diameter", pf, rows)?
        .unwrap_or_else(|| vec![[1.0]; n as usize]);
    let typeid = c
        .read::<u32, 1>("particles/typeid", pf, rows)?
        .unwrap_or_else(|| vec![[0]; n as usize]);
    let image = c
        .read::<i32, 3>("particles/image", pf, rows)?
        .unwrap_or_else(|| vec![[0; 3]; n as usize]);
    // Only the number of type names matters (species = typeid); their width varies by writer.
    let types = c.locate("particles/types", true).map(|(_, e)| e.rows);
    for (i, t) in typeid.iter().enumerate() {
        let t = t[0];
        if let Some(nt) = types {
            if u64::from(t) >= nt {
                return Err(format!(
                    "particle {i} has typeid {t} but particles/types names {nt} type(s)"
                ));
            }
        }
        if t > u32::from(u16::MAX) {
            return Err(format!(
                "particle {i} has typeid {t}: edmd's species go up to 65535"
            ));
        }
    }
    for i in 0..n as usize {
        if mass[i][0] <= 0.0 {
            return Err(format!(
                "particle {i} has mass {}: masses must be > 0",
                mass[i][0]
            ));
        }
        if diameter[i][0] <= 0.0 {
            return Err(format!(
                "particle {i} has diameter {}: diameters must be > 0",
                diameter[i][0]
            ));
        }
        if two_d && (position[i][2] != 0.0 || velocity[i][2] != 0.0) {
            return Err(format!(
                "particle {i} has z = {} and vz = {} in a 2D frame (both must be 0)",
                position[i][2], velocity[i][2]
            ));
        }
    }
    let walls = c
        .read::<u8, 1>("log/edmd/walls", true, Some(3))?
        .map(|w| [w[0][0] != 0, w[1][0] != 0, w[2][0] != 0])
        .unwrap_or([false; 3]);
    let time = match c.one::<f64>("log/edmd/time", false)? {
        Some(t) if !t.is_finite() || t < 0.0 => {
            return Err(format!(
                "log/edmd/time is {t}: the time must be finite and >= 0"
            ))
        }
        Some(t) => t,
        None => 0.0,
    };
    let colour = match c.read::<u8, 3>("log/edmd/colour", false, rows) {
        Ok(v) => v,
        // A display label: a malformed one is not worth refusing the state for.
        Err(why) => {
            notes.push(format!("{why}; the discs are drawn black"));
            None
        }
    };
    let raw = Raw {
        dim,
        bx,
        walls,
        position,
        velocity,
        mass,
        diameter,
        typeid,
        image,
        colour,
    };
    let exact = match exact_copies(&c, &raw) {
        Ok(e) => e,
        Err(why) => {
            notes.push(format!(
                "{why}: the float32 chunks are read instead of edmd's float64 copies"
            ));
            None
        }
    };
    let is_exact = exact.is_some();
    let (system, images) = if two_d {
        let (s, i) = build::<2>(&raw, exact.as_ref(), time);
        (AnyLoaded::Two(s), i)
    } else {
        let (s, i) = build::<3>(&raw, exact.as_ref(), time);
        (AnyLoaded::Three(s), i)
    };
    Ok(GsdFrame {
        system,
        frame,
        frames: index.frames,
        step,
        images,
        exact: is_exact,
        notes,
    })
}

/// HOOMD's chunks of a frame (float32, or float64 in schema 2.x double-precision files),
/// checked.
struct Raw {
    dim: usize,
    bx: [f64; 6],
    walls: [bool; 3],
    position: Vec<[f64; 3]>,
    velocity: Vec<[f64; 3]>,
    mass: Vec<[f64; 1]>,
    diameter: Vec<[f64; 1]>,
    typeid: Vec<[u32; 1]>,
    image: Vec<[i32; 3]>,
    colour: Option<Vec<[u8; 3]>>,
}

/// edmd's float64 copies (`log/edmd/*`, written with [`Precision::Exact`]).
struct Exact {
    lengths: [f64; 3],
    position: Vec<[f64; 3]>,
    velocity: Vec<[f64; 3]>,
    radius: Option<Vec<[f64; 1]>>,
    mass: Option<Vec<[f64; 1]>>,
    /// The image shifts the writer added when it wrapped a rounded position (`in_hoomd_box`),
    /// taken off again since the exact positions are read.
    shifts: Vec<[i32; 3]>,
}

/// The float64 copies of the frame when they are all there and agree with the float32 chunks
/// (each copy rounds to the float32 value it copies, as the writer rounded it); `None` when
/// the frame has none; an error saying which disagrees otherwise.
fn exact_copies(c: &Chunks, raw: &Raw) -> Result<Option<Exact>, String> {
    let n = Some(raw.position.len() as u64);
    let Some(lengths) = c.read::<f64, 1>("log/edmd/box", false, Some(3))? else {
        return Ok(None);
    };
    let lengths: [f64; 3] = std::array::from_fn(|a| lengths[a][0]);
    let missing = |name: &str| format!("{name} is missing beside log/edmd/box");
    let position = c
        .read::<f64, 3>("log/edmd/position", false, n)?
        .ok_or_else(|| missing("log/edmd/position"))?;
    let velocity = c
        .read::<f64, 3>("log/edmd/velocity", false, n)?
        .ok_or_else(|| missing("log/edmd/velocity"))?;
    let radius = c.read::<f64, 1>("log/edmd/radius", false, n)?;
    let mass = c.read::<f64, 1>("log/edmd/mass", false, n)?;
    // The float32 value the writer made of `x`.
    let r32 = |x: f64| f64::from(x as f32);
    let differs = |what: &str| {
        format!("log/edmd/{what} does not match the HOOMD chunk it copies (changed by another program?)")
    };
    for a in 0..raw.dim {
        if !(lengths[a].is_finite() && lengths[a] > 0.0) || r32(lengths[a]) != raw.bx[a] {
            return Err(differs("box"));
        }
    }
    let mut shifts = Vec::with_capacity(position.len());
    for i in 0..position.len() {
        let mut shift = [0i32; 3];
        for a in 0..raw.dim {
            let (p, v) = (position[i][a], velocity[i][a]);
            if !p.is_finite() {
                return Err(differs("position"));
            }
            let (x, s) = in_hoomd_box(p - 0.5 * lengths[a], raw.bx[a] as f32, !raw.walls[a]);
            if f64::from(x) != raw.position[i][a] {
                return Err(differs("position"));
            }
            if !v.is_finite() || r32(v) != raw.velocity[i][a] {
                return Err(differs("velocity"));
            }
            shift[a] = s;
        }
        if let Some(r) = &radius {
            if !(r[i][0] > 0.0 && r[i][0].is_finite()) || r32(2.0 * r[i][0]) != raw.diameter[i][0] {
                return Err(differs("radius"));
            }
        }
        if let Some(m) = &mass {
            if !(m[i][0] > 0.0 && m[i][0].is_finite()) || r32(m[i][0]) != raw.mass[i][0] {
                return Err(differs("mass"));
            }
        }
        shifts.push(shift);
    }
    Ok(Some(Exact {
        lengths,
        position,
        velocity,
        radius,
        mass,
        shifts,
    }))
}

/// The system in `D` dimensions from checked chunks, with the image counts.
fn build<const D: usize>(
    raw: &Raw,
    exact: Option<&Exact>,
    time: f64,
) -> (LoadedSystem<D>, Vec<[i32; 3]>) {
    let lengths: [f64; D] = std::array::from_fn(|a| match exact {
        Some(e) => e.lengths[a],
        None => raw.bx[a],
    });
    let boundaries: [Boundary; D] = std::array::from_fn(|a| {
        if raw.walls[a] {
            Boundary::Walls
        } else {
            Boundary::Periodic
        }
    });
    let sim_box = SimBox {
        lengths,
        boundaries,
    };
    let n = raw.position.len();
    let mut discs = Vec::with_capacity(n);
    let mut images = Vec::with_capacity(n);
    for i in 0..n {
        let mut image = raw.image[i];
        let pos: [f64; D] = std::array::from_fn(|a| match exact {
            Some(e) => {
                image[a] -= e.shifts[i][a];
                e.position[i][a]
            }
            None => {
                let l = lengths[a];
                // For float32 terms the float64 sum is exact unless their magnitudes differ
                // by more than 2^29.
                let x = raw.position[i][a] + 0.5 * l;
                if sim_box.is_periodic(a) && !(0.0..l).contains(&x) {
                    let k = (x / l).floor();
                    let mut w = x - k * l;
                    let mut k = k as i64;
                    // `x - k l` can round up to `l` itself.
                    if w >= l {
                        w -= l;
                        k += 1;
                    }
                    image[a] =
                        (i64::from(image[a]) + k).clamp(i32::MIN.into(), i32::MAX.into()) as i32;
                    w
                } else {
                    x
                }
            }
        });
        let vel: [f64; D] = std::array::from_fn(|a| match exact {
            Some(e) => e.velocity[i][a],
            None => raw.velocity[i][a],
        });
        let radius = match exact.and_then(|e| e.radius.as_ref()) {
            Some(r) => r[i][0],
            None => 0.5 * raw.diameter[i][0],
        };
        let mass = match exact.and_then(|e| e.mass.as_ref()) {
            Some(m) => m[i][0],
            None => raw.mass[i][0],
        };
        discs.push(Disc {
            pos: Vector(pos),
            vel: Vector(vel),
            mass,
            radius,
            colour: raw.colour.as_ref().map_or([0, 0, 0], |c| c[i]),
            // Checked to fit by `read_open`.
            species: raw.typeid[i][0] as u16,
        });
        images.push(image);
    }
    let system = LoadedSystem {
        discs,
        sim_box,
        barriers: Vec::new(),
        lines: (1..=n).collect(),
        format: Format::Princeton(ColumnOrder::RadiusMass),
        time,
        potential: Default::default(),
        reactions: Vec::new(),
        restitution: None,
        gravity: None,
        shear: None,
        ring: None,
        self_gravity: None,
    };
    (system, images)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_rounded_onto_the_far_face_is_wrapped_or_moved_in() {
        let l = 1.0f32;
        // Just below L: x - L/2 rounds to +1/2 in float32.
        let x = 0.5 - 1e-12;
        assert_eq!(in_hoomd_box(x, l, true), (-0.5, 1));
        let (y, s) = in_hoomd_box(x, l, false);
        assert_eq!(s, 0);
        assert!(y < 0.5 && y > 0.4999999);
        assert_eq!(in_hoomd_box(-0.5, l, true), (-0.5, 0));
        assert_eq!(in_hoomd_box(0.25, l, true), (0.25, 0));
    }

    #[test]
    fn type_names_follow_the_alphabet_then_t_numbers() {
        let s = |t| {
            let row = type_name(t);
            row.iter()
                .take_while(|&&c| c != 0)
                .map(|&c| c as u8 as char)
                .collect::<String>()
        };
        assert_eq!(s(0), "A");
        assert_eq!(s(25), "Z");
        assert_eq!(s(26), "T26");
        assert_eq!(s(65535), "T65535");
    }
}
