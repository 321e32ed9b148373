//! `edmd gen KIND [options] --seed S -o FILE`: write a configuration.
//!
//! Every kind starts from its documented defaults (`edmd_core::setup::generators`); each
//! option overrides one parameter, and an option that a kind does not have is an error rather
//! than silently ignored. [`ChemistryArgs`] adds species in given proportions and reaction
//! rules ([`make_with`]). `edmd gen ring` makes a patch of a planetary ring
//! (`edmd_core::setup::ring::RingPatch`), written with its `# edmd ring` line ([`ring_of`]);
//! `edmd gen sheets` a water bag of self-gravitating sheets
//! (`edmd_core::setup::sheets::WaterBag`), written with its `# edmd self-gravity` line
//! ([`self_gravity_of`]).

use std::path::Path;

use anyhow::Result;
use clap::Args;
use edmd_core::setup::generators::{generate, GenKind};
use edmd_core::setup::Sizes;
use edmd_core::{Boundary, Reaction, Reactions};
use edmd_io::princeton::ColumnOrder;
use edmd_io::{Format, Interactions};

use crate::options::BoundaryArg;
use crate::output::AtomicFile;
use crate::user_error;

/// Every option of `edmd gen`: the system's ([`GenArgs`]) and its species' and reactions'
/// ([`ChemistryArgs`]).
#[derive(Debug, Args)]
pub struct GenCommand {
    /// The system (boxed: its options make it the largest of the commands' arguments).
    #[command(flatten)]
    pub args: Box<GenArgs>,
    /// Species and reaction rules.
    #[command(flatten)]
    pub chemistry: ChemistryArgs,
    /// Inelastic collisions, as '# edmd restitution' lines: each a line's words ('0.9',
    /// 'bridges 0.01', '0 1 0.5', 'walls 0.8', 'tc 1e-4'), repeated for more.
    #[arg(long, value_name = "RESTITUTION", allow_hyphen_values = true)]
    pub restitution: Vec<String>,
}

/// The restitution of `--restitution` lines (none without any): each read as a
/// `# edmd restitution` line, every part given at most once, and checked beside the other
/// options (not with the course format, a potential or reaction rules).
pub fn restitution_of(
    args: &GenArgs,
    chemistry: &ChemistryArgs,
    given: &[String],
) -> Result<Option<edmd_core::Restitution>> {
    let name = &args.kind;
    if given.is_empty() {
        return Ok(None);
    }
    if args.course {
        return user_error(format!(
            "gen {name}: the course format has no place for restitution (--course with --restitution)"
        ));
    }
    if args.well.is_some() || args.shoulder.is_some() {
        return user_error(format!(
            "gen {name}: --restitution does not go with --well or --shoulder"
        ));
    }
    if !chemistry.reaction.is_empty() {
        return user_error(format!(
            "gen {name}: --restitution does not go with --reaction"
        ));
    }
    let mut r = edmd_core::Restitution::default();
    let mut parts: Vec<edmd_io::restitution::Part> = Vec::new();
    for text in given {
        let words: Vec<&str> = text.split_whitespace().collect();
        let part = edmd_io::restitution::parse(&words, &mut r)
            .or_else(|e| user_error(format!("gen {name}: --restitution '{text}': {e}")))?;
        if parts.iter().any(|q| q.same(part)) {
            return user_error(format!(
                "gen {name}: --restitution '{text}': a second restitution for {}; give it once",
                part.name()
            ));
        }
        parts.push(part);
    }
    Ok(Some(r))
}

/// Options of `edmd gen` for reactive systems: species in given proportions, and reaction
/// rules written into the file.
#[derive(Clone, Debug, Default, Args)]
pub struct ChemistryArgs {
    /// Species in these proportions (fluid): the number fractions of species 0, 1, 2, ...,
    /// summing to 1 (`--species 0.5,0.5`). Species k gets N f_k discs, rounded down and the
    /// largest remainders up so that the counts add up to N, placed at random (seeded by
    /// --seed), and a colour of its own.
    #[arg(long, value_name = "F0,F1,...")]
    pub species: Option<String>,
    /// A reaction rule, written into the file as a '# edmd reaction' line (repeat for more):
    /// 'A + B -> C + D [activation E] [probability P] [heat Q]', species whole numbers, the
    /// spaces optional ('0+1->2+2 activation 1').
    #[arg(long, value_name = "RULE")]
    pub reaction: Vec<String>,
}

/// Options of `edmd gen`.
#[derive(Debug, Args)]
pub struct GenArgs {
    /// What to generate: single, head-on, angled, one-red, lattice, diffusion1, diffusion2,
    /// dense, brownian, fluid, mixture, ring, sheets.
    pub kind: String,
    /// Output file (`-` for standard output).
    #[arg(long, short, value_name = "FILE")]
    pub output: String,
    /// Dimension: 2 (discs), 3 (spheres; fluid, mixture and ring only) or 1 (hard rods on a
    /// line; fluid and sheets only). Default 2, 3 for ring and 1 for sheets.
    #[arg(long, value_parser = crate::options::parse_dim_with_rods)]
    pub dim: Option<usize>,
    /// Random seed: the same seed gives the same file.
    #[arg(long, default_value_t = 1, allow_negative_numbers = true)]
    pub seed: u64,
    /// Write the course format instead of the Princeton format (equal discs in a walled box).
    #[arg(long)]
    pub course: bool,
    /// Number of discs (for diffusion2: per side; for one-red and brownian: the crowd).
    #[arg(long, allow_negative_numbers = true)]
    pub n: Option<i64>,
    /// Disc radius (brownian: the small discs).
    #[arg(long, allow_negative_numbers = true)]
    pub radius: Option<f64>,
    /// Disc speed.
    #[arg(long, allow_negative_numbers = true)]
    pub speed: Option<f64>,
    /// Disc mass (brownian: the small discs).
    #[arg(long, allow_negative_numbers = true)]
    pub mass: Option<f64>,
    /// Temperature kT (energy units; 5e-5 gives mass 1 an rms speed of 0.01).
    #[arg(long, allow_negative_numbers = true)]
    pub kt: Option<f64>,
    /// Packing fraction (area fraction).
    #[arg(long, allow_negative_numbers = true)]
    pub packing: Option<f64>,
    /// Boundaries (fluid, mixture).
    #[arg(long, value_enum)]
    pub boundary: Option<BoundaryArg>,
    /// Angle between the paths in degrees (angled).
    #[arg(long, allow_negative_numbers = true)]
    pub angle: Option<f64>,
    /// Impact parameter as a fraction of the contact distance (angled).
    #[arg(long, allow_negative_numbers = true)]
    pub impact: Option<f64>,
    /// Side of the central square the discs start in (diffusion1).
    #[arg(long, allow_negative_numbers = true)]
    pub region: Option<f64>,
    /// Radius of the big disc (brownian).
    #[arg(long, allow_negative_numbers = true)]
    pub big_radius: Option<f64>,
    /// Mass of the big disc (brownian).
    #[arg(long, allow_negative_numbers = true)]
    pub big_mass: Option<f64>,
    /// Diameter ratio large/small (mixture, binary).
    #[arg(long, allow_negative_numbers = true)]
    pub size_ratio: Option<f64>,
    /// Number fraction of large discs (mixture, binary).
    #[arg(long, allow_negative_numbers = true)]
    pub fraction_large: Option<f64>,
    /// Polydisperse mixture with diameters uniform in 1 +- SPREAD (instead of binary).
    #[arg(long, allow_negative_numbers = true)]
    pub spread: Option<f64>,
    /// A square-well fluid: a well out to LAMBDA diameters (fluid).
    #[arg(long, value_name = "LAMBDA", allow_negative_numbers = true)]
    pub well: Option<f64>,
    /// A square-shoulder fluid: a shoulder out to LAMBDA diameters (fluid).
    #[arg(long, value_name = "LAMBDA", allow_negative_numbers = true)]
    pub shoulder: Option<f64>,
    /// Depth of the well or height of the shoulder (default 1).
    #[arg(long, value_name = "E", allow_negative_numbers = true)]
    pub depth: Option<f64>,
    /// A uniform field of acceleration G along the last axis (y in 2D, z in 3D; negative
    /// pulls towards 0), written as '# edmd gravity y G' (or z). That axis gets walls; the
    /// others keep --boundary (for fluid and mixture, periodic unless walls are asked for).
    #[arg(long, value_name = "G", allow_hyphen_values = true)]
    pub gravity: Option<f64>,
    /// Shear the fluid at RATE with Lees-Edwards boundaries (fluid and mixture, periodic
    /// boxes), written as '# edmd shear RATE 0': the images across y slide along x at RATE
    /// times the box's height, and the velocities start on the streaming profile
    /// RATE (y - Ly/2) along x, so the run starts in steady flow. Negative: the flow the
    /// other way.
    #[arg(long, value_name = "RATE", allow_hyphen_values = true)]
    pub shear: Option<f64>,
    /// The dynamical optical depth of a ring patch, N pi r^2 / (Lx Ly) (ring; default 0.25;
    /// up to 0.5 in 2D, 2 in 3D).
    #[arg(long, allow_negative_numbers = true)]
    pub tau: Option<f64>,
    /// The orbital frequency Omega of a ring patch (ring; default 1).
    #[arg(long, value_name = "OMEGA", allow_negative_numbers = true)]
    pub omega: Option<f64>,
    /// The velocity dispersion a ring patch starts with about the Keplerian flow, per axis, in
    /// units of Omega times the particles' diameter (ring; default 2; the particles have
    /// radius 0.5, so diameter 1).
    #[arg(long, allow_negative_numbers = true)]
    pub dispersion: Option<f64>,
    /// The height of a 3D ring patch's box, between walls along z, in diameters (ring;
    /// default 60, at least 4).
    #[arg(long, allow_negative_numbers = true)]
    pub height: Option<f64>,
    /// Half the width of a water bag of sheets: positions uniform in [-WIDTH, WIDTH] about
    /// the line's middle (sheets; default 1).
    #[arg(long, allow_negative_numbers = true)]
    pub width: Option<f64>,
    /// The self-gravity's coupling of sheets, 2 pi G per unit area: each sheet is pulled by
    /// COUPLING times the mass on its right less the mass on its left (sheets; default 1/N,
    /// so that the whole mass pulls with 1).
    #[arg(long, allow_negative_numbers = true)]
    pub coupling: Option<f64>,
}

impl GenArgs {
    /// The dimension: `--dim`, else 3 for a ring patch, 1 for sheets and 2 for the rest.
    pub fn dim(&self) -> usize {
        self.dim.unwrap_or(match self.kind.as_str() {
            RING => 3,
            SHEETS => 1,
            _ => 2,
        })
    }

    /// The stepped potential `--well` or `--shoulder` asks for, for discs of diameter
    /// `diameter` (none: hard cores alone).
    pub fn potential(&self, diameter: f64) -> Result<edmd_core::Potential> {
        let name = &self.kind;
        let (lambda, sign) = match (self.well, self.shoulder) {
            (None, None) => {
                if self.depth.is_some() {
                    return user_error(format!(
                        "gen {name}: --depth goes with --well or --shoulder"
                    ));
                }
                return Ok(edmd_core::Potential::default());
            }
            (Some(_), Some(_)) => {
                return user_error(format!("gen {name}: give --well or --shoulder, not both"))
            }
            (Some(l), None) => (l, -1.0),
            (None, Some(l)) => (l, 1.0),
        };
        if name != "fluid" {
            return user_error(format!(
                "gen {name}: --well and --shoulder make fluids only (gen fluid)"
            ));
        }
        if !(lambda.is_finite() && lambda > 1.0 && lambda <= 100.0) {
            return user_error(format!(
                "gen {name}: the range must be above 1 and at most 100 diameters, found {lambda}"
            ));
        }
        let depth = self.depth.unwrap_or(1.0);
        if !(depth.is_finite() && depth > 0.0 && depth <= edmd_core::MAX_STEP_ENERGY) {
            return user_error(format!(
                "gen {name}: --depth must be above 0 and at most {:e}, found {depth}",
                edmd_core::MAX_STEP_ENERGY
            ));
        }
        Ok(edmd_core::Potential::single(
            0,
            0,
            lambda * diameter,
            sign * depth,
        ))
    }

    /// [`Self::potential`] for a generated system: its largest diameter. Refuses a range the
    /// periodic box cannot hold three times across (the run would refuse the file).
    pub fn potential_of(&self, generated: &Generated) -> Result<edmd_core::Potential> {
        // The largest radius and the box's shortest side.
        fn sizes<const D: usize>(s: &edmd_core::System<D>) -> (f64, f64) {
            let shortest = s.sim_box.lengths.iter().copied();
            (
                s.discs.iter().map(|d| d.radius).fold(0.0, f64::max),
                shortest.fold(f64::INFINITY, f64::min),
            )
        }
        let (radius, shortest) = match generated {
            Generated::Two(s, _) => sizes(s),
            Generated::Three(s) => sizes(s),
            Generated::One(s) => sizes(s),
        };
        let potential = self.potential(2.0 * radius)?;
        let reach = potential
            .pairs
            .iter()
            .flat_map(|p| p.steps.last())
            .map(|s| s.radius)
            .fold(0.0, f64::max);
        // The neighbour lists' cells need three ranges across a periodic box, and a little
        // skin (`Steps::new`).
        if reach > 0.0 && shortest < 3.01 * reach {
            return user_error(format!(
                "gen {}: the box ({shortest:.4} across) is too small for a range of {reach:.4}: a periodic box must be over 3 ranges across; give more discs (--n) or a shorter range",
                self.kind
            ));
        }
        Ok(potential)
    }
}

/// A generated system in its dimension, with the format `edmd gen` writes it in.
#[derive(Clone, Debug)]
pub enum Generated {
    /// Discs, in the course or the Princeton format.
    Two(edmd_core::System<2>, Format),
    /// Spheres (a 3D Princeton file).
    Three(edmd_core::System<3>),
    /// Hard rods on a line (a 1D Princeton file).
    One(edmd_core::System<1>),
}

impl Generated {
    /// 1, 2 or 3.
    pub fn dim(&self) -> usize {
        match self {
            Generated::One(_) => 1,
            Generated::Two(..) => 2,
            Generated::Three(_) => 3,
        }
    }
}

/// Runs `edmd gen`.
pub fn run(cmd: &GenCommand) -> Result<()> {
    let args: &GenArgs = &cmd.args;
    crate::output::check_file_destinations(&[("--output", Path::new(&args.output))])?;
    let restitution = restitution_of(args, &cmd.chemistry, &cmd.restitution)?;
    let (generated, rules) = make_with(args, &cmd.chemistry)?;
    let potential = args.potential_of(&generated)?;
    let gravity = gravity_of(args, &generated)?;
    let shear = shear_of(args, &generated)?;
    let ring = ring_of(args)?;
    let self_gravity = self_gravity_of(args)?;
    check_self_gravity_with(args, restitution.is_some(), !rules.is_empty())?;
    if let Some(r) = ring.and(restitution.as_ref()) {
        check_ring_restitution(r, &args.kind)?;
    }
    if let (Some(g), Some(r)) = (gravity, &restitution) {
        if r.tc <= 0.0 && !r.is_elastic() {
            return user_error(format!(
                "gen {}: inelastic collisions in a field need the TC model: add --restitution 'tc T' (T > 0), or grains coming to rest on the floor would collide infinitely often in a finite time (--gravity {})",
                args.kind, g.g
            ));
        }
        if r.wall == 0.0 {
            return user_error(format!(
                "gen {}: in a field the walls' restitution must be above 0 (--restitution 'walls 0'): a disc stopped dead at the floor would meet it again at once",
                args.kind
            ));
        }
    }
    let interactions = Interactions {
        potential: &potential,
        reactions: &rules,
        restitution: restitution.as_ref(),
        gravity,
        // A ring's shear is written in its own line.
        shear: ring
            .map(|r| edmd_core::Shear::new(r.shear_rate()))
            .or(shear),
        self_gravity,
    };
    let princeton = Format::Princeton(ColumnOrder::RadiusMass);
    match generated {
        Generated::Two(system, format) => write_system(&system, interactions, ring, format, args),
        Generated::Three(system) => write_system(&system, interactions, ring, princeton, args),
        Generated::One(system) => write_system(&system, interactions, ring, princeton, args),
    }
}

/// [`make`], with the species and reaction rules of `chemistry`: the system with its discs'
/// species assigned (`--species`), and the rules (`--reaction`), each checked (their text, one
/// rule per pair of species, every reactant a species some disc is or some rule makes).
pub fn make_with(args: &GenArgs, chemistry: &ChemistryArgs) -> Result<(Generated, Vec<Reaction>)> {
    let name = &args.kind;
    let fractions = match &chemistry.species {
        None => None,
        Some(_) if name != "fluid" => {
            return user_error(format!("gen {name}: --species applies to fluid"))
        }
        Some(_) if args.course => {
            return user_error(format!(
                "gen {name}: the course format has no species (--course with --species)"
            ))
        }
        Some(_) if args.well.is_some() || args.shoulder.is_some() => {
            return user_error(format!(
                "gen {name}: --species does not go with --well or --shoulder (their steps are between discs of species 0)"
            ))
        }
        Some(text) => Some(species_fractions(name, text)?),
    };
    let rules = reaction_rules(args, &chemistry.reaction)?;
    let mut generated = make(args)?;
    if let Some(fractions) = fractions {
        match &mut generated {
            Generated::Two(s, _) => assign_species(&mut s.discs, &fractions, args.seed),
            Generated::Three(s) => assign_species(&mut s.discs, &fractions, args.seed),
            Generated::One(s) => assign_species(&mut s.discs, &fractions, args.seed),
        }
    }
    let species: Vec<u16> = match &generated {
        Generated::Two(s, _) => s.discs.iter().map(|d| d.species).collect(),
        Generated::Three(s) => s.discs.iter().map(|d| d.species).collect(),
        Generated::One(s) => s.discs.iter().map(|d| d.species).collect(),
    };
    let made: Vec<u16> = rules
        .iter()
        .flat_map(|r| [r.products.0, r.products.1])
        .collect();
    for (text, r) in chemistry.reaction.iter().zip(&rules) {
        for s in [r.reactants.0, r.reactants.1] {
            if !made.contains(&s) && !species.contains(&s) {
                return user_error(format!(
                    "gen {name}: --reaction '{text}': no disc is of species {s} and no rule makes it"
                ));
            }
        }
    }
    Ok((generated, rules))
}

/// The rules of `--reaction`, each read and all checked together (before any system is made).
fn reaction_rules(args: &GenArgs, given: &[String]) -> Result<Vec<Reaction>> {
    let name = &args.kind;
    if given.is_empty() {
        return Ok(Vec::new());
    }
    if args.course {
        return user_error(format!(
            "gen {name}: the course format has no place for reaction rules (--course with --reaction)"
        ));
    }
    if args.well.is_some() || args.shoulder.is_some() {
        return user_error(format!(
            "gen {name}: --reaction does not go with --well or --shoulder (a reaction would change a pair's steps)"
        ));
    }
    let mut rules = Vec::new();
    for text in given {
        match edmd_io::reaction::parse_text(text) {
            Ok(r) => rules.push(r),
            Err(e) => return user_error(format!("gen {name}: --reaction '{text}': {e}")),
        }
    }
    Reactions::new(rules.clone())
        .validate()
        .or_else(|e| user_error(format!("gen {name}: --reaction: {e}")))?;
    Ok(rules)
}

/// The fractions of `--species F0,F1,...`: each a finite number `>= 0`, at most
/// `MAX_REACTION_SPECIES` of them (the species rules can name), summing to 1.
fn species_fractions(name: &str, text: &str) -> Result<Vec<f64>> {
    let mut fractions = Vec::new();
    for w in text.split(',') {
        match w.trim().parse::<f64>() {
            Ok(f) if f.is_finite() && f >= 0.0 => fractions.push(f),
            _ => {
                return user_error(format!(
                    "gen {name}: --species {text}: each fraction must be a number >= 0, found '{w}'"
                ))
            }
        }
    }
    let most = edmd_core::MAX_REACTION_SPECIES as usize;
    if fractions.len() > most {
        return user_error(format!(
            "gen {name}: --species: {} fractions, more than the {most} species reaction rules can name",
            fractions.len()
        ));
    }
    let sum: f64 = fractions.iter().sum();
    if (sum - 1.0).abs() > 1e-6 {
        return user_error(format!(
            "gen {name}: --species {text}: the fractions must sum to 1, and they sum to {sum}"
        ));
    }
    Ok(fractions)
}

/// Gives the discs species in the proportions `fractions` (of species 0, 1, ...): species `k`
/// gets `N f_k` discs rounded down, and the discs left over go one each to the species with
/// the largest remainders (the lower species first among equal ones), so the counts are as
/// near the fractions as whole numbers allow and add up to `N`; which disc is which is a
/// shuffle seeded by `seed`. Each disc takes its species' colour
/// (`edmd_core::state::species_colour`).
fn assign_species<const D: usize>(discs: &mut [edmd_core::Disc<D>], fractions: &[f64], seed: u64) {
    let n = discs.len();
    let sum: f64 = fractions.iter().sum();
    let exact: Vec<f64> = fractions.iter().map(|f| f / sum * n as f64).collect();
    let mut counts: Vec<usize> = exact.iter().map(|x| x.floor() as usize).collect();
    let mut order: Vec<usize> = (0..fractions.len()).collect();
    order.sort_by(|&a, &b| {
        let (ra, rb) = (exact[a] - exact[a].floor(), exact[b] - exact[b].floor());
        rb.total_cmp(&ra).then(a.cmp(&b))
    });
    let short = n.saturating_sub(counts.iter().sum());
    for &k in order.iter().cycle().take(short) {
        counts[k] += 1;
    }
    let mut labels: Vec<u16> = counts
        .iter()
        .enumerate()
        .flat_map(|(k, &c)| std::iter::repeat_n(k as u16, c))
        .collect();
    labels.truncate(n);
    // Fisher-Yates with SplitMix64, its stream apart from the generators' (which seed PCG).
    let mut state = seed ^ 0x5BEC_1E50_0000_0001;
    let mut next = || {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    };
    for i in (1..labels.len()).rev() {
        let j = ((u128::from(next()) * (i as u128 + 1)) >> 64) as usize;
        labels.swap(i, j);
    }
    for (d, &s) in discs.iter_mut().zip(&labels) {
        d.species = s;
        d.colour = edmd_core::state::species_colour(s);
    }
}

/// Validates the options and generates the system `edmd gen` would write (`args.output` is not
/// used). The Python package calls this too, so both make the same system from the same seed.
/// Under `--shear` the velocities are on the streaming profile ([`shear_of`] gives the shear).
pub fn make(args: &GenArgs) -> Result<Generated> {
    let generated = make_in_field(args)?;
    let Some(shear) = shear_of(args, &generated)? else {
        return Ok(generated);
    };
    Ok(match generated {
        Generated::Two(mut s, f) => {
            on_profile(&mut s, shear.rate);
            Generated::Two(s, f)
        }
        Generated::Three(mut s) => {
            on_profile(&mut s, shear.rate);
            Generated::Three(s)
        }
        // Refused by `shear_of`.
        Generated::One(s) => Generated::One(s),
    })
}

/// Adds the streaming velocity `rate (y - L_y / 2)` to each disc's x velocity, so that a
/// sheared run starts in steady flow rather than spending its first `1 / rate` building it.
fn on_profile<const D: usize>(system: &mut edmd_core::System<D>, rate: f64) {
    let ly = system.sim_box.lengths[1];
    for d in &mut system.discs {
        d.vel[0] += rate * (d.pos[1] - 0.5 * ly);
    }
}

/// The shear `--shear` asks for, from an offset of 0, checked against the other options and
/// the box of `generated` (periodic x and y); `None` without it.
pub fn shear_of(args: &GenArgs, generated: &Generated) -> Result<Option<edmd_core::Shear>> {
    let Some(rate) = args.shear else {
        return Ok(None);
    };
    let name = &args.kind;
    if args.course {
        return user_error(format!(
            "gen {name}: the course format has no place for shear (--course with --shear)"
        ));
    }
    if args.well.is_some() || args.shoulder.is_some() {
        return user_error(format!(
            "gen {name}: --shear does not go with --well or --shoulder"
        ));
    }
    if args.gravity.is_some() {
        return user_error(format!("gen {name}: --shear does not go with --gravity"));
    }
    if !matches!(name.as_str(), "fluid" | "mixture") {
        return user_error(format!(
            "gen {name}: --shear shears fluids and mixtures only (gen fluid, gen mixture)"
        ));
    }
    let (dim, lx, periodic) = match generated {
        Generated::Two(s, _) => (
            2,
            s.sim_box.lengths[0],
            s.sim_box.is_periodic(0) && s.sim_box.is_periodic(1),
        ),
        Generated::Three(s) => (
            3,
            s.sim_box.lengths[0],
            s.sim_box.is_periodic(0) && s.sim_box.is_periodic(1),
        ),
        Generated::One(_) => {
            return user_error(format!(
                "gen {name}: --shear slides the images across y, and rods on a line (--dim 1) have no y axis"
            ))
        }
    };
    if !periodic {
        return user_error(format!(
            "gen {name}: --shear needs a periodic box (Lees-Edwards boundaries slide the images across y), not --boundary walls"
        ));
    }
    let shear = edmd_core::Shear::new(rate);
    shear
        .validate(dim, lx)
        .or_else(|e| user_error(format!("gen {name}: --shear {rate}: {e}")))?;
    Ok(Some(shear))
}

/// [`make`] before the velocities are put on the streaming profile: the system in its box,
/// with a field's walls.
fn make_in_field(args: &GenArgs) -> Result<Generated> {
    let generated = make_in_box(args)?;
    if args.gravity.is_none() {
        return Ok(generated);
    }
    // Made between walls on every axis (`apply`), so that turning the sideways axes periodic
    // keeps every disc clear of the others' images.
    let sideways = match args.boundary {
        Some(BoundaryArg::Walls) => Boundary::Walls,
        _ => Boundary::Periodic,
    };
    let fluid = matches!(args.kind.as_str(), "fluid" | "mixture");
    let open = |bx: &mut edmd_core::SimBox<2>| {
        if fluid {
            bx.boundaries[0] = sideways;
        }
    };
    let open3 = |bx: &mut edmd_core::SimBox<3>| {
        if fluid {
            bx.boundaries[0] = sideways;
            bx.boundaries[1] = sideways;
        }
    };
    Ok(match generated {
        Generated::Two(mut s, f) => {
            open(&mut s.sim_box);
            Generated::Two(s, f)
        }
        Generated::Three(mut s) => {
            open3(&mut s.sim_box);
            Generated::Three(s)
        }
        // A line has no sideways axis: the field is along x, between walls.
        Generated::One(s) => Generated::One(s),
    })
}

/// The field `--gravity` asks for, along the last axis of `generated` (which has walls there:
/// [`make`]), checked; `None` without it.
pub fn gravity_of(args: &GenArgs, generated: &Generated) -> Result<Option<edmd_core::Gravity>> {
    let Some(g) = args.gravity else {
        return Ok(None);
    };
    let name = &args.kind;
    if args.course {
        return user_error(format!(
            "gen {name}: the course format has no place for a field (--course with --gravity)"
        ));
    }
    if args.well.is_some() || args.shoulder.is_some() {
        return user_error(format!(
            "gen {name}: --gravity does not go with --well or --shoulder"
        ));
    }
    let (dim, walled) = match generated {
        Generated::Two(s, _) => (2, !s.sim_box.is_periodic(1)),
        Generated::Three(s) => (3, !s.sim_box.is_periodic(2)),
        Generated::One(s) => (1, !s.sim_box.is_periodic(0)),
    };
    let field = edmd_core::Gravity { axis: dim - 1, g };
    field
        .validate(dim)
        .or_else(|e| user_error(format!("gen {name}: --gravity {g}: {e}")))?;
    if !walled {
        return user_error(format!(
            "gen {name}: --gravity needs walls along {}",
            ["x", "y", "z"][dim - 1]
        ));
    }
    Ok(Some(field))
}

/// [`make`] without the field's box.
fn make_in_box(args: &GenArgs) -> Result<Generated> {
    if args.kind == RING {
        return make_ring(args);
    }
    if args.kind == SHEETS {
        return make_sheets(args);
    }
    let Ok(mut kind) = GenKind::from_name(&args.kind) else {
        return user_error(format!(
            "gen: unknown kind '{}' (one of: {}, {RING}, {SHEETS})",
            args.kind,
            GenKind::NAMES.join(", ")
        ));
    };
    if args.dim() == 3 {
        return make_3d(kind, args);
    }
    if args.dim() == 1 {
        return make_1d(kind, args);
    }
    apply(&mut kind, args)?;
    check_cost(&kind)?;
    let system =
        generate(&kind, args.seed).or_else(|e| user_error(format!("gen {}: {e}", args.kind)))?;
    let format = if args.course {
        if let Err(why) = edmd_io::course::fits(&system.discs, &system.sim_box, &system.barriers) {
            return user_error(format!(
                "gen {}: cannot write the course format: {why}",
                args.kind
            ));
        }
        Format::Course
    } else {
        Format::Princeton(ColumnOrder::RadiusMass)
    };
    Ok(Generated::Two(at_kt(system, args)?, format))
}

/// `edmd gen fluid|mixture --dim 3`: spheres, written as a 3D Princeton file.
fn make_3d(mut kind: GenKind, args: &GenArgs) -> Result<Generated> {
    // The 2D defaults (0.6 and 0.7) are above what spheres allow: 0.45 is a dense fluid, 0.5
    // a dense mixture.
    match &mut kind {
        GenKind::Fluid(k) => k.packing = 0.45,
        GenKind::Mixture(k) => k.packing = 0.5,
        _ => {
            return user_error(format!(
                "gen {}: --dim 3 makes fluids and mixtures only",
                args.kind
            ))
        }
    }
    if args.course {
        return user_error("gen: the course format holds 2D systems only (--course with --dim 3)");
    }
    apply(&mut kind, args)?;
    check_cost(&kind)?;
    let made = match &kind {
        GenKind::Fluid(k) => k.generate_in::<3>(args.seed),
        GenKind::Mixture(k) => k.generate_in::<3>(args.seed),
        _ => unreachable!("checked above"),
    };
    let (system, _) = made.or_else(|e| user_error(format!("gen {}: {e}", args.kind)))?;
    Ok(Generated::Three(at_kt(system, args)?))
}

/// `edmd gen fluid --dim 1`: hard rods (length 1, mass 1) evenly spaced on a line with thermal
/// velocities ([`edmd_core::setup::lattice::rods`]), written as a 1D Princeton file. Rods never
/// pass each other, so there is no lattice to melt: the even spacing is the start.
fn make_1d(mut kind: GenKind, args: &GenArgs) -> Result<Generated> {
    let name = &args.kind;
    match &mut kind {
        GenKind::Fluid(k) => k.packing = 0.5,
        _ => {
            return user_error(format!(
                "gen {name}: --dim 1 makes fluids only (gen fluid: rods on a line)"
            ))
        }
    }
    if args.course {
        return user_error("gen: the course format holds 2D systems only (--course with --dim 1)");
    }
    apply(&mut kind, args)?;
    check_cost(&kind)?;
    let GenKind::Fluid(k) = &kind else {
        unreachable!("checked above")
    };
    let (discs, sim_box) = edmd_core::setup::lattice::rods(k.n, k.packing, k.boundary, args.seed)
        .or_else(|e| user_error(format!("gen {name}: {e}")))?;
    let system = edmd_core::System {
        discs,
        sim_box,
        barriers: Vec::new(),
    };
    Ok(Generated::One(at_kt(system, args)?))
}

/// A fluid at `--kt`: the generator's velocities (kT = 1) scaled by `sqrt(kT)`.
fn at_kt<const D: usize>(
    mut system: edmd_core::System<D>,
    args: &GenArgs,
) -> Result<edmd_core::System<D>> {
    if let (Some(kt), "fluid") = (args.kt, args.kind.as_str()) {
        // The thermostat's bound: speeds at a larger kT overflow into infinite energies.
        if !(kt.is_finite() && kt > 0.0 && kt <= edmd_core::MAX_STEP_ENERGY) {
            return user_error(format!(
                "gen fluid: --kt must be above 0 and at most {:e}, found {kt}",
                edmd_core::MAX_STEP_ENERGY
            ));
        }
        let scale = kt.sqrt();
        for d in &mut system.discs {
            d.vel = d.vel * scale;
        }
    }
    Ok(system)
}

/// Writes a generated system to `args.output` (atomically) or standard output.
fn write_system<const D: usize>(
    system: &edmd_core::System<D>,
    interactions: Interactions,
    ring: Option<edmd_core::Ring>,
    format: Format,
    args: &GenArgs,
) -> Result<()> {
    if format == Format::Course && !interactions.potential.is_hard() {
        return user_error(format!(
            "gen {}: the course format has no place for a potential (--course with --well or --shoulder)",
            args.kind
        ));
    }
    if args.output == "-" {
        let mut out = std::io::stdout().lock();
        edmd_io::write_full_ring(
            &mut out,
            &system.discs,
            &system.sim_box,
            &system.barriers,
            interactions,
            ring,
            format,
            0.0,
        )?;
        std::io::Write::flush(&mut out)?;
    } else {
        let mut f = AtomicFile::create(Path::new(&args.output))?;
        edmd_io::write_full_ring(
            f.writer(),
            &system.discs,
            &system.sim_box,
            &system.barriers,
            interactions,
            ring,
            format,
            0.0,
        )?;
        f.commit()?;
        let rules = match interactions.reactions.len() {
            0 => String::new(),
            1 => " with 1 reaction rule".to_string(),
            k => format!(" with {k} reaction rules"),
        };
        eprintln!(
            "edmd gen: {} {} ({}){rules} written to {}",
            system.discs.len(),
            match D {
                1 => "rods",
                3 => "spheres",
                _ => "discs",
            },
            args.kind,
            args.output
        );
    }
    Ok(())
}

/// The name of the ring patch's kind, `edmd gen ring`.
pub const RING: &str = "ring";

/// The ring patch's particles' radius: diameter 1, the unit `--dispersion` and `--height`
/// are in.
pub const RING_RADIUS: f64 = 0.5;

/// The patch `edmd gen ring` makes, from its options and their defaults (400 particles,
/// optical depth 0.25, Omega 1, a dispersion of 2 Omega d, a box 60 diameters high), every
/// option it does not take refused.
pub fn ring_patch(args: &GenArgs) -> Result<edmd_core::setup::ring::RingPatch> {
    let name = RING;
    let others = [
        (
            "radius (the particles have radius 0.5)",
            args.radius.is_some(),
        ),
        ("speed", args.speed.is_some()),
        ("mass", args.mass.is_some()),
        ("kt (the ring's is --dispersion)", args.kt.is_some()),
        ("packing (the ring's is --tau)", args.packing.is_some()),
        (
            "boundary (x and y are periodic, z has walls)",
            args.boundary.is_some(),
        ),
        ("angle", args.angle.is_some()),
        ("impact", args.impact.is_some()),
        ("region", args.region.is_some()),
        ("big-radius", args.big_radius.is_some()),
        ("big-mass", args.big_mass.is_some()),
        ("size-ratio", args.size_ratio.is_some()),
        ("fraction-large", args.fraction_large.is_some()),
        ("spread", args.spread.is_some()),
        ("well", args.well.is_some()),
        ("shoulder", args.shoulder.is_some()),
        ("depth", args.depth.is_some()),
        (
            "gravity (the ring has its own vertical pull, Omega^2 z)",
            args.gravity.is_some(),
        ),
        (
            "shear (the ring shears at -3/2 Omega itself)",
            args.shear.is_some(),
        ),
        ("width", args.width.is_some()),
        ("coupling", args.coupling.is_some()),
    ];
    if let Some((flag, _)) = others.iter().find(|(_, given)| *given) {
        return user_error(format!(
            "gen {name}: --{flag} does not apply to a ring patch"
        ));
    }
    if args.course {
        return user_error(format!(
            "gen {name}: the course format has no place for a ring patch (--course)"
        ));
    }
    let n = match args.n {
        None => 400,
        Some(n) if n < 2 || n as u64 > crate::MAX_N as u64 => {
            return user_error(format!(
                "gen {name}: --n must be from 2 to {}, found {n}",
                crate::MAX_N
            ))
        }
        Some(n) => n as usize,
    };
    let omega = args.omega.unwrap_or(1.0);
    // Bounded above so that the speeds of the flow and the positions stay far from
    // overflowing (an orbital frequency of 10^300 gave speeds whose energy is not finite).
    let checked = |flag: &str, v: f64, zero: bool| {
        if v.is_finite() && (v > 0.0 || (zero && v == 0.0)) && v <= 1e6 {
            Ok(v)
        } else {
            user_error(format!(
                "gen {name}: --{flag} must be a finite number {} and at most 1e6, found {v}",
                if zero { ">= 0" } else { "> 0" }
            ))
        }
    };
    let omega = checked("omega", omega, false)?;
    let tau = checked("tau", args.tau.unwrap_or(0.25), false)?;
    let dispersion = checked("dispersion", args.dispersion.unwrap_or(2.0), true)?;
    let height = match (args.dim(), args.height) {
        (3, h) => checked("height", h.unwrap_or(60.0), false)?,
        (_, Some(_)) => {
            return user_error(format!(
                "gen {name}: --height is the 3D box's (a 2D patch has no z axis)"
            ))
        }
        (_, None) => 60.0,
    };
    if !matches!(args.dim(), 2 | 3) {
        return user_error(format!(
            "gen {name}: a ring patch has 2 or 3 dimensions, not --dim {}",
            args.dim()
        ));
    }
    Ok(edmd_core::setup::ring::RingPatch {
        n,
        tau,
        radius: RING_RADIUS,
        omega,
        dispersion: dispersion * omega * 2.0 * RING_RADIUS,
        height,
        seed: args.seed,
    })
}

/// `edmd gen ring`: the patch, on the Keplerian flow (its ring is [`ring_of`]'s).
fn make_ring(args: &GenArgs) -> Result<Generated> {
    let patch = ring_patch(args)?;
    let failed =
        |e: edmd_core::Error| anyhow::Error::from(crate::UserError(format!("gen {RING}: {e}")));
    Ok(match args.dim() {
        2 => {
            let (discs, sim_box) = patch.build::<2>().map_err(failed)?;
            Generated::Two(
                edmd_core::System {
                    discs,
                    sim_box,
                    barriers: Vec::new(),
                },
                Format::Princeton(ColumnOrder::RadiusMass),
            )
        }
        _ => {
            let (discs, sim_box) = patch.build::<3>().map_err(failed)?;
            Generated::Three(edmd_core::System {
                discs,
                sim_box,
                barriers: Vec::new(),
            })
        }
    })
}

/// The ring `edmd gen ring` writes (`None` for every other kind).
pub fn ring_of(args: &GenArgs) -> Result<Option<edmd_core::Ring>> {
    if args.kind != RING {
        return Ok(None);
    }
    let omega = ring_patch(args)?.omega;
    Ok(Some(edmd_core::Ring { omega }))
}

/// The name of the sheets' kind, `edmd gen sheets`.
pub const SHEETS: &str = "sheets";

/// The rods' half-length `edmd gen sheets` gives its sheets by default, as `edmd experiment
/// sheets` does: small enough against the bag's spacing that the rods are sheets.
pub const SHEETS_RADIUS: f64 = 1e-7;

/// The water bag `edmd gen sheets` makes, from its options and their defaults (1000 sheets
/// of mass 1, half-width 1, speeds up to 1, rods of half-length 1e-7, coupling 1/N), every
/// option it does not take refused. With the defaults `2K = U` at the start: a uniform bag
/// is in virial equilibrium when `speed^2 = width coupling N`.
pub fn water_bag(args: &GenArgs) -> Result<edmd_core::setup::sheets::WaterBag> {
    let name = SHEETS;
    if args.dim() != 1 {
        return user_error(format!(
            "gen {name}: sheets live on a line (--dim 1), not --dim {}",
            args.dim()
        ));
    }
    if args.course {
        return user_error(format!(
            "gen {name}: the course format has no place for sheets (--course)"
        ));
    }
    let others = [
        ("well", args.well.is_some()),
        ("shoulder", args.shoulder.is_some()),
        ("depth", args.depth.is_some()),
        (
            "gravity (the sheets pull each other; a field does not go with them)",
            args.gravity.is_some(),
        ),
        ("shear", args.shear.is_some()),
    ];
    let used = ["n", "radius", "speed", "width", "coupling"];
    if let Some((flag, _)) = others
        .into_iter()
        .chain(given(args))
        .find(|(f, g)| *g && !used.contains(f))
    {
        return user_error(format!("gen {name}: --{flag} does not apply to sheets"));
    }
    let n = match args.n {
        None => 1000,
        Some(n) if n < 2 || n as u64 > crate::MAX_N as u64 => {
            return user_error(format!(
                "gen {name}: --n must be from 2 to {}, found {n}",
                crate::MAX_N
            ))
        }
        Some(n) => n as usize,
    };
    let positive = |flag: &str, v: f64| {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            user_error(format!(
                "gen {name}: --{flag} must be a finite number > 0, found {v}"
            ))
        }
    };
    let width = positive("width", args.width.unwrap_or(1.0))?;
    let radius = positive("radius", args.radius.unwrap_or(SHEETS_RADIUS))?;
    // The rods take up at most a tenth of the bag, so that they stand for sheets.
    if radius * n as f64 > 0.1 * width {
        return user_error(format!(
            "gen {name}: --radius {radius}: {n} rods of that length take more than a tenth of the bag's width {}; sheets need rods much shorter than their spacing (default {SHEETS_RADIUS:e})",
            2.0 * width
        ));
    }
    Ok(edmd_core::setup::sheets::WaterBag {
        n,
        width,
        speed: positive("speed", args.speed.unwrap_or(1.0))?,
        radius,
        coupling: positive("coupling", args.coupling.unwrap_or(1.0 / n as f64))?,
        seed: args.seed,
    })
}

/// `edmd gen sheets`: the water bag, between walls (its self-gravity is [`self_gravity_of`]'s).
fn make_sheets(args: &GenArgs) -> Result<Generated> {
    let (discs, sim_box) = water_bag(args)?
        .build()
        .or_else(|e| user_error(format!("gen {SHEETS}: {e}")))?;
    Ok(Generated::One(edmd_core::System {
        discs,
        sim_box,
        barriers: Vec::new(),
    }))
}

/// The self-gravity `edmd gen sheets` writes (`None` for every other kind).
pub fn self_gravity_of(args: &GenArgs) -> Result<Option<edmd_core::SelfGravity>> {
    if args.kind != SHEETS {
        return Ok(None);
    }
    let coupling = water_bag(args)?.coupling;
    Ok(Some(edmd_core::SelfGravity { coupling }))
}

/// Refuses restitution (`restitution`: some was asked for) and reaction rules (`reactions`)
/// beside sheets: the sheets pass through each other, so their collisions are elastic.
pub fn check_self_gravity_with(args: &GenArgs, restitution: bool, reactions: bool) -> Result<()> {
    if args.kind != SHEETS {
        return Ok(());
    }
    let what = match (restitution, reactions) {
        (true, _) => "--restitution",
        (_, true) => "--reaction",
        _ => return Ok(()),
    };
    user_error(format!(
        "gen {SHEETS}: {what} does not go with self-gravity (sheets pass through each other, so their collisions are elastic)"
    ))
}

/// Refuses a constant coefficient below 1 on a ring without the TC model: a cold dense patch
/// would otherwise undergo inelastic collapse (infinitely many collisions in a finite time).
/// Bridges' law, elastic at low speeds, needs none.
pub fn check_ring_restitution(r: &edmd_core::Restitution, kind: &str) -> Result<()> {
    if edmd_io::restitution::collapses_without_tc(r) {
        return user_error(format!(
            "gen {kind}: a constant restitution below 1 on a ring needs the TC model: add --restitution 'tc T' (T > 0; 'tc 0.001' for Omega 1), or take Bridges' law ('bridges VC'), or a cold dense patch collapses (infinitely many collisions in a finite time)"
        ));
    }
    Ok(())
}

/// Refuses parameters whose generation would not end in reasonable time or memory (the
/// generators themselves accept them): too many discs, a packing fraction so low that melting
/// by collisions takes hours, a dense packing of a single disc (which never collides, so the
/// compression never ends).
fn check_cost(kind: &GenKind) -> Result<()> {
    use crate::MAX_N;
    use edmd_core::setup::MIN_PACKING;
    let name = kind.name();
    let (n, packing, min_n) = match kind {
        GenKind::OneRed(k) => (k.n, None, 1),
        GenKind::Lattice(k) => (k.n, None, 1),
        GenKind::Diffusion1(k) => (k.n, None, 1),
        GenKind::Diffusion2(k) => (k.n, None, 1),
        GenKind::Dense(k) => (k.n, Some(k.packing), 2),
        GenKind::Brownian(k) => (k.n, None, 1),
        GenKind::Fluid(k) => (k.n, Some(k.packing), 1),
        GenKind::Mixture(k) => (k.n, Some(k.packing), 1),
        _ => return Ok(()),
    };
    if !(min_n..=MAX_N).contains(&n) {
        return user_error(format!(
            "gen {name}: --n must be from {min_n} to {MAX_N}, found {n}"
        ));
    }
    if let Some(p) = packing {
        if p.is_finite() && p < MIN_PACKING {
            return user_error(format!(
                "gen {name}: packing fraction {p:?} is below {MIN_PACKING}, the lowest this generator accepts"
            ));
        }
    }
    Ok(())
}

/// Applies the options that were given to the kind's parameters.
fn apply(kind: &mut GenKind, a: &GenArgs) -> Result<()> {
    let name = kind.name();
    if a.spread.is_some() && (a.size_ratio.is_some() || a.fraction_large.is_some()) {
        return user_error(format!(
            "gen {name}: --spread (polydisperse) and --size-ratio/--fraction-large (binary) exclude each other"
        ));
    }
    let mut used: Vec<&str> = Vec::new();
    let n = match a.n {
        Some(n) if n < 1 => {
            return user_error(format!("gen {name}: --n must be at least 1, got {n}"))
        }
        Some(n) => Some(n as usize),
        None => None,
    };
    macro_rules! set {
        ($flag:literal, $opt:expr, $field:expr) => {
            if let Some(v) = $opt {
                $field = v;
                used.push($flag);
            }
        };
    }
    let boundary = a.boundary.map(|b| match b {
        BoundaryArg::Periodic => Boundary::Periodic,
        BoundaryArg::Walls => Boundary::Walls,
    });
    match kind {
        GenKind::Single(k) => {
            set!("radius", a.radius, k.radius);
            set!("speed", a.speed, k.speed);
            set!("mass", a.mass, k.mass);
        }
        GenKind::HeadOn(k) => {
            set!("radius", a.radius, k.radius);
            set!("speed", a.speed, k.speed);
            set!("mass", a.mass, k.mass);
        }
        GenKind::Angled(k) => {
            set!("radius", a.radius, k.radius);
            set!("speed", a.speed, k.speed);
            set!("mass", a.mass, k.mass);
            set!("angle", a.angle, k.angle_degrees);
            set!("impact", a.impact, k.impact);
        }
        GenKind::OneRed(k) => {
            set!("n", n, k.n);
            set!("radius", a.radius, k.radius);
            set!("speed", a.speed, k.speed);
        }
        GenKind::Lattice(k) => {
            set!("n", n, k.n);
            set!("radius", a.radius, k.radius);
            set!("mass", a.mass, k.mass);
            set!("kt", a.kt, k.kt);
        }
        GenKind::Diffusion1(k) => {
            set!("n", n, k.n);
            set!("radius", a.radius, k.radius);
            set!("speed", a.speed, k.speed);
            set!("region", a.region, k.region);
        }
        GenKind::Diffusion2(k) => {
            set!("n", n, k.n);
            set!("radius", a.radius, k.radius);
            set!("mass", a.mass, k.mass);
            set!("kt", a.kt, k.kt);
        }
        GenKind::Dense(k) => {
            set!("n", n, k.n);
            set!("packing", a.packing, k.packing);
            set!("mass", a.mass, k.mass);
            set!("kt", a.kt, k.kt);
        }
        GenKind::Brownian(k) => {
            set!("n", n, k.n);
            set!("radius", a.radius, k.small_radius);
            set!("mass", a.mass, k.small_mass);
            set!("big-radius", a.big_radius, k.big_radius);
            set!("big-mass", a.big_mass, k.big_mass);
            set!("kt", a.kt, k.kt);
        }
        GenKind::Fluid(k) => {
            set!("n", n, k.n);
            set!("packing", a.packing, k.packing);
            set!("boundary", boundary, k.boundary);
            if a.gravity.is_some() {
                k.boundary = Boundary::Walls;
            }
            // Applied to the velocities after the fluid is made (`at_kt`).
            if a.kt.is_some() {
                used.push("kt");
            }
        }
        GenKind::Mixture(k) => {
            set!("n", n, k.n);
            set!("packing", a.packing, k.packing);
            set!("boundary", boundary, k.boundary);
            if a.gravity.is_some() {
                k.boundary = Boundary::Walls;
            }
            if let Some(spread) = a.spread {
                k.sizes = Sizes::Polydisperse { spread };
                used.push("spread");
            } else if a.size_ratio.is_some() || a.fraction_large.is_some() {
                let (mut size_ratio, mut fraction_large) = match k.sizes {
                    Sizes::Binary {
                        size_ratio,
                        fraction_large,
                    } => (size_ratio, fraction_large),
                    _ => (1.4, 0.5),
                };
                set!("size-ratio", a.size_ratio, size_ratio);
                set!("fraction-large", a.fraction_large, fraction_large);
                k.sizes = Sizes::Binary {
                    size_ratio,
                    fraction_large,
                };
            }
        }
    }
    if let Some((flag, _)) = given(a).into_iter().find(|(f, g)| *g && !used.contains(f)) {
        return user_error(format!("gen {name}: --{flag} does not apply to this kind"));
    }
    Ok(())
}

/// Each option a kind may or may not take, and whether it was given.
fn given(a: &GenArgs) -> Vec<(&'static str, bool)> {
    vec![
        ("n", a.n.is_some()),
        ("radius", a.radius.is_some()),
        ("speed", a.speed.is_some()),
        ("mass", a.mass.is_some()),
        ("kt", a.kt.is_some()),
        ("packing", a.packing.is_some()),
        ("boundary", a.boundary.is_some()),
        ("angle", a.angle.is_some()),
        ("impact", a.impact.is_some()),
        ("region", a.region.is_some()),
        ("big-radius", a.big_radius.is_some()),
        ("big-mass", a.big_mass.is_some()),
        ("size-ratio", a.size_ratio.is_some()),
        ("fraction-large", a.fraction_large.is_some()),
        ("spread", a.spread.is_some()),
        ("tau", a.tau.is_some()),
        ("omega", a.omega.is_some()),
        ("dispersion", a.dispersion.is_some()),
        ("height", a.height.is_some()),
        ("width", a.width.is_some()),
        ("coupling", a.coupling.is_some()),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use edmd_core::{Disc, Vector};

    fn discs(n: usize) -> Vec<Disc> {
        (0..n)
            .map(|k| Disc::new(Vector::new([k as f64, 0.0]), Vector::ZERO, 0.1))
            .collect()
    }

    fn counts(d: &[Disc], k: usize) -> Vec<usize> {
        (0..k)
            .map(|s| d.iter().filter(|x| x.species as usize == s).count())
            .collect()
    }

    /// The counts are the fractions of N rounded down, the largest remainders (the lower
    /// species among equal ones) rounded up: they add up to N and none is off by one or more.
    #[test]
    fn species_come_in_the_proportions_asked_for() {
        let mut d = discs(10);
        assign_species(&mut d, &[0.25, 0.25, 0.5], 1);
        assert_eq!(counts(&d, 3), vec![3, 2, 5]);
        let mut d = discs(1000);
        assign_species(&mut d, &[0.5, 0.5], 1);
        assert_eq!(counts(&d, 2), vec![500, 500]);
        let mut d = discs(7);
        assign_species(&mut d, &[0.1, 0.2, 0.0, 0.7], 1);
        assert_eq!(counts(&d, 4), vec![1, 1, 0, 5]);
        assert!(d
            .iter()
            .all(|x| x.colour == edmd_core::state::species_colour(x.species)));
    }

    /// Which disc is which is a shuffle by the seed: the same seed gives the same discs, another
    /// seed others, and the species are not laid out in runs.
    #[test]
    fn species_are_placed_at_random_by_the_seed() {
        let labels = |seed| {
            let mut d = discs(200);
            assign_species(&mut d, &[0.5, 0.5], seed);
            d.iter().map(|x| x.species).collect::<Vec<_>>()
        };
        assert_eq!(labels(3), labels(3));
        assert_ne!(labels(3), labels(4));
        let a = labels(3);
        let changes = a.windows(2).filter(|w| w[0] != w[1]).count();
        // About 100 for independent labels (sd about 7).
        assert!((70..=130).contains(&changes), "{changes}");
    }
}
