//! Stepped pair potentials in the event loop: each pair's shell, the neighbour lists, the
//! predictions of step events, and what happens at a step.
//!
//! # Neighbour lists
//! A pair reaches as far as its outermost step, so cells wide enough for the grid's `3^D`
//! scan would hand each prediction several times the candidates hard cores have (66 against
//! 16 for the square-well fluid of BENCHMARKS.md). A disc's candidates are instead its
//! neighbour list: every disc whose list centre (where its list was last made) is within the
//! reach plus a skin of its own centre, and every disc it shares a shell with. A disc's list is
//! made again ([`Simulation::relist`]) when the disc has moved half the skin from its centre, an
//! event of its own ([`leash_time`]), so two discs that can come within reach before either list
//! is made again are in both lists. The grid files each disc by its centre, which moves only
//! then, so stepped runs have no cell crossings; the grid serves to make lists. Lists are kept
//! in order and symmetric (each in its disc's row of one array, `lists.rs`); a list made again
//! changes only the lists of the discs that come or go, and a pair inside a step stays listed
//! whatever its centres.
//!
//! # The shell of a pair is a state, never a distance
//! A pair's shell (how many of its steps it is inside, 0 outside them all) is kept for every
//! pair inside at least one step, in the per-disc lists [`Steps::shells`], and changes only at
//! the pair's step events. Predictions read the shell from there: the next event of a pair in
//! shell `s` is its arrival at the inner edge of the shell (step `s`, or the hard core in the
//! innermost shell) if it is approaching and reaches it, otherwise its departure through the
//! outer edge (step `s - 1`). No decision depends on whether a computed distance is a little
//! inside or outside a step, so rounding cannot put a pair in the wrong shell: a pair that has
//! just crossed inward but sits, by rounding, a hair outside the step is still in its new
//! shell, and its next event is computed from that shell's edges (a departure from a shell
//! found a hair outside it and receding is at once, and one approaching is at the far side).
//! At an event, which of the two edges was met is decided by which is nearer: they are a
//! whole step apart, far beyond rounding. `Simulation::shell_mismatches` checks the labels
//! against the distances, with that rounding allowance, and the tests call it along runs.
//!
//! # Energy
//! At a step, the pair's velocities change along the line of centres only, so momentum is
//! conserved; the normal relative speed changes so that the kinetic energy changes by minus
//! the step's energy when the pair crosses (`v_n'^2 = v_n^2 - 2 dU / mu`), and the pair bounces
//! (`v_n' = -v_n`) when it has not the energy to cross. Kinetic plus potential energy is
//! conserved to rounding.

use crate::cells::grid::CellCoord;
use crate::cells::CellGrid;
use crate::events::{EventKind, EventRecord, StepHit};
use crate::math::{select, Vector};
use crate::state::{Disc, Potential, SimBox};

use super::lists::{find, Entry, Lists};
use super::Simulation;

/// The skin of the neighbour lists, in largest diameters: a disc's list holds the discs
/// within the pair's reach plus this, and is made again when the disc has moved half of it.
/// A thinner skin gives shorter lists and more of them: for the square-well fluid of
/// BENCHMARKS.md, 0.5 to 0.7 ran fastest of 0.2 to 1 (0.2 a quarter slower at N = 10^4, 1 a
/// tenth), and 0.5 keeps the lists in the smallest allocations.
pub(super) const SKIN: f64 = 0.5;

/// One pair of species' steps, outermost first, as the loop reads them.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Table {
    /// Step radii, decreasing.
    pub(super) r: Vec<f64>,
    /// Energy change on crossing each step inward.
    pub(super) e: Vec<f64>,
}

/// The stepped potential of a simulation, its neighbour lists and the shells of its pairs.
#[derive(Clone, Debug)]
pub(super) struct Steps<const D: usize> {
    /// The potential as given.
    pub(super) potential: Potential,
    /// Species are below this.
    species: usize,
    /// Per pair of species (`a * species + b`), its table in `tables` plus one (0: none).
    index: Vec<u32>,
    tables: Vec<Table>,
    /// Per pair of species, the outermost step's radius (0 without steps): where a pair
    /// outside every step has its next event, or its hard core if that is farther.
    outer: Vec<f64>,
    /// Per disc, its neighbours in increasing order, each with the pair's shell (0 outside
    /// every step): every disc whose list centre is within [`Self::list_radius`] of its own,
    /// and every disc it shares a shell above 0 with. Both discs of a pair list it.
    pub(super) near: Lists,
    /// Per disc, where its list was made (inside the box on periodic axes). The grid files
    /// each disc by this, not by where it is.
    pub(super) centre: Vec<Vector<D>>,
    /// A disc's list is made again when it is this far from its centre: half the skin.
    pub(super) leash: f64,
    /// Centres nearer than this are neighbours: the reach of a pair (the outermost step or
    /// the largest contact distance) and the skin, with an allowance for rounding.
    pub(super) list_radius: f64,
    /// Box lengths, and half of them on periodic axes (`+inf` on walled ones), for the
    /// nearest image of a neighbour.
    pub(super) lengths: [f64; D],
    pub(super) half: [f64; D],
    /// Spare lists, so that making a list again allocates nothing: the spheres found, the
    /// old list and the new one.
    spare: (Vec<u32>, Vec<Entry>, Vec<Entry>),
    /// In 3D, the centres filed by cell as the grid files them (`centres.rs`), for the
    /// x86-64-v3 list-making.
    pub(super) filed: super::centres::Centres,
    /// The edges of every shell when one table serves every pair (one species with steps),
    /// for the x86-64-v3 scan (`steps_x86.rs`), which reads them per neighbour by shell.
    pub(super) uniform: Option<Edges>,
}

/// The edges of the shells of one table, one row per shell, for the x86-64-v3 scan
/// (`steps_x86.rs`), which reads four neighbours' rows with four loads and no branch.
#[derive(Clone, Debug)]
#[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
pub(super) struct Edges {
    /// Per shell `s`: `[inner, outer, outside, 0]`. The pair's next edge from inside the
    /// shell is the larger of `inner` and its contact distance: `inner` is the outermost step
    /// for shell 0 (the core if that is farther, as [`scan_stepped`] takes it), the step
    /// `r[s]` for the shells between (always beyond the core: [`Steps::new`] refuses a step
    /// inside it), and 0 for the innermost, whose inner edge is the core. `outer` is the
    /// step `r[s - 1]` the pair leaves by (0 for shell 0, which has none), and `outside` is
    /// `-0.0` for shell 0 and `0.0` for the others: a sign that selects, per lane, the pairs
    /// outside every step, which have no departure.
    pub(super) rows: Vec<[f64; 4]>,
}

/// The shell of the pair (`list` is one disc's list, `j` the other disc).
#[inline(always)]
pub(super) fn shell_in(list: &[Entry], j: u32) -> u8 {
    find(list, j).map_or(0, |k| list[k].1)
}

/// Time from now until a pair inside distance `r` (relative position `dr`, velocity `dv`)
/// reaches it moving outward: the larger root of `|dr + dv t| = r`, in the form that keeps
/// its digits for either sign of `dr . dv`. A pair found outside (by rounding) and receding
/// leaves at once; `+inf` if it does not move. (Also a disc's departure from its list centre.)
#[inline(always)]
pub(super) fn exit_time<const D: usize>(dr: Vector<D>, dv: Vector<D>, r: f64) -> f64 {
    let a = dv.norm2();
    if a == 0.0 {
        return f64::INFINITY;
    }
    let b = dr.dot(dv);
    let c = dr.norm2() - r * r;
    if c >= 0.0 && b > 0.0 {
        return 0.0;
    }
    let root = (b * b - a * c).max(0.0).sqrt();
    if b > 0.0 {
        -c / (b + root)
    } else {
        (root - b) / a
    }
}

impl<const D: usize> Steps<D> {
    /// The tables of `potential` for these discs in this box; errors if a step lies inside
    /// the hard core of discs it applies to or names a species no disc has. The lists are
    /// empty until [`Simulation::make_lists`] makes them.
    pub(super) fn new(
        potential: &Potential,
        discs: &[Disc<D>],
        sim_box: &SimBox<D>,
    ) -> Result<Self, crate::Error> {
        potential.validate()?;
        // The tables are per pair of the discs' species: a species beyond the potential's
        // range would make them quadratically large (65 535 species, 34 GB).
        if let Some((k, d)) = discs
            .iter()
            .enumerate()
            .find(|(_, d)| d.species >= crate::state::MAX_POTENTIAL_SPECIES)
        {
            return Err(crate::Error::BadPotential(format!(
                "disc {k} is of species {}: with a stepped potential species go from 0 to {}",
                d.species,
                crate::state::MAX_POTENTIAL_SPECIES - 1
            )));
        }
        let species = discs
            .iter()
            .map(|d| d.species as usize + 1)
            .max()
            .unwrap_or(1);
        let mut largest = vec![0.0f64; species];
        let mut lightest = vec![f64::INFINITY; species];
        for d in discs {
            let l = &mut largest[d.species as usize];
            *l = l.max(d.radius);
            let m = &mut lightest[d.species as usize];
            *m = m.min(d.mass);
        }
        let mut index = vec![0u32; species * species];
        let mut outer = vec![0.0f64; species * species];
        let mut tables = Vec::new();
        let mut range = 0.0f64;
        for p in &potential.pairs {
            let (a, b) = (p.species.0 as usize, p.species.1 as usize);
            if a >= species || b >= species {
                return Err(crate::Error::BadPotential(format!(
                    "species {} {}: no disc is of species {}",
                    p.species.0,
                    p.species.1,
                    if a >= species { a } else { b }
                )));
            }
            if p.steps.is_empty() {
                continue;
            }
            if let Some(why) = crate::state::steps_too_large(&p.steps, lightest[a].min(lightest[b]))
            {
                return Err(crate::Error::BadPotential(format!(
                    "species {a} {b}: {why}"
                )));
            }
            let core = largest[a] + largest[b];
            let inner = p.steps[0].radius;
            if largest[a] > 0.0 && largest[b] > 0.0 && inner <= core {
                return Err(crate::Error::BadPotential(format!(
                    "species {a} {b}: the step at {inner} is inside the hard core (contact distance {core})"
                )));
            }
            tables.push(Table {
                r: p.steps.iter().rev().map(|s| s.radius).collect(),
                e: p.steps.iter().rev().map(|s| s.energy).collect(),
            });
            let k = tables.len() as u32;
            index[a * species + b] = k;
            index[b * species + a] = k;
            let r = p.steps[p.steps.len() - 1].radius;
            outer[a * species + b] = r;
            outer[b * species + a] = r;
            range = range.max(p.steps[p.steps.len() - 1].radius);
        }
        // The skin: `SKIN` diameters, or less where a periodic axis has room for only three
        // cells of the reach and a thinner skin (the grid refuses a box without room for a
        // thousandth of the reach). The list radius is the reach and the skin, and a rounding
        // allowance `EPS` that the cells' width must include too.
        const EPS: f64 = 1e-9;
        let max_diameter = discs.iter().map(|d| 2.0 * d.radius).fold(0.0, f64::max);
        let reach = range.max(max_diameter);
        let mut skin = SKIN
            * if max_diameter > 0.0 {
                max_diameter
            } else {
                reach
            };
        for a in 0..D {
            if sim_box.is_periodic(a) {
                skin = skin.min(sim_box.lengths[a] / (3.0 * (1.0 + 2.0 * EPS)) - reach);
            }
        }
        let skin = skin.max(1e-3 * reach);
        let list_radius = (reach + skin) * (1.0 + EPS);
        // The lists' expected length at the mean density, for their rows' width.
        let volume: f64 = sim_box.lengths.iter().product();
        let ball = match D {
            1 => 2.0 * list_radius,
            2 => std::f64::consts::PI * list_radius.powi(2),
            _ => 4.0 / 3.0 * std::f64::consts::PI * list_radius.powi(3),
        };
        let expected = discs.len() as f64 * (ball / volume).min(1.0);
        let uniform = (species == 1 && tables.len() == 1).then(|| {
            let t = &tables[0];
            let m = t.r.len();
            Edges {
                rows: (0..=m)
                    .map(|s| {
                        let inner = if s == 0 {
                            outer[0]
                        } else if s < m {
                            t.r[s]
                        } else {
                            0.0
                        };
                        let leave = if s > 0 { t.r[s - 1] } else { 0.0 };
                        let outside = if s == 0 { -0.0 } else { 0.0 };
                        [inner, leave, outside, 0.0]
                    })
                    .collect(),
            }
        });
        Ok(Steps {
            potential: potential.clone(),
            species,
            index,
            tables,
            outer,
            near: Lists::new(discs.len(), expected),
            centre: crate::hint::filled(Vector::ZERO, discs.len()),
            leash: 0.5 * skin,
            list_radius,
            lengths: sim_box.lengths,
            half: std::array::from_fn(|a| {
                if sim_box.is_periodic(a) {
                    0.5 * sim_box.lengths[a]
                } else {
                    f64::INFINITY
                }
            }),
            spare: Default::default(),
            filed: Default::default(),
            uniform,
        })
    }

    /// The table of species `a` and `b`, if they have steps.
    #[inline(always)]
    pub(super) fn table(&self, a: u16, b: u16) -> Option<&Table> {
        let k = self.index[a as usize * self.species + b as usize];
        (k != 0).then(|| &self.tables[k as usize - 1])
    }

    /// The nearest image of a displacement between neighbours (at most the list radius and
    /// the skin apart, under a third of a periodic box), without branches.
    #[inline(always)]
    pub(super) fn nearest_image(&self, mut d: Vector<D>) -> Vector<D> {
        for a in 0..D {
            let l = self.lengths[a];
            let x = d[a];
            d[a] = select(x > self.half[a], x - l, select(x < -self.half[a], x + l, x));
        }
        d
    }

    /// Sets the shell of the pair `i`, `j` (0: outside every step, still neighbours).
    pub(super) fn set_shell(&mut self, i: usize, j: usize, s: u8) {
        self.near.put(i, j as u32, s);
        self.near.put(j, i as u32, s);
    }

    /// The potential energy of a pair in shell `s` of `table`.
    pub(super) fn energy(table: &Table, s: u8) -> f64 {
        table.e[..s as usize].iter().sum()
    }

    /// Bytes held by the lists.
    pub(super) fn memory_bytes(&self) -> usize {
        self.near.memory_bytes()
            + self.centre.capacity() * size_of::<Vector<D>>()
            + self.filed.memory_bytes()
    }
}

/// Which shell a pair at distance `r` is in: how many of the (decreasing) radii exceed it.
pub(super) fn shell_at(table: &Table, r: f64) -> u8 {
    table.r.iter().take_while(|&&x| r < x).count() as u8
}

/// Disc `i`'s earliest pair event among its neighbours (`i` advanced to `t0`), for a stepped
/// potential: for each, the arrival at its shell's inner edge if it gets there, else its
/// departure through the outer edge. Most neighbours are outside every step (shell 0), whose
/// only event is the arrival at the outermost one, if they meet it. In 3D each time goes to
/// `nearest` in the list's order, which decides ties as the x86-64-v3 scan does (one root
/// there for four lanes, whichever each needs). In 2D, which has no such scan, the contact
/// terms of those outside every step go to `nearest` as a hard core's do, without a branch,
/// the roots worked out only for those that meet (3% faster for the square-well fluid of
/// BENCHMARKS.md at N = 10^4 than a root each as they come).
#[inline(always)]
pub(super) fn scan_stepped<const D: usize, const FAR: bool>(
    body: &[super::Body<D>],
    species: &super::per_disc::PerDisc<u16>,
    steps: &Steps<D>,
    i: usize,
    t0: f64,
    nearest: &mut super::predict::Nearest<'_>,
) {
    // The fields, not a copy of the record (see `predict_with`).
    let (pos, vel, radius) = (body[i].pos, body[i].vel, body[i].radius);
    let own_species = species[i];
    let row = own_species as usize * steps.species;
    for &(j, s) in steps.near.get(i) {
        let bj = &body[j as usize];
        let dr = steps.nearest_image(bj.position_at(t0) - pos);
        let dv = bj.vel - vel;
        let sigma = radius + bj.radius;
        if s == 0 {
            let reach = steps.outer[row + species[j as usize] as usize].max(sigma);
            let terms = crate::predict::contact_terms::<D, FAR>(dr, dv, reach);
            if D == 3 {
                if terms.meets() {
                    nearest.take(t0 + crate::predict::contact_root(terms), j);
                }
            } else {
                nearest.offer(j as usize, terms);
            }
            continue;
        }
        // Only pairs with steps are ever in a shell above 0.
        let Some(table) = steps.table(own_species, species[j as usize]) else {
            continue;
        };
        let s = s as usize;
        let inner = if s < table.r.len() { table.r[s] } else { sigma };
        let terms = crate::predict::contact_terms::<D, FAR>(dr, dv, inner);
        let t = if terms.meets() {
            t0 + crate::predict::contact_root(terms)
        } else {
            t0 + exit_time(dr, dv, table.r[s - 1])
        };
        nearest.take(t, j);
    }
}

impl<const D: usize> Simulation<D> {
    /// Makes every disc's neighbour list at its position now, each pair inside a step filed
    /// in the shell its distance puts it in, or (`keep`) in the shell given there: the pairs
    /// of `keep[i]` with discs above `i`. Files the discs in the grid by their centres.
    pub(super) fn make_lists(&mut self, keep: Option<&[Vec<(u32, u8)>]>) {
        let Some(steps) = self.steps.as_deref_mut() else {
            return;
        };
        let now = self.event_time;
        let n = self.body.len();
        for i in 0..n {
            let b = &mut self.body[i];
            b.advance_to(now);
            let image = wrap_into(&mut b.pos, &self.sim_box, self.image.get(i));
            self.image.set(i, image);
            steps.centre[i] = b.pos;
        }
        self.grid.clear();
        for i in 0..n {
            let c = self.grid.coord_of(steps.centre[i]);
            self.grid.insert(i, c);
        }
        steps.filed.refile(&self.grid, &steps.centre);
        let mut near: Vec<Vec<Entry>> = vec![Vec::new(); n];
        for i in 0..n {
            let mut found = Vec::new();
            let (c, ci) = (self.grid.cell_of(i), steps.centre[i]);
            for_each_listed(&self.grid, steps, c, ci, |j, r2| {
                if j <= i {
                    return;
                }
                let s = match keep {
                    Some(k) => shell_in(&k[i], j as u32),
                    None => steps
                        .table(self.species[i], self.species[j])
                        .map_or(0, |t| shell_at(t, r2.sqrt())),
                };
                found.push((j, s));
            });
            for (j, s) in found {
                near[i].push((j as u32, s));
                near[j].push((i as u32, s));
            }
        }
        steps.near.clear();
        for (i, list) in near.iter_mut().enumerate() {
            list.sort_unstable_by_key(|e| e.0);
            steps.near.set(i, list);
        }
        // Pairs a caller keeps in a shell stay neighbours whatever their centres.
        if let Some(k) = keep {
            for (i, list) in k.iter().enumerate() {
                for &(j, s) in list {
                    if s > 0 {
                        steps.set_shell(i, j as usize, s);
                    }
                }
            }
        }
    }

    /// Makes disc `i`'s neighbour list again where it is at `t`, half a skin from where it
    /// was made: a bookkeeping event that changes no velocity. Pairs inside a step keep their
    /// shells and stay listed; pairs that come within the list radius join as shell 0.
    #[inline(never)]
    pub(super) fn relist(&mut self, i: usize, t: f64) -> EventRecord<D> {
        let b = &mut self.body[i];
        b.advance_to(t);
        let image = wrap_into(&mut b.pos, &self.sim_box, self.image.get(i));
        self.image.set(i, image);
        let p = b.pos;
        let steps = self.steps.as_deref_mut().expect("a stepped simulation");
        steps.centre[i] = p;
        let c = self.grid.coord_of(p);
        let was = self.grid.cell_of(i);
        let k = self.grid.index_of(c);
        if c != was {
            self.grid.remove(i);
            self.grid.insert(i, c);
            if D == 3 {
                let from = self.grid.index_of(was);
                steps.filed.unfile(from, i as u32, &steps.centre);
                steps.filed.file(k, i as u32, p);
            }
        } else if D == 3 {
            steps.filed.moved(k, i as u32, p);
        }
        let (mut found, mut old, mut new) = std::mem::take(&mut steps.spare);
        found.clear();
        old.clear();
        new.clear();
        old.extend_from_slice(steps.near.get(i));
        #[cfg(target_arch = "x86_64")]
        let simd = D == 3 && self.v3;
        #[cfg(not(target_arch = "x86_64"))]
        let simd = false;
        if simd {
            // The centres filed in the cells, four at a time, the same spheres found
            // (`steps_x86.rs`).
            #[cfg(target_arch = "x86_64")]
            // SAFETY: `v3` is only set when the processor has AVX2 (`set_portable_loop`).
            #[allow(unsafe_code)]
            unsafe {
                super::steps_x86::listed(&self.grid, steps, c, p, i, &mut found)
            };
        } else {
            for_each_listed(&self.grid, steps, c, p, |j, _| {
                if j != i {
                    found.push(j as u32);
                }
            });
        }
        found.sort_unstable();
        // The old list and the spheres found side by side (both in order): a pair in both
        // keeps its shell and its place in the other disc's list; a pair inside a step stays
        // whatever its centres; only the pairs that come or go touch the other disc's list.
        let (mut a, mut b) = (0, 0);
        while a < old.len() || b < found.len() {
            let (jo, so) = old.get(a).copied().unwrap_or((u32::MAX, 0));
            let jn = found.get(b).copied().unwrap_or(u32::MAX);
            if jo == jn {
                new.push((jo, so));
                a += 1;
                b += 1;
            } else if jo < jn {
                if so > 0 {
                    new.push((jo, so));
                } else {
                    steps.near.remove(jo as usize, i as u32);
                }
                a += 1;
            } else {
                new.push((jn, 0));
                steps.near.join(jn as usize, i as u32);
                b += 1;
            }
        }
        steps.near.set(i, &new);
        steps.spare = (found, old, new);
        self.stats.neighbour_list = self.stats.neighbour_list.wrapping_add(1);
        EventRecord {
            time: t,
            kind: EventKind::NeighbourList { i },
            impulse: Vector::ZERO,
        }
    }

    /// Whether this simulation has a stepped potential.
    pub fn is_stepped(&self) -> bool {
        self.steps.is_some()
    }

    /// The stepped potential, if the simulation has one.
    pub fn potential(&self) -> Option<&Potential> {
        self.steps.as_ref().map(|s| &s.potential)
    }

    /// The potential energy: the sum over pairs of the energy of their shell (0 without a
    /// stepped potential), plus the field's ([`Self::field_energy`]) and the self-gravity's
    /// ([`Self::self_gravity_energy`]). Kinetic plus potential
    /// energy is conserved (without a thermostat, reactions' heat or restitution).
    pub fn potential_energy(&self) -> f64 {
        self.shells()
            .into_iter()
            .map(|(i, j, s)| self.pair_energy(i, j, s))
            .sum::<f64>()
            + self.field_energy()
            + self.self_gravity_energy()
            + self.ring_energy()
    }

    /// The energy of the pair `i`, `j` in shell `s`.
    fn pair_energy(&self, i: usize, j: usize, s: u8) -> f64 {
        self.steps
            .as_ref()
            .and_then(|st| st.table(self.species[i], self.species[j]))
            .map_or(0.0, |t| Steps::<D>::energy(t, s))
    }

    /// The potential energy of the pairs disc `i` is in (each pair's whole energy: the sum
    /// over all discs is twice [`Self::potential_energy`]). For colouring discs by energy.
    pub fn potential_energy_of(&self, i: usize) -> f64 {
        self.partners_of(i)
            .into_iter()
            .map(|(j, s)| self.pair_energy(i, j, s))
            .sum()
    }

    /// The discs disc `i` shares a shell above 0 with, and the shell (for drawing bonds).
    pub fn partners_of(&self, i: usize) -> Vec<(usize, u8)> {
        self.steps.as_ref().map_or_else(Vec::new, |s| {
            s.near
                .get(i)
                .iter()
                .filter(|e| e.1 > 0)
                .map(|&(j, sh)| (j as usize, sh))
                .collect()
        })
    }

    /// The pairs inside at least one step, each once as `(i, j, shell)` with `i < j`, in
    /// order; the shell counts the steps the pair is inside.
    pub fn shells(&self) -> Vec<(usize, usize, u8)> {
        let Some(steps) = &self.steps else {
            return Vec::new();
        };
        let mut out = Vec::new();
        for (i, list) in steps.near.iter().enumerate() {
            for &(j, s) in list {
                if (j as usize) > i && s > 0 {
                    out.push((i, j as usize, s));
                }
            }
        }
        out
    }

    /// Pairs whose shell disagrees with their distance now by more than `tol` (relative) of the
    /// step between: `(i, j, shell kept, shell of the distance)`. Empty in every honest state:
    /// a shell changes only at the pair's events, where the pair stands at the step.
    pub fn shell_mismatches(&self, tol: f64) -> Vec<(usize, usize, u8, u8)> {
        let Some(steps) = &self.steps else {
            return Vec::new();
        };
        let now = self.now;
        let mut out = Vec::new();
        for i in 0..self.body.len() {
            let pi = self.body[i].position_at(now);
            let list = steps.near.get(i);
            self.grid.for_each_near(self.grid.cell_of(i), |j, _| {
                if j <= i {
                    return;
                }
                let Some(table) = steps.table(self.species[i], self.species[j]) else {
                    return;
                };
                let dr = steps.nearest_image(self.body[j].position_at(now) - pi);
                let r = dr.norm2().sqrt();
                let kept = shell_in(list, j as u32);
                let lo = shell_at(table, r * (1.0 + tol));
                let hi = shell_at(table, r * (1.0 - tol));
                if !(lo..=hi).contains(&kept) {
                    out.push((i, j, kept, shell_at(table, r)));
                }
            });
        }
        out
    }

    /// Pairs that should be neighbours (their centres within the list radius, or a shell
    /// above 0) and are not both listed so, or are listed with shells that disagree; every
    /// disc's list in order. For checking checkpoints. `None` in every honest state.
    pub(super) fn list_fault(&self) -> Option<String> {
        let steps = self.steps.as_ref()?;
        let n = self.body.len();
        for (i, list) in steps.near.iter().enumerate() {
            for (k, &(j, s)) in list.iter().enumerate() {
                let ju = j as usize;
                if ju >= n || ju == i || (k > 0 && list[k - 1].0 >= j) {
                    return Some(format!("disc {i}: neighbour list out of order at {j}"));
                }
                let m = steps
                    .table(self.species[i], self.species[ju])
                    .map_or(0, |t| t.r.len());
                if s as usize > m {
                    return Some(format!("disc {i}: shell {s} with disc {j}"));
                }
                let other = steps.near.get(ju);
                if find(other, i as u32).map(|x| other[x].1) != Ok(s) {
                    return Some(format!("discs {i} and {j}: lists that disagree"));
                }
            }
            let mut missing = None;
            let (c, ci) = (self.grid.cell_of(i), steps.centre[i]);
            for_each_listed(&self.grid, steps, c, ci, |j, _| {
                if j != i && missing.is_none() && find(list, j as u32).is_err() {
                    missing = Some(j);
                }
            });
            if let Some(j) = missing {
                return Some(format!("discs {i} and {j}: neighbours not listed"));
            }
        }
        None
    }

    /// The pair event of `i` and `j` at `t` under a stepped potential: a hard-core collision,
    /// or a step met from inside or outside, crossed or bounced off. Returns the record and
    /// the discs to predict again.
    #[inline(never)]
    pub(super) fn collide_stepped(
        &mut self,
        i: usize,
        j: usize,
        t: f64,
    ) -> (EventRecord<D>, [usize; 2]) {
        self.body[i].advance_to(t);
        self.body[j].advance_to(t);
        let steps = self.steps.as_ref().expect("a stepped simulation");
        let Some(table) = steps.table(self.species[i], self.species[j]) else {
            return self.collide(i, j, t);
        };
        let s = shell_in(steps.near.get(i), j as u32) as usize;
        let m = table.r.len();
        let dr = steps.nearest_image(self.body[j].pos - self.body[i].pos);
        let r2 = dr.norm2();
        let sigma = self.body[i].radius + self.body[j].radius;
        let inner = if s < m { table.r[s] } else { sigma };
        let at_inner = s == 0 || (r2 - inner * inner).abs() <= (r2 - table.r[s - 1].powi(2)).abs();
        if at_inner && s == m {
            return self.collide(i, j, t);
        }
        let (du, next) = if at_inner {
            (table.e[s], s + 1)
        } else {
            (-table.e[s - 1], s - 1)
        };
        let n = dr * (1.0 / r2.sqrt());
        let dv = self.body[j].vel - self.body[i].vel;
        let vn = dv.dot(n);
        let (mi, mj) = (self.mass[i], self.mass[j]);
        let mu = mi * mj / (mi + mj);
        // Approaching at the inner edge, receding at the outer one; a pair that grazes the
        // edge the other way by rounding is left as it is.
        let moving = if at_inner { vn < 0.0 } else { vn > 0.0 };
        let (vn_new, hit) = if !moving {
            (
                vn,
                if at_inner {
                    StepHit::Repelled
                } else {
                    StepHit::Held
                },
            )
        } else if 0.5 * mu * vn * vn > du {
            let v = (vn * vn - 2.0 * du / mu).sqrt();
            (
                if vn < 0.0 { -v } else { v },
                if at_inner {
                    StepHit::Entered
                } else {
                    StepHit::Left
                },
            )
        } else {
            (
                -vn,
                if at_inner {
                    StepHit::Repelled
                } else {
                    StepHit::Held
                },
            )
        };
        if matches!(hit, StepHit::Entered | StepHit::Left) {
            self.steps
                .as_mut()
                .expect("a stepped simulation")
                .set_shell(i, j, next as u8);
        }
        let dvn = vn_new - vn;
        let impulse = n * (-mu * dvn);
        self.body[i].vel += impulse * (1.0 / mi);
        self.body[j].vel -= impulse * (1.0 / mj);
        self.body[i].count = self.body[i].count.wrapping_add(1);
        self.body[j].count = self.body[j].count.wrapping_add(1);
        self.stats.step = self.stats.step.wrapping_add(1);
        let record = EventRecord {
            time: t,
            kind: EventKind::Step { i, j, hit },
            impulse,
        };
        (record, [i, j])
    }
}

/// Calls `f(j, r^2)` for every disc `j` filed in the cells around `c` whose list centre is
/// nearer `p` than the lists' radius, at distance `r` (the disc whose centre is `p` included):
/// the discs a list made at `p` holds.
fn for_each_listed<const D: usize>(
    grid: &CellGrid<D>,
    steps: &Steps<D>,
    c: CellCoord<D>,
    p: Vector<D>,
    mut f: impl FnMut(usize, f64),
) {
    let limit = steps.list_radius * steps.list_radius;
    grid.for_each_near(c, |j, _| {
        let r2 = steps.nearest_image(steps.centre[j] - p).norm2();
        if r2 < limit {
            f(j, r2);
        }
    });
}

/// Time until disc `i`, at `pos` moving at `vel`, strays half the skin from its list's centre
/// (`+inf` if it stands still). The position and velocity by value: a reference to the disc's
/// record kept the prediction from reading only the fields it needs.
#[inline(always)]
pub(super) fn leash_time<const D: usize>(
    steps: &Steps<D>,
    pos: Vector<D>,
    vel: Vector<D>,
    i: usize,
) -> f64 {
    exit_time(pos - steps.centre[i], vel, steps.leash)
}

/// Moves `p` into the box on periodic axes, returning the disc's image counts after the move
/// (a position that leaves through the low side is shifted up by a box length, and its count
/// of images crossed goes down by one, as a cell crossing does).
fn wrap_into<const D: usize>(
    p: &mut Vector<D>,
    sim_box: &SimBox<D>,
    mut image: [i32; D],
) -> [i32; D] {
    for a in 0..D {
        if !sim_box.is_periodic(a) {
            continue;
        }
        let l = sim_box.lengths[a];
        if p[a] < 0.0 {
            p[a] += l;
            image[a] = image[a].wrapping_sub(1);
        } else if p[a] >= l {
            p[a] -= l;
            image[a] = image[a].wrapping_add(1);
        }
    }
    image
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::setup::lattice_fluid_in;
    use crate::{Boundary, Options, PairSteps, Step};

    /// Runs `sim` in chunks, checking after each that every neighbour list is whole, in order
    /// and agrees with its partners' (`list_fault`), that the shells match the distances,
    /// that energy is kept, and that lists were made again along the way.
    fn lists_hold<const D: usize>(mut sim: Simulation<D>) {
        let e0 = sim.kinetic_energy() + sim.potential_energy();
        assert_eq!(sim.list_fault(), None);
        for _ in 0..20 {
            sim.run_events(3_000, &mut ());
            assert_eq!(sim.list_fault(), None);
            assert!(sim.shell_mismatches(1e-9).is_empty());
            assert!(sim.overlaps(crate::OVERLAP_TOLERANCE).first.is_none());
            let e = sim.kinetic_energy() + sim.potential_energy();
            assert!((e - e0).abs() < 1e-10 * e0.abs(), "{e} from {e0}");
        }
        let st = sim.stats();
        assert!(st.neighbour_list > 1_000 && st.cell_crossing == 0, "{st:?}");
    }

    fn fluid<const D: usize>(n: usize, boundary: Boundary, p: &Potential) -> Simulation<D> {
        let (discs, bx) = lattice_fluid_in::<D>(n, 0.3, boundary, 3).unwrap();
        Simulation::with_potential_at(&discs, bx, &[], p, Options::default(), 0.0).unwrap()
    }

    #[test]
    fn neighbour_lists_stay_whole_along_runs() {
        let well = Potential::single(0, 0, 1.5, -1.0);
        lists_hold(fluid::<3>(300, Boundary::Periodic, &well));
        lists_hold(fluid::<2>(300, Boundary::Walls, &well));
        // A mixture whose species-1 pairs have no steps: their hard cores are met through
        // the same lists.
        let (mut discs, bx) = lattice_fluid_in::<2>(300, 0.3, Boundary::Periodic, 5).unwrap();
        for d in discs.iter_mut().step_by(3) {
            d.species = 1;
        }
        let mixed = Potential {
            pairs: vec![
                PairSteps {
                    species: (0, 0),
                    steps: vec![Step {
                        radius: 1.5,
                        energy: -1.0,
                    }],
                },
                PairSteps {
                    species: (0, 1),
                    steps: vec![Step {
                        radius: 1.2,
                        energy: 0.5,
                    }],
                },
            ],
        };
        let sim = Simulation::with_potential_at(&discs, bx, &[], &mixed, Options::default(), 0.0)
            .unwrap();
        lists_hold(sim);
        // A box with room for a thinner skin only: 12 discs, 5.6 diameters across, three
        // cells of at least 1.5 plus the skin.
        let small = fluid::<2>(12, Boundary::Periodic, &well);
        let steps = small.steps.as_deref().unwrap();
        assert!(
            steps.leash < 0.5 * SKIN && steps.leash > 0.0,
            "{}",
            steps.leash
        );
        lists_hold(small);
    }

    #[test]
    fn exit_time_from_inside_and_at_the_edge() {
        // From the centre at unit speed: out at r.
        let t = exit_time(Vector::new([0.0, 0.0]), Vector::new([1.0, 0.0]), 1.5);
        assert_eq!(t, 1.5);
        // Moving inward from x = 1: through and out the far side at x = -1.5.
        let t = exit_time(Vector::new([1.0, 0.0]), Vector::new([-1.0, 0.0]), 1.5);
        assert_eq!(t, 2.5);
        // A hair outside and receding: at once. A hair outside and approaching: the far side.
        let t = exit_time(
            Vector::new([1.5 + 1e-15, 0.0]),
            Vector::new([1.0, 0.0]),
            1.5,
        );
        assert_eq!(t, 0.0);
        let t = exit_time(
            Vector::new([1.5 + 1e-15, 0.0]),
            Vector::new([-1.0, 0.0]),
            1.5,
        );
        assert!((t - 3.0).abs() < 1e-14, "{t}");
        // Receding from just inside: the small root, to within the rounding of the distance
        // (c = x^2 - r^2 is exact to about ulp(r^2) = 4e-16, which moves t by 1.5e-16).
        let x = 1.5 - 1e-12;
        let t = exit_time(Vector::new([x, 0.0]), Vector::new([1.0, 0.0]), 1.5);
        assert!((t - (1.5 - x)).abs() < 1e-15, "{t}");
        // Standing still: never.
        assert_eq!(
            exit_time(Vector::new([1.0, 0.0]), Vector::new([0.0, 0.0]), 1.5),
            f64::INFINITY
        );
    }
}
