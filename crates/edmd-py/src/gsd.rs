//! A small write-only GSD layer: frames in the HOOMD schema, as read by the `gsd` Python
//! package, HOOMD-blue, OVITO and VMD.
//!
//! GSD file layer 2.0 (<https://gsd.readthedocs.io/en/stable/specification.html>): a 256-byte
//! header, the data chunks, then the name list (NUL-terminated names; a chunk's id is its
//! name's place in the list) and the index (one 32-byte entry per chunk, sorted by frame), both
//! written by [`Writer::finish`], which then rewrites the header to point at them.
//!
//! The HOOMD schema (1.4) wants a box centred on the origin, so positions are written as
//! `x - L/2`; positions, velocities, diameters and masses are float32, as the schema says.
//! HOOMD boxes are periodic: which axes have walls, and the exact time, are `log/` chunks
//! (`log/edmd/walls`, one uint8 per axis of x, y, z; `log/edmd/time`, float64).

use std::io::{Seek, SeekFrom, Write};

use edmd_core::Simulation;

const MAGIC: u64 = 0x65DF_65DF_65DF_65DF;
const HEADER: u64 = 256;

const fn version(major: u32, minor: u32) -> u32 {
    (major << 16) | minor
}

/// GSD data types.
#[derive(Clone, Copy)]
#[repr(u8)]
enum Type {
    U8 = 1,
    U32 = 3,
    U64 = 4,
    I8 = 5,
    I32 = 7,
    F32 = 9,
    F64 = 10,
}

struct Entry {
    frame: u64,
    n: u64,
    location: u64,
    m: u32,
    id: u16,
    kind: Type,
}

/// Writes GSD frames to `W`; the file is complete once [`Writer::finish`] has run (dropping
/// the writer finishes it too, ignoring errors).
pub struct Writer<W: Write + Seek = std::io::BufWriter<std::fs::File>> {
    out: Option<W>,
    at: u64,
    frame: u64,
    names: Vec<&'static str>,
    index: Vec<Entry>,
}

impl Writer<std::io::BufWriter<std::fs::File>> {
    /// A writer to a new file.
    pub fn new(file: std::fs::File) -> std::io::Result<Self> {
        Writer::to(std::io::BufWriter::new(file))
    }
}

impl<W: Write + Seek> Writer<W> {
    /// A writer to any seekable output, positioned at its start.
    pub fn to(mut out: W) -> std::io::Result<Self> {
        out.write_all(&[0u8; HEADER as usize])?;
        Ok(Writer {
            out: Some(out),
            at: HEADER,
            frame: 0,
            names: Vec::new(),
            index: Vec::new(),
        })
    }

    fn chunk(
        &mut self,
        name: &'static str,
        kind: Type,
        n: u64,
        m: u32,
        bytes: &[u8],
    ) -> std::io::Result<()> {
        let id = match self.names.iter().position(|x| *x == name) {
            Some(k) => k,
            None => {
                self.names.push(name);
                self.names.len() - 1
            }
        };
        self.index.push(Entry {
            frame: self.frame,
            n,
            location: self.at,
            m,
            id: id as u16,
            kind,
        });
        self.out.as_mut().expect("not finished").write_all(bytes)?;
        self.at += bytes.len() as u64;
        Ok(())
    }

    /// Writes the simulation's current state as the next frame.
    pub fn frame<const D: usize>(&mut self, sim: &Simulation<D>) -> std::io::Result<()> {
        let n = sim.len();
        let b = sim.sim_box();
        let l = |a: usize| if a < D { b.lengths[a] } else { 0.0 };
        let f32s = |v: &[f32]| v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();
        let step = (sim.stats().disc_disc).to_le_bytes();
        self.chunk("configuration/step", Type::U64, 1, 1, &step)?;
        self.chunk("configuration/dimensions", Type::U8, 1, 1, &[D as u8])?;
        let bx = [l(0) as f32, l(1) as f32, l(2) as f32, 0.0, 0.0, 0.0];
        self.chunk("configuration/box", Type::F32, 6, 1, &f32s(&bx))?;
        self.chunk("particles/N", Type::U32, 1, 1, &(n as u32).to_le_bytes())?;
        let mut pos = Vec::with_capacity(3 * n);
        let mut vel = Vec::with_capacity(3 * n);
        let mut image = Vec::with_capacity(3 * n);
        for i in 0..n {
            let p = sim.position(i);
            let u = sim.unwrapped_position(i);
            let v = sim.velocity(i);
            for a in 0..3 {
                if a < D {
                    pos.push((p[a] - 0.5 * b.lengths[a]) as f32);
                    vel.push(v[a] as f32);
                    image.push(((u[a] - p[a]) / b.lengths[a]).round() as i32);
                } else {
                    pos.push(0.0);
                    vel.push(0.0);
                    image.push(0);
                }
            }
        }
        self.chunk("particles/position", Type::F32, n as u64, 3, &f32s(&pos))?;
        self.chunk("particles/velocity", Type::F32, n as u64, 3, &f32s(&vel))?;
        let diam: Vec<f32> = (0..n).map(|i| (2.0 * sim.radius(i)) as f32).collect();
        self.chunk("particles/diameter", Type::F32, n as u64, 1, &f32s(&diam))?;
        let mass: Vec<f32> = (0..n).map(|i| sim.mass(i) as f32).collect();
        self.chunk("particles/mass", Type::F32, n as u64, 1, &f32s(&mass))?;
        let typeid: Vec<u8> = (0..n)
            .flat_map(|i| u32::from(sim.species(i)).to_le_bytes())
            .collect();
        self.chunk("particles/typeid", Type::U32, n as u64, 1, &typeid)?;
        let types = (0..n)
            .map(|i| sim.species(i))
            .max()
            .map_or(1, |m| m as usize + 1);
        // Type names "A", "B", ... then "T26", "T27", ...: NUL-padded rows of int8.
        let names: Vec<String> = (0..types)
            .map(|t| {
                if t < 26 {
                    ((b'A' + t as u8) as char).to_string()
                } else {
                    format!("T{t}")
                }
            })
            .collect();
        let width = names.iter().map(|s| s.len()).max().unwrap_or(1) + 1;
        let mut tb = vec![0u8; types * width];
        for (t, s) in names.iter().enumerate() {
            tb[t * width..t * width + s.len()].copy_from_slice(s.as_bytes());
        }
        self.chunk("particles/types", Type::I8, types as u64, width as u32, &tb)?;
        let image: Vec<u8> = image.iter().flat_map(|x| x.to_le_bytes()).collect();
        self.chunk("particles/image", Type::I32, n as u64, 3, &image)?;
        let walls: Vec<u8> = (0..3)
            .map(|a| u8::from(a < D && !b.is_periodic(a)))
            .collect();
        self.chunk("log/edmd/walls", Type::U8, 3, 1, &walls)?;
        self.chunk("log/edmd/time", Type::F64, 1, 1, &sim.time().to_le_bytes())?;
        self.frame += 1;
        Ok(())
    }

    /// Writes the name list, the index and the header; returns the output.
    pub fn finish(mut self) -> std::io::Result<W> {
        self.finish_in_place()?;
        Ok(self.out.take().expect("finished once"))
    }

    fn finish_in_place(&mut self) -> std::io::Result<()> {
        let Some(out) = self.out.as_mut() else {
            return Ok(());
        };
        let namelist_location = self.at;
        // Layer 2.0 packs the names, each ending in NUL, an empty name ending the list,
        // allocated in blocks of 64 bytes.
        let mut names = Vec::new();
        for s in &self.names {
            names.extend_from_slice(s.as_bytes());
            names.push(0);
        }
        names.push(0);
        names.resize(names.len().div_ceil(64) * 64, 0);
        let name_entries = names.len() / 64;
        out.write_all(&names)?;
        let index_location = namelist_location + names.len() as u64;
        // At least one (empty) index entry: readers scan for the end.
        let index_entries = self.index.len().max(1);
        let mut index = Vec::with_capacity(32 * index_entries);
        for e in &self.index {
            index.extend_from_slice(&e.frame.to_le_bytes());
            index.extend_from_slice(&e.n.to_le_bytes());
            index.extend_from_slice(&e.location.to_le_bytes());
            index.extend_from_slice(&e.m.to_le_bytes());
            index.extend_from_slice(&e.id.to_le_bytes());
            index.push(e.kind as u8);
            index.push(0);
        }
        index.resize(32 * index_entries, 0);
        out.write_all(&index)?;
        let mut header = Vec::with_capacity(HEADER as usize);
        header.extend_from_slice(&MAGIC.to_le_bytes());
        header.extend_from_slice(&index_location.to_le_bytes());
        header.extend_from_slice(&(index_entries as u64).to_le_bytes());
        header.extend_from_slice(&namelist_location.to_le_bytes());
        header.extend_from_slice(&(name_entries as u64).to_le_bytes());
        header.extend_from_slice(&version(1, 4).to_le_bytes());
        header.extend_from_slice(&version(2, 0).to_le_bytes());
        let mut text = |s: &str, len: usize| {
            let mut b = vec![0u8; len];
            b[..s.len()].copy_from_slice(s.as_bytes());
            header.extend_from_slice(&b);
        };
        text(concat!("edmd ", env!("CARGO_PKG_VERSION")), 64);
        text("hoomd", 64);
        text("", 80);
        out.seek(SeekFrom::Start(0))?;
        out.write_all(&header)?;
        out.seek(SeekFrom::End(0))?;
        out.flush()?;
        self.at = index_location + index.len() as u64;
        Ok(())
    }
}

impl<W: Write + Seek> Drop for Writer<W> {
    fn drop(&mut self) {
        if self.out.is_some() {
            let _ = self.finish_in_place();
        }
    }
}
