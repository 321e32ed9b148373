//! Extended XYZ trajectory frames (the format of ASE and OVITO).
//!
//! Each frame is `N`, a comment line with `Lattice="..." Properties=... Time=... pbc="..."`, and
//! one line per disc: `species x y z vx vy vz px py pz radius mass mass r g b`, with `z = 0` in
//! 2D (both readers want three components) and the real `z` for spheres. Velocities and masses are written twice, because the two
//! readers name them differently: OVITO maps `velo` to Velocity and `mass` to Mass, while ASE
//! takes `momenta` (`m v`) and `masses` (it reads `velo` and `mass` as unnamed extra arrays, and
//! would otherwise give every disc the mass of hydrogen and zero velocity). Colours are written in `[0, 1]` as OVITO's `Color` property expects.
//! Species are written as element symbols (`H`, `He`, ... by species number) so that ASE, which
//! turns species into chemical symbols, reads every file.

use edmd_core::{Disc, SimBox};

/// Chemical symbols used for species 0, 1, 2, ...
const SYMBOLS: [&str; 10] = ["H", "He", "Li", "Be", "B", "C", "N", "O", "F", "Ne"];

/// Writes one frame.
pub fn write_frame<const D: usize>(
    out: &mut impl std::io::Write,
    discs: &[Disc<D>],
    sim_box: &SimBox<D>,
    time: f64,
) -> std::io::Result<()> {
    if D == 3 {
        return write_frame_3d(out, discs, sim_box, time);
    }
    let l = sim_box.lengths;
    let pbc: Vec<&str> = (0..D)
        .map(|a| if sim_box.is_periodic(a) { "T" } else { "F" })
        .collect();
    writeln!(out, "{}", discs.len())?;
    writeln!(
        out,
        "Lattice=\"{} 0.0 0.0 0.0 {} 0.0 0.0 0.0 1.0\" Properties=species:S:1:pos:R:3:velo:R:3:momenta:R:3:radius:R:1:mass:R:1:masses:R:1:color:R:3 Time={:?} pbc=\"{} {} F\"",
        l[0], l[1], time, pbc[0], pbc[1]
    )?;
    for d in discs {
        let s = SYMBOLS[d.species as usize % SYMBOLS.len()];
        writeln!(
            out,
            "{s} {:?} {:?} 0.0 {:?} {:?} 0.0 {:?} {:?} 0.0 {:?} {:?} {:?} {:.4} {:.4} {:.4}",
            d.pos[0],
            d.pos[1],
            d.vel[0],
            d.vel[1],
            d.mass * d.vel[0],
            d.mass * d.vel[1],
            d.radius,
            d.mass,
            d.mass,
            d.colour[0] as f64 / 255.0,
            d.colour[1] as f64 / 255.0,
            d.colour[2] as f64 / 255.0
        )?;
    }
    Ok(())
}

/// [`write_frame`] for spheres: real `z` components and the box's own `Lz`.
fn write_frame_3d<const D: usize>(
    out: &mut impl std::io::Write,
    discs: &[Disc<D>],
    sim_box: &SimBox<D>,
    time: f64,
) -> std::io::Result<()> {
    let l = sim_box.lengths;
    let pbc: Vec<&str> = (0..D)
        .map(|a| if sim_box.is_periodic(a) { "T" } else { "F" })
        .collect();
    writeln!(out, "{}", discs.len())?;
    writeln!(
        out,
        "Lattice=\"{} 0.0 0.0 0.0 {} 0.0 0.0 0.0 {}\" Properties=species:S:1:pos:R:3:velo:R:3:momenta:R:3:radius:R:1:mass:R:1:masses:R:1:color:R:3 Time={:?} pbc=\"{} {} {}\"",
        l[0], l[1], l[2], time, pbc[0], pbc[1], pbc[2]
    )?;
    for d in discs {
        let s = SYMBOLS[d.species as usize % SYMBOLS.len()];
        let (p, v, m) = (d.pos, d.vel, d.mass);
        writeln!(
            out,
            "{s} {:?} {:?} {:?} {:?} {:?} {:?} {:?} {:?} {:?} {:?} {:?} {:?} {:.4} {:.4} {:.4}",
            p[0],
            p[1],
            p[2],
            v[0],
            v[1],
            v[2],
            m * v[0],
            m * v[1],
            m * v[2],
            d.radius,
            m,
            m,
            d.colour[0] as f64 / 255.0,
            d.colour[1] as f64 / 255.0,
            d.colour[2] as f64 / 255.0
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use edmd_core::Vector;

    #[test]
    fn frame_layout() {
        let d = Disc::new(Vector::new([0.5, 0.25]), Vector::new([1.0, 0.0]), 0.1);
        let mut out = Vec::new();
        write_frame(&mut out, &[d], &SimBox::periodic([2.0, 3.0]), 1.5).unwrap();
        let text = String::from_utf8(out).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], "1");
        assert!(lines[1].starts_with("Lattice=\"2 0.0 0.0 0.0 3 0.0 0.0 0.0 1.0\""));
        assert!(lines[1].contains("Time=1.5 pbc=\"T T F\""));
        assert_eq!(
            lines[2],
            "H 0.5 0.25 0.0 1.0 0.0 0.0 1.0 0.0 0.0 0.1 1.0 1.0 0.0000 0.0000 0.0000"
        );
    }

    #[test]
    fn sphere_frame_has_real_z() {
        let mut d = Disc::new(
            Vector::new([0.5, 0.25, 2.5]),
            Vector::new([1.0, 0.0, -2.0]),
            0.1,
        );
        d.mass = 2.0;
        let mut out = Vec::new();
        let bx = SimBox {
            lengths: [2.0, 3.0, 4.0],
            boundaries: [
                edmd_core::Boundary::Periodic,
                edmd_core::Boundary::Periodic,
                edmd_core::Boundary::Walls,
            ],
        };
        write_frame(&mut out, &[d], &bx, 0.5).unwrap();
        let text = String::from_utf8(out).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert!(
            lines[1].starts_with("Lattice=\"2 0.0 0.0 0.0 3 0.0 0.0 0.0 4\""),
            "{}",
            lines[1]
        );
        assert!(lines[1].contains("pbc=\"T T F\""));
        assert_eq!(
            lines[2],
            "H 0.5 0.25 2.5 1.0 0.0 -2.0 2.0 0.0 -4.0 0.1 2.0 2.0 0.0000 0.0000 0.0000"
        );
    }
}
