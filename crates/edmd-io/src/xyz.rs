//! Extended XYZ trajectory frames (the format of ASE and OVITO).
//!
//! Each frame is `N`, a comment line with `Lattice="..." Properties=... Time=... pbc="..."`, and
//! one line per disc: `species x y z vx vy vz px py pz radius mass mass r g b`, with `z = 0` in
//! 2D (both readers want three components), `y = z = 0` for rods on a line (1D) and the real
//! `z` for spheres. Velocities and masses are written twice, because the two
//! readers name them differently: OVITO maps `velo` to Velocity and `mass` to Mass, while ASE
//! takes `momenta` (`m v`) and `masses` (it reads `velo` and `mass` as unnamed extra arrays, and
//! would otherwise give every disc the mass of hydrogen and zero velocity). Colours are written in `[0, 1]` as OVITO's `Color` property expects.
//! Species are written as element symbols (`H`, `He`, ... by species number: species `k` is the
//! element of atomic number `k + 1`) so that ASE, which turns species into chemical symbols,
//! reads every file and keeps every species apart. There are 118 elements: a system with a
//! species from 118 on is refused before anything is written ([`check_species`]).

use edmd_core::{Disc, SimBox};

/// Chemical symbols used for species 0, 1, 2, ...: the elements in order of atomic number.
const SYMBOLS: [&str; 118] = [
    "H", "He", "Li", "Be", "B", "C", "N", "O", "F", "Ne", "Na", "Mg", "Al", "Si", "P", "S", "Cl",
    "Ar", "K", "Ca", "Sc", "Ti", "V", "Cr", "Mn", "Fe", "Co", "Ni", "Cu", "Zn", "Ga", "Ge", "As",
    "Se", "Br", "Kr", "Rb", "Sr", "Y", "Zr", "Nb", "Mo", "Tc", "Ru", "Rh", "Pd", "Ag", "Cd", "In",
    "Sn", "Sb", "Te", "I", "Xe", "Cs", "Ba", "La", "Ce", "Pr", "Nd", "Pm", "Sm", "Eu", "Gd", "Tb",
    "Dy", "Ho", "Er", "Tm", "Yb", "Lu", "Hf", "Ta", "W", "Re", "Os", "Ir", "Pt", "Au", "Hg", "Tl",
    "Pb", "Bi", "Po", "At", "Rn", "Fr", "Ra", "Ac", "Th", "Pa", "U", "Np", "Pu", "Am", "Cm", "Bk",
    "Cf", "Es", "Fm", "Md", "No", "Lr", "Rf", "Db", "Sg", "Bh", "Hs", "Mt", "Ds", "Rg", "Cn", "Nh",
    "Fl", "Mc", "Lv", "Ts", "Og",
];

/// The number of species extended XYZ can tell apart: one per chemical element.
pub const MAX_SPECIES: usize = SYMBOLS.len();

/// Refuses discs with a species that has no element symbol (from [`MAX_SPECIES`] on): ASE
/// reads species as chemical symbols, so two species written with one symbol would become one.
/// The message names the first such disc (0-based) and its species.
pub fn check_species<const D: usize>(discs: &[Disc<D>]) -> Result<(), String> {
    match discs
        .iter()
        .position(|d| d.species as usize >= MAX_SPECIES)
    {
        Some(i) => Err(format!(
            "disc {i} has species {}, and extended XYZ names species by chemical element (species 0 to {} are H to Og): a trajectory cannot keep it apart; use a .gsd trajectory",
            discs[i].species,
            MAX_SPECIES - 1
        )),
        None => Ok(()),
    }
}

fn symbol(species: u16) -> std::io::Result<&'static str> {
    SYMBOLS.get(species as usize).copied().ok_or_else(|| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!("species {species} has no chemical symbol in extended XYZ"),
        )
    })
}

/// Writes one frame. A species without an element symbol ([`check_species`]) is an
/// `InvalidInput` error, before anything is written.
pub fn write_frame<const D: usize>(
    out: &mut impl std::io::Write,
    discs: &[Disc<D>],
    sim_box: &SimBox<D>,
    time: f64,
) -> std::io::Result<()> {
    check_species(discs).map_err(|e| std::io::Error::new(std::io::ErrorKind::InvalidInput, e))?;
    if D == 3 {
        return write_frame_3d(out, discs, sim_box, time);
    }
    // Rods on a line (1D) are written as discs on the x axis: y = 0, with a unit, non-periodic
    // y length as the 2D frames have a unit z.
    let l = |a: usize| if a < D { sim_box.lengths[a] } else { 1.0 };
    let pbc = |a: usize| {
        if a < D && sim_box.is_periodic(a) {
            "T"
        } else {
            "F"
        }
    };
    let c = |v: edmd_core::Vector<D>, a: usize| if a < D { v[a] } else { 0.0 };
    writeln!(out, "{}", discs.len())?;
    writeln!(
        out,
        "Lattice=\"{} 0.0 0.0 0.0 {} 0.0 0.0 0.0 1.0\" Properties=species:S:1:pos:R:3:velo:R:3:momenta:R:3:radius:R:1:mass:R:1:masses:R:1:color:R:3 Time={:?} pbc=\"{} {} F\"",
        l(0), l(1), time, pbc(0), pbc(1)
    )?;
    for d in discs {
        let s = symbol(d.species)?;
        writeln!(
            out,
            "{s} {:?} {:?} 0.0 {:?} {:?} 0.0 {:?} {:?} 0.0 {:?} {:?} {:?} {:.4} {:.4} {:.4}",
            c(d.pos, 0),
            c(d.pos, 1),
            c(d.vel, 0),
            c(d.vel, 1),
            d.mass * c(d.vel, 0),
            d.mass * c(d.vel, 1),
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
        let s = symbol(d.species)?;
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

    // Species 0 and 10 were both written as H (the symbols went round after ten), so ASE read
    // two species as one.
    #[test]
    fn every_species_has_its_own_symbol_and_too_many_are_refused() {
        let mut seen = std::collections::HashSet::new();
        for k in 0..MAX_SPECIES as u16 {
            assert!(
                seen.insert(symbol(k).unwrap()),
                "species {k} repeats a symbol"
            );
        }
        assert_eq!(symbol(0).unwrap(), "H");
        assert_eq!(symbol(10).unwrap(), "Na");
        assert_eq!(symbol(117).unwrap(), "Og");
        let mut d = Disc::new(Vector::new([0.5, 0.25]), Vector::new([1.0, 0.0]), 0.1);
        d.species = 118;
        let mut out = Vec::new();
        let e = write_frame(&mut out, &[d], &SimBox::walls([1.0, 1.0]), 0.0).unwrap_err();
        assert!(e.to_string().contains("disc 0 has species 118"), "{e}");
        assert!(out.is_empty(), "nothing is written before the refusal");
    }

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

    #[test]
    fn rods_are_written_on_the_x_axis() {
        let d = Disc::new(Vector([0.5]), Vector([-2.0]), 0.25);
        let mut out = Vec::new();
        write_frame(&mut out, &[d], &SimBox::periodic([4.0]), 0.5).unwrap();
        let text = String::from_utf8(out).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], "1");
        assert!(
            lines[1].starts_with("Lattice=\"4 0.0 0.0 0.0 1 0.0"),
            "{text}"
        );
        assert!(lines[1].ends_with("pbc=\"T F F\""), "{text}");
        assert_eq!(
            lines[2],
            "H 0.5 0.0 0.0 -2.0 0.0 0.0 -2.0 0.0 0.0 0.25 1.0 1.0 0.0000 0.0000 0.0000"
        );
    }
}
