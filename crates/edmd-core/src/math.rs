//! The vector type, written once for every dimension.
//!
//! The dimension `D` is a const parameter of [`Vector`] and of every type built on it
//! (`Disc<D>`, `SimBox<D>`, `Simulation<D>`), so one source compiles to a 2D and a 3D engine,
//! each monomorphised: a loop over `0..D` unrolls as if the dimension were written out.
//! The parameter defaults to 2, the dimension edmd started with, so `Vector` alone is a 2D
//! vector.

use std::ops::{Add, AddAssign, Div, Index, IndexMut, Mul, Neg, Sub, SubAssign};

/// The dimension of the 2D engine (the default of every `D` parameter).
pub const DIM: usize = 2;

/// A vector in `D` dimensions (2 unless said otherwise).
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(transparent)]
pub struct Vector<const D: usize = 2>(pub [f64; D]);

/// A vector is written as its `D` components (serde has no impls for arrays of generic
/// length).
#[cfg(feature = "serde")]
impl<const D: usize> serde::Serialize for Vector<D> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeTuple;
        let mut t = s.serialize_tuple(D)?;
        for x in &self.0 {
            t.serialize_element(x)?;
        }
        t.end()
    }
}

#[cfg(feature = "serde")]
impl<'de, const D: usize> serde::Deserialize<'de> for Vector<D> {
    fn deserialize<De: serde::Deserializer<'de>>(d: De) -> Result<Self, De::Error> {
        struct Components<const D: usize>;
        impl<'de, const D: usize> serde::de::Visitor<'de> for Components<D> {
            type Value = Vector<D>;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                write!(f, "{D} numbers")
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> Result<Vector<D>, A::Error> {
                let mut v = [0.0; D];
                for (k, x) in v.iter_mut().enumerate() {
                    *x = seq
                        .next_element()?
                        .ok_or_else(|| serde::de::Error::invalid_length(k, &self))?;
                }
                Ok(Vector(v))
            }
        }
        d.deserialize_tuple(D, Components::<D>)
    }
}

impl<const D: usize> Default for Vector<D> {
    fn default() -> Self {
        Vector([0.0; D])
    }
}

impl<const D: usize> Vector<D> {
    /// The zero vector.
    pub const ZERO: Vector<D> = Vector([0.0; D]);

    /// A vector from its components.
    pub const fn new(c: [f64; D]) -> Self {
        Vector(c)
    }

    /// Dot product.
    #[inline(always)]
    pub fn dot(self, o: Vector<D>) -> f64 {
        let mut s = 0.0;
        for a in 0..D {
            s += self.0[a] * o.0[a];
        }
        s
    }

    /// Squared length.
    #[inline(always)]
    pub fn norm2(self) -> f64 {
        self.dot(self)
    }

    /// Squared length of the wedge (in 3D cross) product, `|self|^2 |o|^2 - (self.o)^2` by
    /// Lagrange's identity, summed from the components `self_a o_b - self_b o_a` so that it keeps
    /// its digits when the two vectors are nearly parallel (the difference form cancels).
    #[inline(always)]
    pub fn wedge2(self, o: Vector<D>) -> f64 {
        let (p, q) = (&self.0, &o.0);
        let w = |a: usize, b: usize| p[a] * q[b] - p[b] * q[a];
        match D {
            1 => 0.0,
            2 => w(0, 1) * w(0, 1),
            3 => {
                let (x, y, z) = (w(1, 2), w(2, 0), w(0, 1));
                x * x + y * y + z * z
            }
            _ => {
                let mut s = 0.0;
                for a in 0..D {
                    for b in a + 1..D {
                        s += w(a, b) * w(a, b);
                    }
                }
                s
            }
        }
    }

    /// `self + v * t`, the straight-line motion used everywhere.
    #[inline(always)]
    pub fn advanced(self, v: Vector<D>, t: f64) -> Vector<D> {
        let mut r = self;
        for a in 0..D {
            r.0[a] += v.0[a] * t;
        }
        r
    }

    /// True when every component is finite.
    pub fn is_finite(self) -> bool {
        self.0.iter().all(|c| c.is_finite())
    }
}

impl<const D: usize> Index<usize> for Vector<D> {
    type Output = f64;
    #[inline(always)]
    fn index(&self, a: usize) -> &f64 {
        &self.0[a]
    }
}

impl<const D: usize> IndexMut<usize> for Vector<D> {
    #[inline(always)]
    fn index_mut(&mut self, a: usize) -> &mut f64 {
        &mut self.0[a]
    }
}

impl<const D: usize> Add for Vector<D> {
    type Output = Vector<D>;
    #[inline(always)]
    fn add(mut self, o: Vector<D>) -> Vector<D> {
        self += o;
        self
    }
}

impl<const D: usize> AddAssign for Vector<D> {
    #[inline(always)]
    fn add_assign(&mut self, o: Vector<D>) {
        for a in 0..D {
            self.0[a] += o.0[a];
        }
    }
}

impl<const D: usize> Sub for Vector<D> {
    type Output = Vector<D>;
    #[inline(always)]
    fn sub(mut self, o: Vector<D>) -> Vector<D> {
        self -= o;
        self
    }
}

impl<const D: usize> SubAssign for Vector<D> {
    #[inline(always)]
    fn sub_assign(&mut self, o: Vector<D>) {
        for a in 0..D {
            self.0[a] -= o.0[a];
        }
    }
}

impl<const D: usize> Mul<f64> for Vector<D> {
    type Output = Vector<D>;
    #[inline(always)]
    fn mul(mut self, s: f64) -> Vector<D> {
        for a in 0..D {
            self.0[a] *= s;
        }
        self
    }
}

impl<const D: usize> Div<f64> for Vector<D> {
    type Output = Vector<D>;
    #[inline(always)]
    fn div(mut self, s: f64) -> Vector<D> {
        for a in 0..D {
            self.0[a] /= s;
        }
        self
    }
}

impl<const D: usize> Neg for Vector<D> {
    type Output = Vector<D>;
    #[inline(always)]
    fn neg(self) -> Vector<D> {
        self * -1.0
    }
}

/// `a` if `cond`, else `b`, chosen by bit masks. The compiler is free to turn `if cond { a }
/// else { b }` into a branch, and does in some inlining contexts; where `cond` is a coin toss
/// (the sign of a velocity component) a mispredicted branch costs more than both operands.
#[inline(always)]
pub(crate) fn select(cond: bool, a: f64, b: f64) -> f64 {
    let mask = (cond as u64).wrapping_neg();
    f64::from_bits((a.to_bits() & mask) | (b.to_bits() & !mask))
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
