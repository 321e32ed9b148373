//! Command-line options of `edmd-view`, and building the simulation they describe.

use std::path::PathBuf;

use anyhow::Result;
use clap::{Parser, ValueEnum};
use edmd::input::{build, load, read_any, read_text};
use edmd::user_error;
use edmd_core::setup::generators::{generate, GenKind};
use edmd_core::{Boundary, Options, Simulation};
use edmd_draw::Colouring;
use edmd_io::princeton::ColumnOrder;

/// Disc colouring.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ColourArg {
    /// The file's colours.
    File,
    /// By speed (viridis: dark purple slow, yellow-green fast).
    Speed,
    /// By species.
    Species,
    /// By potential energy (stepped potentials only): blue bound, grey free, red repelled.
    Energy,
}

impl From<ColourArg> for Colouring {
    fn from(c: ColourArg) -> Self {
        match c {
            ColourArg::File => Colouring::File,
            ColourArg::Speed => Colouring::Speed,
            ColourArg::Species => Colouring::Species,
            ColourArg::Energy => Colouring::Energy,
        }
    }
}

/// Boundary of a generated fluid or mixture.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum BoundaryArg {
    /// Periodic in both directions.
    Periodic,
    /// Reflecting walls.
    Walls,
}

/// `edmd-view FILE` or `edmd-view --gen KIND`: watch hard discs collide, event by event.
///
/// Keys: space play/pause, right arrow one event, R restart, V reverse velocities, C next
/// colouring, B bonds (stepped potentials). Click a disc to tag it and draw its path.
#[derive(Debug, Parser)]
#[command(name = "edmd-view", version)]
pub struct ViewArgs {
    /// Data file (Princeton or course format, detected; `-` for standard input).
    #[arg(required_unless_present = "gen", conflicts_with = "gen")]
    pub file: Option<String>,
    /// Generate the system instead of reading it: single, head-on, angled, one-red, lattice,
    /// diffusion1, diffusion2, dense, brownian, fluid, mixture (as `edmd gen`).
    #[arg(long, value_name = "KIND")]
    pub gen: Option<String>,
    /// Number of discs (with --gen).
    #[arg(long, allow_negative_numbers = true)]
    pub n: Option<i64>,
    /// Packing fraction (with --gen dense, fluid or mixture).
    #[arg(long, allow_negative_numbers = true)]
    pub packing: Option<f64>,
    /// Boundaries (with --gen fluid or mixture).
    #[arg(long, value_enum)]
    pub boundary: Option<BoundaryArg>,
    /// Temperature kT (with --gen lattice, diffusion2, dense or brownian).
    #[arg(long, allow_negative_numbers = true)]
    pub kt: Option<f64>,
    /// Random seed of the generator (default 1).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Disc colouring.
    #[arg(long, value_enum, default_value_t = ColourArg::File)]
    pub colour: ColourArg,
    /// Stepped potentials: draw a bond between the discs of each pair inside a well or shoulder
    /// (B toggles it in the window; 2D and 3D).
    #[arg(long)]
    pub bonds: bool,
    /// Simulated time per second of wall time (default: a disc of RMS speed crosses a
    /// twentieth of the box per second).
    #[arg(long, value_name = "S", allow_negative_numbers = true)]
    pub speed: Option<f64>,
    /// Start paused.
    #[arg(long)]
    pub paused: bool,
    /// Print the mean frame rate on exit.
    #[arg(long)]
    pub fps_report: bool,
    /// Save a screenshot of the window as PNG (at --quit-after, or after 2 seconds).
    #[arg(long, value_name = "FILE.png")]
    pub screenshot: Option<PathBuf>,
    /// Quit after this many seconds of wall time (after taking the screenshot, if asked).
    #[arg(long, value_name = "SECONDS", allow_negative_numbers = true)]
    pub quit_after: Option<f64>,
    /// Window size in logical pixels, `WIDTHxHEIGHT`.
    #[arg(long, value_name = "WxH", default_value = "1280x800", value_parser = parse_size)]
    pub size: [f32; 2],
}

fn parse_size(s: &str) -> Result<[f32; 2], String> {
    let bad = || format!("'{s}' is not WIDTHxHEIGHT (for example 1280x800)");
    let (w, h) = s.split_once('x').ok_or_else(bad)?;
    let w: f32 = w.trim().parse().map_err(|_| bad())?;
    let h: f32 = h.trim().parse().map_err(|_| bad())?;
    if w >= 200.0 && h >= 150.0 && w.is_finite() && h.is_finite() {
        Ok([w, h])
    } else {
        Err(format!("'{s}': the window must be at least 200x150"))
    }
}

/// A simulation of any dimension.
pub enum AnySimulation {
    /// Rods on a line (self-gravitating sheets among them).
    One(Simulation<1>),
    /// Discs.
    Two(Simulation<2>),
    /// Spheres.
    Three(Simulation<3>),
}

impl ViewArgs {
    /// Checks the options that clap cannot.
    pub fn validate(&self) -> Result<()> {
        if self.gen.is_none() {
            let given = [
                ("n", self.n.is_some()),
                ("packing", self.packing.is_some()),
                ("boundary", self.boundary.is_some()),
                ("kt", self.kt.is_some()),
                ("seed", self.seed.is_some()),
            ];
            if let Some((flag, _)) = given.iter().find(|(_, g)| *g) {
                return user_error(format!(
                    "--{flag} needs --gen KIND (it sets up a generated system)"
                ));
            }
        }
        if let Some(s) = self.speed {
            if !(s.is_finite() && s > 0.0) {
                return user_error(format!("--speed must be a positive number, got {s}"));
            }
        }
        if let Some(q) = self.quit_after {
            if !(q.is_finite() && q >= 0.0) {
                return user_error(format!("--quit-after must be a number >= 0, got {q}"));
            }
        }
        if let Some(p) = &self.screenshot {
            let dir = p.parent().filter(|d| !d.as_os_str().is_empty());
            if dir.is_some_and(|d| !d.is_dir()) {
                return user_error(format!(
                    "{}: the folder for the screenshot does not exist",
                    p.display()
                ));
            }
        }
        Ok(())
    }

    /// Refuses `--bonds` and `--colour energy` for a system without a stepped potential
    /// (`stepped`: [`Simulation::is_stepped`]), as `edmd render` does.
    pub fn check_potential(&self, stepped: bool) -> Result<()> {
        if stepped {
            return Ok(());
        }
        let option = if self.bonds {
            "--bonds"
        } else if self.colour == ColourArg::Energy {
            "--colour energy"
        } else {
            return Ok(());
        };
        let what = match (&self.gen, self.file.as_deref()) {
            (Some(kind), _) => format!("--gen {kind}"),
            (None, file) => file.unwrap_or("-").to_string(),
        };
        user_error(format!(
            "{what}: {option} needs a stepped potential (a well or shoulder, '# edmd potential'), and this system has hard discs only"
        ))
    }

    /// Refuses `--bonds` for rods on a line: the picture is a strip with no room for bonds, and
    /// the rods of a pair inside a well are neighbours on the line anyway.
    pub fn check_line(&self) -> Result<()> {
        if !self.bonds {
            return Ok(());
        }
        let what = self.file.as_deref().unwrap_or("-");
        user_error(format!(
            "{what}: --bonds draws lines between discs or spheres; rods on a line have none (--colour energy shows their pairs' energy)"
        ))
    }

    /// The simulation to show, in the dimension of its file (1, 2 or 3; generated systems are
    /// 2D).
    pub fn simulation_any(&self) -> Result<AnySimulation> {
        if let Some(kind) = &self.gen {
            return self.generated(kind).map(AnySimulation::Two);
        }
        let path = self.file.as_deref().unwrap_or("-");
        match read_any(path, None, ColumnOrder::RadiusMass, None)? {
            edmd_io::AnyLoaded::Two(sys) => {
                build(path, &sys, Options::default()).map(AnySimulation::Two)
            }
            edmd_io::AnyLoaded::Three(sys) => {
                build(path, &sys, Options::default()).map(AnySimulation::Three)
            }
            edmd_io::AnyLoaded::One(sys) => {
                build(path, &sys, Options::default()).map(AnySimulation::One)
            }
        }
    }

    /// The simulation to show: the file read as `edmd run` reads it, or the generated system.
    pub fn simulation(&self) -> Result<Simulation> {
        if let Some(kind) = &self.gen {
            return self.generated(kind);
        }
        let path = self.file.as_deref().unwrap_or("-");
        let text = read_text(path)?;
        let sys = load(path, &text, None, ColumnOrder::RadiusMass)?;
        build(path, &sys, Options::default())
    }

    fn generated(&self, name: &str) -> Result<Simulation> {
        let Ok(mut kind) = GenKind::from_name(name) else {
            return user_error(format!(
                "--gen: unknown kind '{name}' (one of: {})",
                GenKind::NAMES.join(", ")
            ));
        };
        let n = match self.n {
            Some(n) if n < 1 => return user_error(format!("--n must be at least 1, got {n}")),
            n => n.map(|n| n as usize),
        };
        let boundary = self.boundary.map(|b| match b {
            BoundaryArg::Periodic => Boundary::Periodic,
            BoundaryArg::Walls => Boundary::Walls,
        });
        let mut used: Vec<&str> = Vec::new();
        macro_rules! set {
            ($flag:literal, $opt:expr, $field:expr) => {
                if let Some(v) = $opt {
                    $field = v;
                    used.push($flag);
                }
            };
        }
        match &mut kind {
            GenKind::Single(_) | GenKind::HeadOn(_) | GenKind::Angled(_) => {}
            GenKind::OneRed(k) => set!("n", n, k.n),
            GenKind::Lattice(k) => {
                set!("n", n, k.n);
                set!("kt", self.kt, k.kt);
            }
            GenKind::Diffusion1(k) => set!("n", n, k.n),
            GenKind::Diffusion2(k) => {
                set!("n", n, k.n);
                set!("kt", self.kt, k.kt);
            }
            GenKind::Dense(k) => {
                set!("n", n, k.n);
                set!("packing", self.packing, k.packing);
                set!("kt", self.kt, k.kt);
            }
            GenKind::Brownian(k) => {
                set!("n", n, k.n);
                set!("kt", self.kt, k.kt);
            }
            GenKind::Fluid(k) => {
                set!("n", n, k.n);
                set!("packing", self.packing, k.packing);
                set!("boundary", boundary, k.boundary);
            }
            GenKind::Mixture(k) => {
                set!("n", n, k.n);
                set!("packing", self.packing, k.packing);
                set!("boundary", boundary, k.boundary);
            }
        }
        let given = [
            ("n", self.n.is_some()),
            ("packing", self.packing.is_some()),
            ("boundary", self.boundary.is_some()),
            ("kt", self.kt.is_some()),
        ];
        if let Some((flag, _)) = given.iter().find(|(f, g)| *g && !used.contains(f)) {
            return user_error(format!(
                "--gen {name}: --{flag} does not apply to this kind"
            ));
        }
        let system = generate(&kind, self.seed.unwrap_or(1))
            .or_else(|e| user_error(format!("--gen {name}: {e}")))?;
        Simulation::from_system(&system, Options::default())
            .or_else(|e| user_error(format!("--gen {name}: {e}")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(args: &[&str]) -> Result<ViewArgs, clap::Error> {
        ViewArgs::try_parse_from(std::iter::once("edmd-view").chain(args.iter().copied()))
    }

    #[test]
    fn generated_fluid() {
        let a = parse(&[
            "--gen",
            "fluid",
            "--n",
            "100",
            "--packing",
            "0.3",
            "--seed",
            "3",
        ])
        .unwrap();
        a.validate().unwrap();
        let sim = a.simulation().unwrap();
        assert_eq!(sim.len(), 100);
        assert_eq!(a.size, [1280.0, 800.0]);
    }

    #[test]
    fn options_that_do_not_apply_are_refused() {
        let a = parse(&["--gen", "single", "--n", "10"]).unwrap();
        let e = a.simulation().unwrap_err().to_string();
        assert!(e.contains("--n does not apply"), "{e}");
        let a = parse(&["--gen", "nonsense"]).unwrap();
        assert!(a
            .simulation()
            .unwrap_err()
            .to_string()
            .contains("unknown kind"));
    }

    #[test]
    fn bonds_and_energy_colours_need_a_stepped_potential() {
        let a = parse(&["--gen", "fluid", "--bonds"]).unwrap();
        assert!(a.bonds);
        let e = a.check_potential(false).unwrap_err().to_string();
        assert!(e.contains("--bonds") && e.contains("hard discs"), "{e}");
        a.check_potential(true).unwrap();
        let a = parse(&["x.txt", "--colour", "energy"]).unwrap();
        assert_eq!(Colouring::from(a.colour), Colouring::Energy);
        let e = a.check_potential(false).unwrap_err().to_string();
        assert!(e.starts_with("x.txt: --colour energy"), "{e}");
        parse(&["--gen", "fluid"])
            .unwrap()
            .check_potential(false)
            .unwrap();
    }

    #[test]
    fn a_file_or_a_generator_but_not_both() {
        assert!(parse(&[]).is_err());
        assert!(parse(&["f.txt", "--gen", "fluid"]).is_err());
        assert!(parse(&["f.txt", "--n", "3"]).unwrap().validate().is_err());
        assert!(parse(&["f.txt", "--seed", "3"])
            .unwrap()
            .validate()
            .is_err());
        assert!(parse(&["f.txt", "--size", "10x10"]).is_err());
        let a = parse(&["f.txt", "--speed", "-1"]).unwrap();
        assert!(a.validate().is_err());
    }

    /// A file with reaction rules opens with its collisions reactive, and the picture shows each
    /// disc in the colour of the species it has now: the discs' colours are read from the
    /// simulation at every frame, so a product takes its species' colour when it is made, and a
    /// restart gives the reactants theirs back.
    #[test]
    fn a_file_with_reactions_shows_the_products_in_their_colour() {
        use crate::model::Model;
        use edmd_draw::AnyScene;
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("react.txt");
        // Head on at t = 1 with normal kinetic energy 1 (reduced mass 1/2, closing at 2), over
        // the activation energy 0.5: both become species 2, which no disc has, so they take
        // its colour from the palette.
        std::fs::write(
            &path,
            "2\n# edmd box 10 10\n# edmd reaction 0 + 1 -> 2 + 2 activation 0.5\n3 5 1 0 1 1 200 0 0 0\n7 5 -1 0 1 1 0 0 200 1\n",
        )
        .unwrap();
        let a = parse(&[path.to_str().unwrap()]).unwrap();
        let AnySimulation::Two(sim) = a.simulation_any().unwrap() else {
            panic!("a 2D file");
        };
        assert_eq!(sim.reactions().map(|r| r.rules.len()), Some(1));
        let colours = |m: &Model| match m.scene() {
            AnyScene::Flat(s) => s.colours,
            _ => unreachable!("a 2D file"),
        };
        let mut m = Model::new(sim, Colouring::File);
        assert_eq!(colours(&m), vec![[200, 0, 0], [0, 0, 200]]);
        m.run_until(0.5);
        assert_eq!(colours(&m), vec![[200, 0, 0], [0, 0, 200]]);
        m.run_until(2.0);
        let made = edmd_core::state::species_colour(2);
        assert_eq!(colours(&m), vec![made, made]);
        assert_eq!(m.sim.reaction_counts(), &[1]);
        m.restart();
        assert_eq!(colours(&m), vec![[200, 0, 0], [0, 0, 200]]);
    }

    #[test]
    fn a_missing_file_is_one_user_error() {
        let a = parse(&["/nonexistent/discs.txt"]).unwrap();
        let e = a.simulation().unwrap_err();
        assert!(e.downcast_ref::<edmd::UserError>().is_some());
        assert!(e.to_string().contains("cannot read"));
    }

    /// A 1D file opens as rods on a line (it was refused, naming `edmd render`): the rods
    /// where the file puts them, drawn as a strip, and the example file of the guide too.
    #[test]
    fn a_1d_file_opens_as_rods_on_a_line() {
        use crate::model::Model;
        use edmd_draw::AnyScene;
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("rods.txt");
        std::fs::write(&path, "1\n# edmd dim 1\n# edmd box 4\n1 1 0.5 1 0 0 0\n").unwrap();
        let a = parse(&[path.to_str().unwrap()]).unwrap();
        let Ok(AnySimulation::One(sim)) = a.simulation_any() else {
            panic!("a 1D file did not open as rods on a line");
        };
        assert_eq!((sim.len(), sim.sim_box().lengths), (1, [4.0]));
        a.check_line().unwrap();
        let m = Model::new(sim, Colouring::File);
        match m.scene() {
            AnyScene::Line(s) => {
                assert_eq!((s.length, s.periodic), (4.0, false));
                assert_eq!((s.positions, s.radii), (vec![1.0], vec![0.5]));
            }
            _ => panic!("rods drawn as discs or spheres"),
        }
        assert_eq!(m.phase_points(), vec![[1.0, 1.0]]);

        let example = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../examples/data/rods-1d.txt"
        );
        let Ok(AnySimulation::One(sim)) = parse(&[example]).unwrap().simulation_any() else {
            panic!("{example} did not open as rods on a line");
        };
        assert_eq!(sim.len(), 12);
        assert!(sim.sim_box().is_periodic(0));
    }

    #[test]
    fn bonds_are_refused_on_a_line() {
        let a = parse(&["rods.txt", "--bonds"]).unwrap();
        let e = a.check_line().unwrap_err();
        assert!(e.downcast_ref::<edmd::UserError>().is_some());
        let e = e.to_string();
        assert!(
            e.starts_with("rods.txt: --bonds") && e.contains("rods on a line"),
            "{e}"
        );
        parse(&["rods.txt", "--colour", "energy"])
            .unwrap()
            .check_line()
            .unwrap();
    }
}
