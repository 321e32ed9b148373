//! A disc as given by the user.

use crate::math::Vector;

/// An RGB colour, carried along untouched (the Princeton format's `r g b`).
pub type Colour = [u8; 3];

/// One disc: position, velocity, mass, radius, and labels the engine never looks at.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Disc<const D: usize = 2> {
    /// Centre position.
    pub pos: Vector<D>,
    /// Velocity.
    pub vel: Vector<D>,
    /// Mass, `> 0`.
    pub mass: f64,
    /// Radius, `> 0`.
    pub radius: f64,
    /// Display colour.
    pub colour: Colour,
    /// Species label (0 unless a file or generator sets one).
    pub species: u16,
}

impl<const D: usize> Disc<D> {
    /// A disc of unit mass, black, species 0.
    pub fn new(pos: Vector<D>, vel: Vector<D>, radius: f64) -> Self {
        Disc {
            pos,
            vel,
            mass: 1.0,
            radius,
            colour: [0, 0, 0],
            species: 0,
        }
    }

    /// The same disc in `E` dimensions: the first `min(D, E)` components of its position and
    /// velocity, the others zero. Lets code written for one dimension hand discs to code
    /// written for another (for `E == D` it is a copy).
    pub fn with_dim<const E: usize>(&self) -> Disc<E> {
        let cut = |v: Vector<D>| Vector(std::array::from_fn(|a| if a < D { v[a] } else { 0.0 }));
        Disc {
            pos: cut(self.pos),
            vel: cut(self.vel),
            mass: self.mass,
            radius: self.radius,
            colour: self.colour,
            species: self.species,
        }
    }

    /// Kinetic energy `m v^2 / 2`.
    pub fn kinetic_energy(&self) -> f64 {
        0.5 * self.mass * self.vel.norm2()
    }
}
