//! A plain grid of bins for the neighbour searches outside the event loop (the random start
//! and the contact analysis): bins at least one given width wide, each a list of particles.

use crate::math::Vector;
use crate::state::SimBox;

/// Particles binned by position.
pub(crate) struct Bins<const D: usize> {
    cells: [usize; D],
    sim_box: SimBox<D>,
    lists: Vec<Vec<u32>>,
}

impl<const D: usize> Bins<D> {
    /// Empty bins at least `width` wide (and at most about `n` of them).
    pub fn new(sim_box: &SimBox<D>, width: f64, n: usize) -> Self {
        let width = width.max((sim_box.volume() / n.max(1) as f64).powf(1.0 / D as f64));
        let cells: [usize; D] =
            std::array::from_fn(|a| ((sim_box.lengths[a] / width) as usize).max(1));
        Bins {
            cells,
            sim_box: *sim_box,
            lists: vec![Vec::new(); cells.iter().product()],
        }
    }

    fn coords(&self, p: Vector<D>) -> [usize; D] {
        std::array::from_fn(|a| {
            let x = p[a] / self.sim_box.lengths[a] * self.cells[a] as f64;
            (x.max(0.0) as usize).min(self.cells[a] - 1)
        })
    }

    fn index(&self, c: [usize; D]) -> usize {
        let mut k = 0;
        for a in (0..D).rev() {
            k = k * self.cells[a] + c[a];
        }
        k
    }

    /// Files particle `i` at `p` (a position in the box).
    pub fn insert(&mut self, i: usize, p: Vector<D>) {
        let k = self.index(self.coords(p));
        self.lists[k].push(i as u32);
    }

    /// The particles in the bins around `p` (its own and the adjacent ones, each once).
    pub fn near(&self, p: Vector<D>) -> impl Iterator<Item = usize> + '_ {
        let c = self.coords(p);
        let mut near: Vec<usize> = Vec::with_capacity(27);
        for k in 0..3usize.pow(D as u32) {
            let mut cc = [0usize; D];
            let mut ok = true;
            let mut code = k;
            for a in 0..D {
                let x = c[a] as isize + (code % 3) as isize - 1;
                code /= 3;
                let m = self.cells[a] as isize;
                if (0..m).contains(&x) {
                    cc[a] = x as usize;
                } else if self.sim_box.is_periodic(a) {
                    cc[a] = x.rem_euclid(m) as usize;
                } else {
                    ok = false;
                }
            }
            if ok {
                near.push(self.index(cc));
            }
        }
        near.sort_unstable();
        near.dedup();
        near.into_iter()
            .flat_map(move |k| self.lists[k].iter().map(|&j| j as usize))
    }
}
