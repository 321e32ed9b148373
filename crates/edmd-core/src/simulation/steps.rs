//! Stepped pair potentials in the event loop: each pair's shell, the predictions of step
//! events, and what happens at a step.
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

use crate::events::{EventKind, EventRecord, StepHit};
use crate::math::Vector;
use crate::state::{Disc, Potential};

use super::Simulation;

/// One pair of species' steps, outermost first, as the loop reads them.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Table {
    /// Step radii, decreasing.
    pub(super) r: Vec<f64>,
    /// Energy change on crossing each step inward.
    pub(super) e: Vec<f64>,
}

/// The stepped potential of a simulation and the shells of its pairs.
#[derive(Clone, Debug)]
pub(super) struct Steps {
    /// The potential as given.
    pub(super) potential: Potential,
    /// Species are below this.
    species: usize,
    /// Per pair of species (`a * species + b`), its table in `tables` plus one (0: none).
    index: Vec<u32>,
    tables: Vec<Table>,
    /// Per disc, the discs it shares a shell above 0 with, and the shell (both discs of a
    /// pair list it).
    pub(super) shells: Vec<Vec<(u32, u8)>>,
    /// The largest step radius: the range of the interaction.
    pub(super) range: f64,
}

/// The shell of the pair (`list` is one disc's list, `j` the other disc).
#[inline(always)]
pub(super) fn shell_in(list: &[(u32, u8)], j: u32) -> u8 {
    let mut s = 0;
    for &(k, sh) in list {
        if k == j {
            s = sh;
        }
    }
    s
}

/// Time from now until a pair inside distance `r` (relative position `dr`, velocity `dv`)
/// reaches it moving outward: the larger root of `|dr + dv t| = r`, in the form that keeps
/// its digits for either sign of `dr . dv`. A pair found outside (by rounding) and receding
/// leaves at once; `+inf` if it does not move.
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

impl Steps {
    /// The tables of `potential` for these discs; errors if a step lies inside the hard core of
    /// discs it applies to or names a species no disc has.
    pub(super) fn new<const D: usize>(
        potential: &Potential,
        discs: &[Disc<D>],
    ) -> Result<Self, crate::Error> {
        potential.validate()?;
        let species = discs
            .iter()
            .map(|d| d.species as usize + 1)
            .max()
            .unwrap_or(1);
        let mut largest = vec![0.0f64; species];
        for d in discs {
            let l = &mut largest[d.species as usize];
            *l = l.max(d.radius);
        }
        let mut index = vec![0u32; species * species];
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
            range = range.max(p.steps[p.steps.len() - 1].radius);
        }
        Ok(Steps {
            potential: potential.clone(),
            species,
            index,
            tables,
            shells: vec![Vec::new(); discs.len()],
            range,
        })
    }

    /// The table of species `a` and `b`, if they have steps.
    #[inline(always)]
    pub(super) fn table(&self, a: u16, b: u16) -> Option<&Table> {
        let k = self.index[a as usize * self.species + b as usize];
        (k != 0).then(|| &self.tables[k as usize - 1])
    }

    /// Sets the shell of the pair `i`, `j` (0 removes it from both lists).
    pub(super) fn set_shell(&mut self, i: usize, j: usize, s: u8) {
        for (x, y) in [(i, j), (j, i)] {
            let list = &mut self.shells[x];
            match list.iter().position(|e| e.0 == y as u32) {
                Some(k) if s == 0 => {
                    list.swap_remove(k);
                }
                Some(k) => list[k].1 = s,
                None if s != 0 => list.push((y as u32, s)),
                None => {}
            }
        }
    }

    /// The potential energy of a pair in shell `s` of `table`.
    pub(super) fn energy(table: &Table, s: u8) -> f64 {
        table.e[..s as usize].iter().sum()
    }
}

/// Which shell a pair at distance `r` is in: how many of the (decreasing) radii exceed it.
pub(super) fn shell_at(table: &Table, r: f64) -> u8 {
    table.r.iter().take_while(|&&x| r < x).count() as u8
}

/// Disc `i`'s earliest pair event among the discs around it (`bi`, advanced to `t0`), for a
/// stepped potential: for each candidate, the arrival at its shell's inner edge if it gets
/// there, else its departure through the outer edge. Most candidates are outside every step
/// (shell 0), whose only event is the arrival at the outermost one: their contact terms go to
/// `nearest` as a hard core's do, the roots worked out only for those that meet; the few inside
/// a step give their times directly.
#[inline(always)]
pub(super) fn scan_stepped<const D: usize, const FAR: bool>(
    grid: &crate::cells::CellGrid<D>,
    body: &[super::Body<D>],
    species: &[u16],
    steps: &Steps,
    i: usize,
    t0: f64,
    nearest: &mut super::predict::Nearest<'_>,
) {
    let mut scan = SteppedCandidates::<D, FAR> {
        body,
        species,
        steps,
        own: body[i],
        own_species: species[i],
        list: &steps.shells[i][..],
        t0,
        nearest,
    };
    grid.visit_near(grid.cell_of(i), &mut scan);
}

/// [`scan_stepped`]'s visit of one candidate.
struct SteppedCandidates<'a, 'n, const D: usize, const FAR: bool> {
    body: &'a [super::Body<D>],
    species: &'a [u16],
    steps: &'a Steps,
    own: super::Body<D>,
    own_species: u16,
    list: &'a [(u32, u8)],
    t0: f64,
    nearest: &'a mut super::predict::Nearest<'n>,
}

impl<const D: usize, const FAR: bool> crate::cells::Visit<D>
    for &mut SteppedCandidates<'_, '_, D, FAR>
{
    #[inline(always)]
    fn visit(&mut self, j: usize, shift: Vector<D>) {
        let (bi, bj) = (&self.own, &self.body[j]);
        let dr = bj.position_at(self.t0) + shift - bi.pos;
        let dv = bj.vel - bi.vel;
        let sigma = bi.radius + bj.radius;
        // Disc `i` itself (or its periodic image) has dv = 0, which never meets, and shell 0.
        let table = self.steps.table(self.own_species, self.species[j]);
        let s = if table.is_some() {
            shell_in(self.list, j as u32) as usize
        } else {
            0
        };
        match table {
            Some(table) if s > 0 => {
                let inner = if s < table.r.len() { table.r[s] } else { sigma };
                let terms = crate::predict::contact_terms::<D, FAR>(dr, dv, inner);
                let t = if terms.meets() {
                    self.t0 + crate::predict::contact_root(terms)
                } else {
                    self.t0 + exit_time(dr, dv, table.r[s - 1])
                };
                self.nearest.take(t, j as u32);
            }
            _ => {
                let reach = table.map_or(sigma, |t| t.r[0]);
                self.nearest
                    .offer(j, crate::predict::contact_terms::<D, FAR>(dr, dv, reach));
            }
        }
    }
}

impl<const D: usize> Simulation<D> {
    /// Files every pair inside a step in its shell, from the distances (at construction).
    pub(super) fn assign_shells(&mut self) {
        let Some(steps) = self.steps.as_mut() else {
            return;
        };
        let now = self.event_time;
        let mut found = Vec::new();
        for i in 0..self.body.len() {
            let pi = self.body[i].position_at(now);
            self.grid.for_each_near(self.grid.cell_of(i), |j, shift| {
                if j <= i {
                    return;
                }
                let Some(table) = steps.table(self.species[i], self.species[j]) else {
                    return;
                };
                let r = (self.body[j].position_at(now) + shift - pi).norm2().sqrt();
                let s = shell_at(table, r);
                if s > 0 {
                    found.push((i, j, s));
                }
            });
        }
        for (i, j, s) in found {
            steps.set_shell(i, j, s);
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
    /// stepped potential). Kinetic plus potential energy is conserved.
    pub fn potential_energy(&self) -> f64 {
        let Some(steps) = &self.steps else {
            return 0.0;
        };
        let mut u = 0.0;
        for (i, list) in steps.shells.iter().enumerate() {
            for &(j, s) in list {
                if (j as usize) > i {
                    if let Some(t) = steps.table(self.species[i], self.species[j as usize]) {
                        u += Steps::energy(t, s);
                    }
                }
            }
        }
        u
    }

    /// The potential energy of the pairs disc `i` is in (each pair's whole energy: the sum
    /// over all discs is twice [`Self::potential_energy`]). For colouring discs by energy.
    pub fn potential_energy_of(&self, i: usize) -> f64 {
        let Some(steps) = &self.steps else {
            return 0.0;
        };
        steps.shells[i]
            .iter()
            .filter_map(|&(j, s)| {
                steps
                    .table(self.species[i], self.species[j as usize])
                    .map(|t| Steps::energy(t, s))
            })
            .sum()
    }

    /// The discs disc `i` shares a shell above 0 with, and the shell (for drawing bonds).
    pub fn partners_of(&self, i: usize) -> Vec<(usize, u8)> {
        self.steps.as_ref().map_or_else(Vec::new, |s| {
            s.shells[i]
                .iter()
                .map(|&(j, sh)| (j as usize, sh))
                .collect()
        })
    }

    /// The pairs inside at least one step, each once as `(i, j, shell)` with `i < j`; the
    /// shell counts the steps the pair is inside.
    pub fn shells(&self) -> Vec<(usize, usize, u8)> {
        let Some(steps) = &self.steps else {
            return Vec::new();
        };
        let mut out = Vec::new();
        for (i, list) in steps.shells.iter().enumerate() {
            for &(j, s) in list {
                if (j as usize) > i {
                    out.push((i, j as usize, s));
                }
            }
        }
        out.sort_unstable();
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
            let list = &steps.shells[i];
            self.grid.for_each_near(self.grid.cell_of(i), |j, shift| {
                if j <= i {
                    return;
                }
                let Some(table) = steps.table(self.species[i], self.species[j]) else {
                    return;
                };
                let r = (self.body[j].position_at(now) + shift - pi).norm2().sqrt();
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
        let s = shell_in(&steps.shells[i], j as u32) as usize;
        let m = table.r.len();
        let dr = self
            .sim_box
            .minimum_image(self.body[j].pos - self.body[i].pos);
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

#[cfg(test)]
mod tests {
    use super::*;

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
