//! The frame shared by the two kinds of checkpoint: a run's (`simulation/persist.rs`, magic
//! `EDMDCKPT`) and a packing's (`pack/persist.rs`, magic `EDMDPACK`).
//!
//! A file is the magic number (8 bytes), a format version (u32), the dimension (u32), the
//! payload length (u64), the payload, and a CRC-32 of everything before it, all
//! little-endian. [`open`] checks all of that before a payload byte is read; [`Reader`] fails
//! on every read past the end and bounds every count by the bytes left, so nothing is
//! allocated that the file does not hold.

use crate::error::Error;

/// Header bytes: magic, version, dimension, payload length.
pub(crate) const HEADER: usize = 8 + 4 + 4 + 8;

/// One kind of checkpoint.
pub(crate) struct Kind {
    /// Its first bytes.
    pub magic: &'static [u8; 8],
    /// The version this build writes (it reads that one and those in `older`).
    pub version: u32,
    /// Older versions this build still reads.
    pub older: &'static [u32],
    /// How a message names it when the other kind is given instead.
    pub name: &'static str,
    /// The lowest dimension it holds (the highest is 3).
    pub min_dim: usize,
}

/// A run's checkpoint (`edmd run`).
pub(crate) const RUN: Kind = Kind {
    magic: b"EDMDCKPT",
    version: 10,
    older: &[1, 2, 3, 4, 5, 6, 7, 8, 9],
    name: "a run checkpoint (edmd run continues it)",
    min_dim: 1,
};

/// A packing's checkpoint (`edmd pack`).
pub(crate) const PACK: Kind = Kind {
    magic: b"EDMDPACK",
    version: 1,
    older: &[],
    name: "a packing checkpoint (edmd pack continues it)",
    min_dim: 2,
};

const KINDS: [&Kind; 2] = [&RUN, &PACK];

/// [`open`] for a reader of dimension `D`: refuses a checkpoint of the other dimension, and
/// returns the format version and the payload.
pub(crate) fn open_as<'a, const D: usize>(
    bytes: &'a [u8],
    kind: &Kind,
) -> Result<(u32, &'a [u8]), Error> {
    let (dim, version, payload) = open(bytes, kind)?;
    if dim != D {
        return Err(Error::Checkpoint(format!(
            "a {dim}D checkpoint, read as {D}D"
        )));
    }
    Ok((version, payload))
}

/// Checks the frame of a checkpoint of `kind` and returns the dimension, the format version and
/// the payload.
pub(crate) fn open<'a>(bytes: &'a [u8], kind: &Kind) -> Result<(usize, u32, &'a [u8]), Error> {
    let bad = |what: String| Err(Error::Checkpoint(what));
    if bytes.len() < 8 || !bytes.starts_with(kind.magic) {
        if let Some(other) = KINDS.iter().find(|k| bytes.starts_with(k.magic)) {
            return bad(format!("this is {}, not {}", other.name, kind.name));
        }
        let magic = String::from_utf8_lossy(kind.magic);
        return bad(format!("not an edmd checkpoint (no {magic} magic number)"));
    }
    if bytes.len() < HEADER + 4 {
        return bad(format!(
            "truncated: {} bytes, shorter than the header",
            bytes.len()
        ));
    }
    let word = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().expect("4 bytes"));
    let version = word(8);
    if version != kind.version && !kind.older.contains(&version) {
        let newest = kind.version;
        // Far beyond this build's version, a newer edmd is less likely than a damaged header.
        return bad(if version > newest.saturating_add(1000) {
            format!("format version {version}: no edmd writes that; the file is corrupted")
        } else if version > newest {
            format!("format version {version} is newer than this edmd reads ({newest}); use a newer edmd")
        } else {
            format!("format version {version} is not one this edmd reads ({newest})")
        });
    }
    let dim = word(12) as usize;
    if !(kind.min_dim..=3).contains(&dim) {
        return bad(format!("dimension {dim} ({} to 3 expected)", kind.min_dim));
    }
    let len = u64::from_le_bytes(bytes[16..24].try_into().expect("8 bytes"));
    let expected = (HEADER as u64).saturating_add(len).saturating_add(4);
    if bytes.len() as u64 != expected {
        return bad(format!(
            "truncated or extended: {} bytes where the header says {expected}",
            bytes.len()
        ));
    }
    let body_end = bytes.len() - 4;
    let stored = u32::from_le_bytes(bytes[body_end..].try_into().expect("4 bytes"));
    if crc32fast::hash(&bytes[..body_end]) != stored {
        return bad("corrupted: the checksum does not match".into());
    }
    Ok((dim, version, &bytes[HEADER..body_end]))
}

/// Little-endian writer of a checkpoint: [`Writer::begin`] writes the header, [`Writer::seal`]
/// the length and the checksum.
pub(crate) struct Writer(pub Vec<u8>);

impl Writer {
    /// A checkpoint of `kind` and dimension `dim`, about `capacity` bytes long.
    pub fn begin(kind: &Kind, dim: usize, capacity: usize) -> Self {
        let mut w = Writer(Vec::with_capacity(HEADER + capacity + 4));
        w.0.extend_from_slice(kind.magic);
        w.u32(kind.version);
        w.u32(dim as u32);
        w.u64(0); // the payload length, filled in by `seal`
        w
    }
    /// The finished file: the payload length filled in and the checksum appended.
    pub fn seal(mut self) -> Vec<u8> {
        let payload = (self.0.len() - HEADER) as u64;
        self.0[16..24].copy_from_slice(&payload.to_le_bytes());
        let crc = crc32fast::hash(&self.0);
        self.u32(crc);
        self.0
    }
    pub fn u8(&mut self, x: u8) {
        self.0.push(x);
    }
    pub fn u32(&mut self, x: u32) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    pub fn u64(&mut self, x: u64) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    pub fn f64(&mut self, x: f64) {
        self.u64(x.to_bits());
    }
    pub fn len(&mut self, n: usize) {
        self.u64(n as u64);
    }
    pub fn bytes(&mut self, b: &[u8]) {
        self.len(b.len());
        self.0.extend_from_slice(b);
    }
}

/// Little-endian reader; every read past the end is an error.
pub(crate) struct Reader<'a> {
    pub bytes: &'a [u8],
    pub at: usize,
}

impl<'a> Reader<'a> {
    pub fn new(bytes: &'a [u8]) -> Self {
        Reader { bytes, at: 0 }
    }
    fn take(&mut self, k: usize) -> Result<&'a [u8], Error> {
        if self.bytes.len() - self.at < k {
            return Err(Error::Checkpoint("truncated payload".into()));
        }
        let s = &self.bytes[self.at..self.at + k];
        self.at += k;
        Ok(s)
    }
    pub fn u8(&mut self) -> Result<u8, Error> {
        Ok(self.take(1)?[0])
    }
    pub fn u32(&mut self) -> Result<u32, Error> {
        Ok(u32::from_le_bytes(self.take(4)?.try_into().expect("4")))
    }
    pub fn u64(&mut self) -> Result<u64, Error> {
        Ok(u64::from_le_bytes(self.take(8)?.try_into().expect("8")))
    }
    pub fn f64(&mut self) -> Result<f64, Error> {
        self.u64().map(f64::from_bits)
    }
    /// A count of items of `size` bytes each that must fit in what is left.
    pub fn len(&mut self, size: usize) -> Result<usize, Error> {
        let n = self.u64()?;
        let left = (self.bytes.len() - self.at) as u64;
        if n.saturating_mul(size.max(1) as u64) > left {
            return Err(Error::Checkpoint(format!(
                "a count of {n} does not fit in the {left} bytes left"
            )));
        }
        Ok(n as usize)
    }
    pub fn bytes(&mut self) -> Result<&'a [u8], Error> {
        let n = self.len(1)?;
        self.take(n)
    }
    /// A yes/no byte, 0 or 1 as written: anything else would not round-trip.
    pub fn flag(&mut self, what: &str) -> Result<bool, Error> {
        match self.u8()? {
            0 => Ok(false),
            1 => Ok(true),
            x => Err(Error::Checkpoint(format!(
                "{what} flag {x} (0 or 1 expected)"
            ))),
        }
    }
    /// Whether every byte has been read.
    pub fn at_end(&self) -> bool {
        self.at == self.bytes.len()
    }
}
