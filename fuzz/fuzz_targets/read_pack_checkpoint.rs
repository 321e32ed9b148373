//! Packing checkpoint files (`Packer::from_checkpoint`), as `read_checkpoint` fuzzes a run's:
//! the first byte is a mode; with its high bit set the rest is a whole file as it is (the
//! frame: magic, version, dimension, length, checksum); otherwise the rest is a payload, framed
//! here with a correct length and CRC-32 (dimension 2 or 3 from the low bit), so that the
//! mutations reach every structural check behind the checksum. Nothing may panic; an accepted
//! checkpoint must give back the same bytes and run.
#![no_main]

use edmd_fuzz::{
    box_is_tame, checkpoint_box, frame_pack_checkpoint, pack_checkpoint, CHECKPOINT_HEADER,
};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Some((&mode, rest)) = data.split_first() else {
        return;
    };
    let bytes = if mode & 0x80 != 0 {
        rest.to_vec()
    } else {
        frame_pack_checkpoint(2 + u32::from(mode & 1), rest)
    };
    // Keep clear of known defect 1 (a box far longer on one axis makes the engine's cell grid
    // huge; the reader checks the particles with the engine's constructor). The payload starts
    // with the box, as a run checkpoint's does.
    let dim = if bytes.len() >= CHECKPOINT_HEADER {
        u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize
    } else {
        0
    };
    if dim == 2 || dim == 3 {
        if let Some(lengths) = checkpoint_box(dim, &bytes[CHECKPOINT_HEADER..]) {
            if lengths.iter().all(|l| l.is_finite() && *l > 0.0) && !box_is_tame(&lengths) {
                return;
            }
        }
    }
    pack_checkpoint(&bytes);
});
