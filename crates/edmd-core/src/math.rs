//! The dimension and the vector type, written once.
//!
//! Everything dimension-dependent in the engine loops over [`DIM`], so a 3D build is this
//! file's `DIM = 3` plus the file formats.

use std::ops::{Add, AddAssign, Div, Index, IndexMut, Mul, Neg, Sub, SubAssign};

/// Number of spatial dimensions.
pub const DIM: usize = 2;

/// A vector in `DIM` dimensions.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Vector(pub [f64; DIM]);

impl Vector {
    /// The zero vector.
    pub const ZERO: Vector = Vector([0.0; DIM]);

    /// A vector from its components.
    pub const fn new(c: [f64; DIM]) -> Self {
        Vector(c)
    }

    /// Dot product.
    #[inline(always)]
    pub fn dot(self, o: Vector) -> f64 {
        let mut s = 0.0;
        for a in 0..DIM {
            s += self.0[a] * o.0[a];
        }
        s
    }

    /// Squared length.
    #[inline(always)]
    pub fn norm2(self) -> f64 {
        self.dot(self)
    }

    /// `self + v * t`, the straight-line motion used everywhere.
    #[inline(always)]
    pub fn advanced(self, v: Vector, t: f64) -> Vector {
        let mut r = self;
        for a in 0..DIM {
            r.0[a] += v.0[a] * t;
        }
        r
    }

    /// True when every component is finite.
    pub fn is_finite(self) -> bool {
        self.0.iter().all(|c| c.is_finite())
    }
}

impl Index<usize> for Vector {
    type Output = f64;
    #[inline(always)]
    fn index(&self, a: usize) -> &f64 {
        &self.0[a]
    }
}

impl IndexMut<usize> for Vector {
    #[inline(always)]
    fn index_mut(&mut self, a: usize) -> &mut f64 {
        &mut self.0[a]
    }
}

impl Add for Vector {
    type Output = Vector;
    #[inline(always)]
    fn add(mut self, o: Vector) -> Vector {
        self += o;
        self
    }
}

impl AddAssign for Vector {
    #[inline(always)]
    fn add_assign(&mut self, o: Vector) {
        for a in 0..DIM {
            self.0[a] += o.0[a];
        }
    }
}

impl Sub for Vector {
    type Output = Vector;
    #[inline(always)]
    fn sub(mut self, o: Vector) -> Vector {
        self -= o;
        self
    }
}

impl SubAssign for Vector {
    #[inline(always)]
    fn sub_assign(&mut self, o: Vector) {
        for a in 0..DIM {
            self.0[a] -= o.0[a];
        }
    }
}

impl Mul<f64> for Vector {
    type Output = Vector;
    #[inline(always)]
    fn mul(mut self, s: f64) -> Vector {
        for a in 0..DIM {
            self.0[a] *= s;
        }
        self
    }
}

impl Div<f64> for Vector {
    type Output = Vector;
    #[inline(always)]
    fn div(mut self, s: f64) -> Vector {
        for a in 0..DIM {
            self.0[a] /= s;
        }
        self
    }
}

impl Neg for Vector {
    type Output = Vector;
    #[inline(always)]
    fn neg(self) -> Vector {
        self * -1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dot_and_motion() {
        let a = Vector::new([3.0, 4.0]);
        assert_eq!(a.norm2(), 25.0);
        assert_eq!(
            a.advanced(Vector::new([1.0, -1.0]), 2.0),
            Vector::new([5.0, 2.0])
        );
        assert_eq!(-a, Vector::new([-3.0, -4.0]));
    }
}
