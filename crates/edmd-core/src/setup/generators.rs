//! Initial configurations by name: the data sets of the Princeton CollisionSystem assignment
//! and equilibrium fluids and mixtures.
//!
//! The Princeton kinds live in the unit box with walls, with radii (0.0025 to 0.05), speeds
//! (about 0.01) and colours like the published data files: red `[200, 0, 0]` for the disc to
//! watch, blue `[0, 0, 200]` and green `[0, 200, 0]` for the others, black where the assignment
//! names no colour. Temperatures are in the same units: `kT = 5e-5` gives discs of mass 1 a
//! root-mean-square speed of 0.01 (`m <v^2> / 2 = kT` in 2D). `fluid` and `mixture` use
//! diameter 1, mass 1 and `kT = 1` in a box sized from `N` and the packing fraction.
//!
//! Every random choice comes from the seed (`Pcg64Mcg`): the same kind and seed give the same
//! system, bit for bit. Kinds without random choices (`head-on`, `angled`) ignore the seed.
//!
//! ```
//! use edmd_core::setup::generators::{generate, GenKind, OneRed};
//! let system = generate(&GenKind::OneRed(OneRed { n: 50, ..OneRed::default() }), 7).unwrap();
//! assert_eq!(system.discs.len(), 51);
//! assert_eq!(system.discs[0].colour, [200, 0, 0]);
//! ```

use std::f64::consts::PI;

use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;

use super::compress::compress;
use super::fluid::{run_collisions, shuffle, Fluid, Mixture, Recipe};
use super::lattice::{thermal_velocities, CLOSE_PACKING};
use super::placement::{random_positions, Region};
use super::MIN_PACKING;
use crate::error::Error;
use crate::math::Vector;
use crate::simulation::{Options, Simulation};
use crate::state::{Colour, Disc, SimBox, System};

/// The disc to watch.
pub const RED: Colour = [200, 0, 0];
/// The crowd.
pub const BLUE: Colour = [0, 0, 200];
/// The second species of `diffusion2`.
pub const GREEN: Colour = [0, 200, 0];

/// `kT` that gives discs of mass 1 a root-mean-square speed of 0.01.
pub const PRINCETON_KT: f64 = 5e-5;

/// Packing at which `dense` places its discs at random before compressing them.
const DENSE_START: f64 = 0.3;

/// Position of the partition of `diffusion2`: the vertical line `x = 0.5`. To keep the halves
/// apart, add `Barrier::solid(0, DIFFUSION2_PARTITION)` to the system.
pub const DIFFUSION2_PARTITION: f64 = 0.5;

/// `single`: one disc in motion, at a random position in a random direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Single {
    /// Radius, in `(0, 0.5)`. Default 0.01.
    pub radius: f64,
    /// Speed, `> 0`. Default 0.01.
    pub speed: f64,
    /// Mass, `> 0`. Default 1.
    pub mass: f64,
}

impl Default for Single {
    fn default() -> Self {
        Single {
            radius: 0.01,
            speed: 0.01,
            mass: 1.0,
        }
    }
}

/// `head-on`: two equal discs on the line `y = 0.5`, red at `x = 0.25` moving right and blue at
/// `x = 0.75` moving left; they meet at `t = (0.5 - 2 r) / (2 speed)`. No random choices.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeadOn {
    /// Radius of both, in `(0, 0.25)`. Default 0.02.
    pub radius: f64,
    /// Speed of both, `> 0`. Default 0.01.
    pub speed: f64,
    /// Mass of both, `> 0`. Default 1.
    pub mass: f64,
}

impl Default for HeadOn {
    fn default() -> Self {
        HeadOn {
            radius: 0.02,
            speed: 0.01,
            mass: 1.0,
        }
    }
}

/// `angled`: a blue disc at rest in the centre and a red one coming at it along the direction
/// `angle_degrees` from the x axis, from 0.25 away and off-centre (to its left) by `impact`
/// contact distances. The blue disc leaves along the line of centres, `asin(impact)` to the
/// right of the line of approach, and (equal masses) the red one at a right angle to it. No
/// random choices.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Angled {
    /// Radius of both, in `(0, 0.08]`. Default 0.02.
    pub radius: f64,
    /// Speed of the moving disc, `> 0`. Default 0.01.
    pub speed: f64,
    /// Mass of both, `> 0`. Default 1.
    pub mass: f64,
    /// Direction of approach, degrees from the x axis. Default 30.
    pub angle_degrees: f64,
    /// Impact parameter over the contact distance `2 r`, in `[0, 1)`. Default 0.5.
    pub impact: f64,
}

impl Default for Angled {
    fn default() -> Self {
        Angled {
            radius: 0.02,
            speed: 0.01,
            mass: 1.0,
            angle_degrees: 30.0,
            impact: 0.5,
        }
    }
}

/// `one-red`: a red disc in motion (disc 0, random position and direction) among `n` blue discs
/// at rest at random positions, all of mass 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OneRed {
    /// Number of blue discs. Default 100.
    pub n: usize,
    /// Radius of every disc. Default 0.01.
    pub radius: f64,
    /// Speed of the red disc, `> 0`. Default 0.01.
    pub speed: f64,
}

impl Default for OneRed {
    fn default() -> Self {
        OneRed {
            n: 100,
            radius: 0.01,
            speed: 0.01,
        }
    }
}

/// `lattice`: `n` black discs on a square lattice (`k = ceil(sqrt n)` sites a side, spacing
/// `1 / k`, filled row by row), all at the speed `sqrt(2 kT / m)` in random directions, so that
/// `sum m v^2 / 2 = N kT` and the total momentum is zero: directions come in opposite pairs
/// (and one triple at 120 degrees if `n` is odd), dealt to the sites in random order.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lattice {
    /// Number of discs, at least 2 (one disc cannot move with zero momentum). Default 100.
    pub n: usize,
    /// Radius, at most half the spacing. Default 0.01.
    pub radius: f64,
    /// Mass. Default 1.
    pub mass: f64,
    /// Temperature `kT`, `> 0`. Default [`PRINCETON_KT`] (speed 0.01 at mass 1).
    pub kt: f64,
}

impl Default for Lattice {
    fn default() -> Self {
        Lattice {
            n: 100,
            radius: 0.01,
            mass: 1.0,
            kt: PRINCETON_KT,
        }
    }
}

/// `diffusion1`: `n` tiny red discs of equal size (mass 1) at random positions in a square of
/// side `region` in the centre of the box, all at the same speed in random directions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Diffusion1 {
    /// Number of discs. Default 500.
    pub n: usize,
    /// Radius. Default 0.0025.
    pub radius: f64,
    /// Speed, `> 0`. Default 0.01.
    pub speed: f64,
    /// Side of the central square, in `(0, 1]`; the discs may cover at most 40% of it.
    /// Default 0.2.
    pub region: f64,
}

impl Default for Diffusion1 {
    fn default() -> Self {
        Diffusion1 {
            n: 500,
            radius: 0.0025,
            speed: 0.01,
            region: 0.2,
        }
    }
}

/// `diffusion2`: `n` blue discs (species 0) in the left half and `n` green ones (species 1) in
/// the right half, each half thermalised on its own.
///
/// Each half is made as its own walled box `0.5 x 1`: random positions, Maxwell-Boltzmann
/// velocities at `kT` (zero momentum, kinetic energy exactly `n kT`), then the engine runs it
/// for `collisions_per_disc` collisions per disc. The right half is then moved over by 0.5.
/// The partition that kept them apart is at `x = 0.5` ([`DIFFUSION2_PARTITION`]); it is not in
/// the returned system (the halves mix), add `Barrier::solid(0, 0.5)` to keep it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Diffusion2 {
    /// Discs per side. Default 200.
    pub n: usize,
    /// Radius of every disc. Default 0.005.
    pub radius: f64,
    /// Mass of every disc. Default 1.
    pub mass: f64,
    /// Temperature `kT`, `> 0`. Default [`PRINCETON_KT`].
    pub kt: f64,
    /// Collisions per disc run in each half. Default 20.
    pub collisions_per_disc: u32,
}

impl Default for Diffusion2 {
    fn default() -> Self {
        Diffusion2 {
            n: 200,
            radius: 0.005,
            mass: 1.0,
            kt: PRINCETON_KT,
            collisions_per_disc: 20,
        }
    }
}

/// `dense`: `n` big black discs filling the unit box at a high packing fraction, with little
/// room to move.
///
/// The discs are placed at random in a larger walled box (at packing 0.3), get
/// Maxwell-Boltzmann velocities at `kT`, are compressed into the unit box in stages that the
/// engine relaxes (as for a [`Mixture`]; see [`super::compress`]), and are run for
/// `collisions_per_disc` collisions per disc. Up to a packing of about 0.70 the result is a
/// dense liquid; above, equal discs order as they should (hexatic, then solid). Near jamming
/// the compression gives up with an error: for 100 discs it stopped between 0.78 and 0.81.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dense {
    /// Number of discs. Default 100.
    pub n: usize,
    /// Packing fraction `n pi r^2` (the box has area 1), which sets the radius `r`, in
    /// `(0, 0.9069)`. Default 0.65 (radius 0.0455 for 100 discs).
    pub packing: f64,
    /// Mass. Default 1.
    pub mass: f64,
    /// Temperature `kT`, `> 0`. Default [`PRINCETON_KT`].
    pub kt: f64,
    /// Collisions per disc run after the lattice start. Default 20.
    pub collisions_per_disc: u32,
}

impl Default for Dense {
    fn default() -> Self {
        Dense {
            n: 100,
            packing: 0.65,
            mass: 1.0,
            kt: PRINCETON_KT,
            collisions_per_disc: 20,
        }
    }
}

/// `brownian`: one big heavy red disc (disc 0, species 1) in the centre among `n` small blue ones
/// (species 0) at random positions, all with Maxwell-Boltzmann velocities at `kT` (zero total momentum, kinetic
/// energy exactly `(n + 1) kT`; the big disc moves `sqrt(big_mass / small_mass)` times slower).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Brownian {
    /// Number of small discs. Default 1000.
    pub n: usize,
    /// Radius of the small discs. Default 0.0025.
    pub small_radius: f64,
    /// Mass of the small discs. Default 1.
    pub small_mass: f64,
    /// Radius of the big disc. Default 0.05.
    pub big_radius: f64,
    /// Mass of the big disc. Default 100.
    pub big_mass: f64,
    /// Temperature `kT`, `> 0`. Default [`PRINCETON_KT`].
    pub kt: f64,
}

impl Default for Brownian {
    fn default() -> Self {
        Brownian {
            n: 1000,
            small_radius: 0.0025,
            small_mass: 1.0,
            big_radius: 0.05,
            big_mass: 100.0,
            kt: PRINCETON_KT,
        }
    }
}

/// A configuration generator with its parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GenKind {
    /// `single`: one disc in motion.
    Single(Single),
    /// `head-on`: two discs colliding head on.
    HeadOn(HeadOn),
    /// `angled`: two discs colliding at an angle, one at rest.
    Angled(Angled),
    /// `one-red`: one red disc in motion among blue discs at rest.
    OneRed(OneRed),
    /// `lattice`: discs on a lattice, equal speeds, zero momentum, set temperature.
    Lattice(Lattice),
    /// `diffusion1`: tiny discs near the centre.
    Diffusion1(Diffusion1),
    /// `diffusion2`: blue on the left, green on the right, thermalised apart.
    Diffusion2(Diffusion2),
    /// `dense`: big discs with little room to move.
    Dense(Dense),
    /// `brownian`: one big heavy red disc among small blue ones.
    Brownian(Brownian),
    /// `fluid`: an equilibrium fluid of equal discs at a packing fraction.
    Fluid(Fluid),
    /// `mixture`: a fluid mixture of discs of different sizes at a packing fraction.
    Mixture(Mixture),
}

impl GenKind {
    /// The kinds' names, as the Princeton assignment lists them (then `fluid`, `mixture`).
    pub const NAMES: [&'static str; 11] = [
        "single",
        "head-on",
        "angled",
        "one-red",
        "lattice",
        "diffusion1",
        "diffusion2",
        "dense",
        "brownian",
        "fluid",
        "mixture",
    ];

    /// The kind's name (one of [`Self::NAMES`]).
    pub fn name(&self) -> &'static str {
        let k = match self {
            GenKind::Single(_) => 0,
            GenKind::HeadOn(_) => 1,
            GenKind::Angled(_) => 2,
            GenKind::OneRed(_) => 3,
            GenKind::Lattice(_) => 4,
            GenKind::Diffusion1(_) => 5,
            GenKind::Diffusion2(_) => 6,
            GenKind::Dense(_) => 7,
            GenKind::Brownian(_) => 8,
            GenKind::Fluid(_) => 9,
            GenKind::Mixture(_) => 10,
        };
        Self::NAMES[k]
    }

    /// The kind called `name`, with its default parameters.
    pub fn from_name(name: &str) -> Result<GenKind, Error> {
        Ok(match name {
            "single" => GenKind::Single(Single::default()),
            "head-on" => GenKind::HeadOn(HeadOn::default()),
            "angled" => GenKind::Angled(Angled::default()),
            "one-red" => GenKind::OneRed(OneRed::default()),
            "lattice" => GenKind::Lattice(Lattice::default()),
            "diffusion1" => GenKind::Diffusion1(Diffusion1::default()),
            "diffusion2" => GenKind::Diffusion2(Diffusion2::default()),
            "dense" => GenKind::Dense(Dense::default()),
            "brownian" => GenKind::Brownian(Brownian::default()),
            "fluid" => GenKind::Fluid(Fluid::default()),
            "mixture" => GenKind::Mixture(Mixture::default()),
            _ => {
                return Err(Error::Invalid(format!(
                    "unknown generator {name:?}; the generators are {}",
                    Self::NAMES.join(", ")
                )))
            }
        })
    }
}

/// Builds the system `kind` describes; every random choice comes from `seed`.
///
/// Errors are [`Error::Invalid`] with a message naming the kind, what is wrong and what is
/// allowed.
pub fn generate(kind: &GenKind, seed: u64) -> Result<System, Error> {
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    let name = kind.name();
    let discs = match kind {
        GenKind::Fluid(f) => return f.generate(seed),
        GenKind::Mixture(m) => return m.generate(seed),
        GenKind::Single(p) => single(p, &mut rng)?,
        GenKind::HeadOn(p) => head_on(p)?,
        GenKind::Angled(p) => angled(p)?,
        GenKind::OneRed(p) => one_red(p, &mut rng)?,
        GenKind::Lattice(p) => lattice(p, &mut rng)?,
        GenKind::Diffusion1(p) => diffusion1(p, &mut rng)?,
        GenKind::Diffusion2(p) => diffusion2(p, &mut rng)?,
        GenKind::Dense(p) => dense(p, &mut rng)?,
        GenKind::Brownian(p) => brownian(p, &mut rng)?,
    };
    let sim_box = SimBox::unit();
    // The checks above should make this impossible; it guards the engine's invariants.
    Simulation::new(&discs, sim_box, Options::default())
        .map_err(|e| Error::Invalid(format!("{name}: the generated system is invalid: {e}")))?;
    Ok(System {
        discs,
        sim_box,
        barriers: Vec::new(),
    })
}

/// `Err` unless `x` is finite and `> 0`.
fn positive(kind: &str, what: &str, x: f64) -> Result<(), Error> {
    if x.is_finite() && x > 0.0 {
        Ok(())
    } else {
        Err(Error::Invalid(format!(
            "{kind}: {what} {x} is not a finite positive number"
        )))
    }
}

/// `Err` unless `0 < r < max`.
fn radius_below(kind: &str, what: &str, r: f64, max: f64) -> Result<(), Error> {
    positive(kind, what, r)?;
    if r < max {
        Ok(())
    } else {
        Err(Error::Invalid(format!(
            "{kind}: {what} {r} is too large; it must be below {max}"
        )))
    }
}

/// `Err` unless `n >= min`.
fn at_least(kind: &str, n: usize, min: usize) -> Result<(), Error> {
    if n >= min {
        Ok(())
    } else {
        Err(Error::Invalid(format!(
            "{kind}: needs at least {min} discs, got {n}"
        )))
    }
}

/// A disc with every field given.
fn disc(pos: Vector, vel: Vector, radius: f64, mass: f64, colour: Colour, species: u16) -> Disc {
    Disc {
        pos,
        vel,
        mass,
        radius,
        colour,
        species,
    }
}

/// A velocity of the given speed in a uniformly random direction.
fn random_direction(speed: f64, rng: &mut impl Rng) -> Vector {
    let theta = 2.0 * PI * rng.random::<f64>();
    Vector::new([speed * theta.cos(), speed * theta.sin()])
}

fn single(p: &Single, rng: &mut impl Rng) -> Result<Vec<Disc>, Error> {
    radius_below("single", "radius", p.radius, 0.5)?;
    positive("single", "speed", p.speed)?;
    positive("single", "mass", p.mass)?;
    let r = p.radius;
    let pos = Vector::new([rng.random_range(r..1.0 - r), rng.random_range(r..1.0 - r)]);
    let vel = random_direction(p.speed, rng);
    Ok(vec![disc(pos, vel, r, p.mass, RED, 0)])
}

fn head_on(p: &HeadOn) -> Result<Vec<Disc>, Error> {
    radius_below("head-on", "radius", p.radius, 0.25)?;
    positive("head-on", "speed", p.speed)?;
    positive("head-on", "mass", p.mass)?;
    let (r, v, m) = (p.radius, p.speed, p.mass);
    Ok(vec![
        disc(
            Vector::new([0.25, 0.5]),
            Vector::new([v, 0.0]),
            r,
            m,
            RED,
            0,
        ),
        disc(
            Vector::new([0.75, 0.5]),
            Vector::new([-v, 0.0]),
            r,
            m,
            BLUE,
            0,
        ),
    ])
}

fn angled(p: &Angled) -> Result<Vec<Disc>, Error> {
    positive("angled", "radius", p.radius)?;
    if p.radius > 0.08 {
        return Err(Error::Invalid(format!(
            "angled: radius {} is too large; it must be at most 0.08",
            p.radius
        )));
    }
    positive("angled", "speed", p.speed)?;
    positive("angled", "mass", p.mass)?;
    if !(p.angle_degrees.is_finite()) {
        return Err(Error::Invalid(format!(
            "angled: angle {} is not a finite number of degrees",
            p.angle_degrees
        )));
    }
    if !(0.0..1.0).contains(&p.impact) {
        return Err(Error::Invalid(format!(
            "angled: impact parameter {} is outside [0, 1) (in contact distances; 1 only grazes)",
            p.impact
        )));
    }
    let (r, m) = (p.radius, p.mass);
    let a = p.angle_degrees.to_radians();
    let along = Vector::new([a.cos(), a.sin()]);
    let across = Vector::new([-a.sin(), a.cos()]);
    let centre = Vector::new([0.5, 0.5]);
    let start = centre - along * 0.25 + across * (2.0 * r * p.impact);
    Ok(vec![
        disc(start, along * p.speed, r, m, RED, 0),
        disc(centre, Vector::ZERO, r, m, BLUE, 0),
    ])
}

fn one_red(p: &OneRed, rng: &mut impl Rng) -> Result<Vec<Disc>, Error> {
    at_least("one-red", p.n, 1)?;
    radius_below("one-red", "radius", p.radius, 0.5)?;
    positive("one-red", "speed", p.speed)?;
    let r = p.radius;
    let radii = vec![r; p.n + 1];
    let pos = random_positions(
        "one-red",
        &radii,
        Region::of(&SimBox::unit()),
        &[],
        &SimBox::unit(),
        rng,
    )?;
    let vel = random_direction(p.speed, rng);
    Ok(pos
        .iter()
        .enumerate()
        .map(|(k, &x)| {
            if k == 0 {
                disc(x, vel, r, 1.0, RED, 0)
            } else {
                disc(x, Vector::ZERO, r, 1.0, BLUE, 0)
            }
        })
        .collect())
}

fn lattice(p: &Lattice, rng: &mut impl Rng) -> Result<Vec<Disc>, Error> {
    at_least("lattice", p.n, 2)?;
    positive("lattice", "mass", p.mass)?;
    positive("lattice", "kT", p.kt)?;
    let k = (p.n as f64).sqrt().ceil() as usize;
    let k = if k * k < p.n { k + 1 } else { k };
    let spacing = 1.0 / k as f64;
    positive("lattice", "radius", p.radius)?;
    if p.radius > 0.5 * spacing {
        return Err(Error::Invalid(format!(
            "lattice: radius {} does not fit {} discs on a {k} x {k} lattice in the unit box; \
             it must be at most half the spacing, {}",
            p.radius,
            p.n,
            0.5 * spacing
        )));
    }
    let speed = (2.0 * p.kt / p.mass).sqrt();
    let mut vel = Vec::with_capacity(p.n);
    if p.n % 2 == 1 {
        let theta = 2.0 * PI * rng.random::<f64>();
        for j in 0..3 {
            let t = theta + 2.0 * PI * j as f64 / 3.0;
            vel.push(Vector::new([speed * t.cos(), speed * t.sin()]));
        }
    }
    while vel.len() < p.n {
        let v = random_direction(speed, rng);
        vel.push(v);
        vel.push(-v);
    }
    shuffle(&mut vel, rng);
    Ok((0..p.n)
        .map(|s| {
            let pos = Vector::new([
                (0.5 + (s % k) as f64) * spacing,
                (0.5 + (s / k) as f64) * spacing,
            ]);
            disc(pos, vel[s], p.radius, p.mass, [0, 0, 0], 0)
        })
        .collect())
}

fn diffusion1(p: &Diffusion1, rng: &mut impl Rng) -> Result<Vec<Disc>, Error> {
    at_least("diffusion1", p.n, 1)?;
    positive("diffusion1", "radius", p.radius)?;
    positive("diffusion1", "speed", p.speed)?;
    if !(p.region > 0.0 && p.region <= 1.0) {
        return Err(Error::Invalid(format!(
            "diffusion1: region side {} is outside (0, 1]",
            p.region
        )));
    }
    let (lo, hi) = (0.5 - 0.5 * p.region, 0.5 + 0.5 * p.region);
    let region = Region {
        lo: [lo; 2],
        hi: [hi; 2],
    };
    let radii = vec![p.radius; p.n];
    let pos = random_positions("diffusion1", &radii, region, &[], &SimBox::unit(), rng)?;
    Ok(pos
        .into_iter()
        .map(|x| disc(x, random_direction(p.speed, rng), p.radius, 1.0, RED, 0))
        .collect())
}

fn diffusion2(p: &Diffusion2, rng: &mut impl Rng) -> Result<Vec<Disc>, Error> {
    let kind = "diffusion2";
    at_least(kind, p.n, 1)?;
    radius_below(kind, "radius", p.radius, 0.25)?;
    positive(kind, "mass", p.mass)?;
    positive(kind, "kT", p.kt)?;
    let half = SimBox::walls([DIFFUSION2_PARTITION, 1.0]);
    let mut all = Vec::with_capacity(2 * p.n);
    for (species, colour) in [(0u16, BLUE), (1, GREEN)] {
        let radii = vec![p.radius; p.n];
        let pos = random_positions(kind, &radii, Region::of(&half), &[], &half, rng)?;
        let mut discs: Vec<Disc> = pos
            .into_iter()
            .map(|x| disc(x, Vector::ZERO, p.radius, p.mass, colour, species))
            .collect();
        thermal_velocities(&mut discs, p.kt, rng);
        let discs = run_for(kind, discs, half, p.collisions_per_disc)?;
        let shift = DIFFUSION2_PARTITION * species as f64;
        all.extend(discs.into_iter().map(|mut d| {
            d.pos[0] += shift;
            d
        }));
    }
    Ok(all)
}

fn dense(p: &Dense, rng: &mut impl Rng) -> Result<Vec<Disc>, Error> {
    let kind = "dense";
    // One disc never collides, so compressing it (and equilibrating it) never ends.
    at_least(kind, p.n, 2)?;
    positive(kind, "mass", p.mass)?;
    positive(kind, "kT", p.kt)?;
    if !(p.packing >= MIN_PACKING && p.packing < CLOSE_PACKING) {
        return Err(Error::Invalid(format!(
            "dense: packing fraction {} is outside [{MIN_PACKING}, {CLOSE_PACKING:.4})",
            p.packing
        )));
    }
    let r = (p.packing / (p.n as f64 * PI)).sqrt();
    if r >= 0.5 {
        return Err(Error::Invalid(format!(
            "dense: at packing {} the radius of {} disc(s) would be {r:.4}, too large for the unit box",
            p.packing, p.n
        )));
    }
    // Random positions in a box large enough for random placement, compressed to the unit box.
    let side = (p.packing / p.packing.min(DENSE_START)).sqrt();
    let start_box = SimBox::walls([side, side]);
    let radii = vec![r; p.n];
    let pos = random_positions(kind, &radii, Region::of(&start_box), &[], &start_box, rng)?;
    let mut discs: Vec<Disc> = pos
        .into_iter()
        .map(|x| disc(x, Vector::ZERO, r, p.mass, [0, 0, 0], 0))
        .collect();
    thermal_velocities(&mut discs, p.kt, rng);
    if side > 1.0 {
        let sim = Simulation::new(&discs, start_box, Options::default())
            .map_err(|e| Error::Invalid(format!("{kind}: the generated system is invalid: {e}")))?;
        let max_stages = Recipe::default().max_stages;
        let c = compress(sim, [1.0, 1.0], max_stages).map_err(|(reached, k)| {
            Error::Invalid(format!(
                "dense: compression reached packing {:.4} but not {} within {k} stages: too near \
                 jamming for {} equal discs in the unit box",
                reached, p.packing, p.n
            ))
        })?;
        discs = c.sim.discs();
    }
    run_for(kind, discs, SimBox::unit(), p.collisions_per_disc)
}

fn brownian(p: &Brownian, rng: &mut impl Rng) -> Result<Vec<Disc>, Error> {
    let kind = "brownian";
    at_least(kind, p.n, 1)?;
    radius_below(kind, "small radius", p.small_radius, 0.5)?;
    radius_below(kind, "big radius", p.big_radius, 0.5)?;
    positive(kind, "small mass", p.small_mass)?;
    positive(kind, "big mass", p.big_mass)?;
    positive(kind, "kT", p.kt)?;
    let big = disc(
        Vector::new([0.5, 0.5]),
        Vector::ZERO,
        p.big_radius,
        p.big_mass,
        RED,
        1,
    );
    let radii = vec![p.small_radius; p.n];
    let unit = SimBox::unit();
    let pos = random_positions(kind, &radii, Region::of(&unit), &[big], &unit, rng)?;
    let mut discs = vec![big];
    discs.extend(
        pos.into_iter()
            .map(|x| disc(x, Vector::ZERO, p.small_radius, p.small_mass, BLUE, 0)),
    );
    thermal_velocities(&mut discs, p.kt, rng);
    Ok(discs)
}

/// Runs `discs` in `sim_box` for `collisions_per_disc` collisions per disc and returns them.
/// Fewer than two discs never collide and are returned as they are.
fn run_for(
    kind: &str,
    discs: Vec<Disc>,
    sim_box: SimBox,
    collisions_per_disc: u32,
) -> Result<Vec<Disc>, Error> {
    if discs.len() < 2 || collisions_per_disc == 0 {
        return Ok(discs);
    }
    let mut sim = Simulation::new(&discs, sim_box, Options::default())
        .map_err(|e| Error::Invalid(format!("{kind}: the generated system is invalid: {e}")))?;
    let target = (collisions_per_disc as u64 * discs.len() as u64).div_ceil(2);
    // Dilute systems have many wall and cell events per collision; ten thousand per collision
    // means that the discs hardly ever meet.
    if !run_collisions(&mut sim, target, target.saturating_mul(10_000)) {
        return Err(Error::Invalid(format!(
            "{kind}: the discs hardly ever collide ({} collisions in {} events, {target} wanted); \
             use more or bigger discs, or fewer collisions per disc",
            sim.stats().disc_disc,
            sim.stats().disc_disc + sim.stats().wall + sim.stats().cell_crossing
        )));
    }
    Ok(sim.discs())
}
