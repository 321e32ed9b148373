//! The simulation box `[0, L_0] x [0, L_1] x ...`, each axis with its own boundary.

use crate::math::Vector;

/// What happens at the two ends of one axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Boundary {
    /// Hard reflecting walls at 0 and L.
    Walls,
    /// Periodic: leaving at L re-enters at 0.
    Periodic,
}

/// A rectangular box with a boundary kind per axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimBox<const D: usize = 2> {
    /// Edge lengths.
    pub lengths: [f64; D],
    /// Boundary kind per axis.
    pub boundaries: [Boundary; D],
}

impl<const D: usize> SimBox<D> {
    /// A box with walls on every axis.
    pub fn walls(lengths: [f64; D]) -> Self {
        SimBox {
            lengths,
            boundaries: [Boundary::Walls; D],
        }
    }

    /// A fully periodic box.
    pub fn periodic(lengths: [f64; D]) -> Self {
        SimBox {
            lengths,
            boundaries: [Boundary::Periodic; D],
        }
    }

    /// The unit box with walls (the Princeton assignment's container).
    pub fn unit() -> Self {
        Self::walls([1.0; D])
    }

    /// Area (volume in 3D).
    pub fn volume(&self) -> f64 {
        self.lengths.iter().product()
    }

    /// True if the axis is periodic.
    pub fn is_periodic(&self, axis: usize) -> bool {
        self.boundaries[axis] == Boundary::Periodic
    }

    /// The minimum-image form of a displacement (identity on walled axes).
    pub fn minimum_image(&self, mut d: Vector<D>) -> Vector<D> {
        for a in 0..D {
            if self.is_periodic(a) {
                let l = self.lengths[a];
                // Cheap for the usual case of a displacement already within one box length.
                if d[a] > 0.5 * l {
                    d[a] -= l;
                    if d[a] > 0.5 * l {
                        d[a] -= l * (d[a] / l).round();
                    }
                } else if d[a] < -0.5 * l {
                    d[a] += l;
                    if d[a] < -0.5 * l {
                        d[a] -= l * (d[a] / l).round();
                    }
                }
            }
        }
        d
    }

    /// Maps a position into the primary box `[0, L)` on periodic axes.
    pub fn wrap(&self, mut p: Vector<D>) -> Vector<D> {
        for a in 0..D {
            if self.is_periodic(a) {
                let l = self.lengths[a];
                p[a] -= l * (p[a] / l).floor();
                if p[a] >= l {
                    p[a] -= l;
                }
            }
        }
        p
    }
}
