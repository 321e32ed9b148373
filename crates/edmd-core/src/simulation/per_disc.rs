//! A per-disc value that is usually the same for every disc (mass, colour, species): held once
//! while the discs agree, as an array from the first that differs. Equal discs, the common
//! case and the one of the largest runs, then spend 13 bytes per disc less (BENCHMARKS.md,
//! "Memory at scale"); reading a value is one predictable branch more.

use std::ops::{Index, IndexMut};

#[derive(Clone, Debug)]
pub(crate) enum PerDisc<T> {
    /// Every one of `len` discs has `value`.
    Same {
        value: T,
        len: usize,
    },
    Each(Vec<T>),
}

impl<T: Copy + PartialEq> PerDisc<T> {
    pub(crate) fn new() -> Self {
        PerDisc::Each(Vec::new())
    }

    pub(crate) fn from_vec(v: Vec<T>) -> Self {
        let mut p = Self::new();
        for x in v {
            p.push(x);
        }
        p
    }

    pub(crate) fn len(&self) -> usize {
        match self {
            PerDisc::Same { len, .. } => *len,
            PerDisc::Each(v) => v.len(),
        }
    }

    pub(crate) fn push(&mut self, x: T) {
        match self {
            PerDisc::Each(v) if v.is_empty() => *self = PerDisc::Same { value: x, len: 1 },
            PerDisc::Same { value, len } if *value == x => *len += 1,
            _ => self.each().push(x),
        }
    }

    /// Gives back the room an array grew beyond its values.
    pub(crate) fn shrink_to_fit(&mut self) {
        if let PerDisc::Each(v) = self {
            v.shrink_to_fit();
        }
    }

    pub(crate) fn reverse(&mut self) {
        if let PerDisc::Each(v) = self {
            v.reverse();
        }
    }

    pub(crate) fn iter(&self) -> impl Iterator<Item = &T> + '_ {
        (0..self.len()).map(move |i| &self[i])
    }

    pub(crate) fn to_vec(&self) -> Vec<T> {
        self.iter().copied().collect()
    }

    /// Bytes held for the values.
    pub(crate) fn memory_bytes(&self) -> usize {
        match self {
            PerDisc::Same { .. } => 0,
            PerDisc::Each(v) => v.capacity() * std::mem::size_of::<T>(),
        }
    }

    /// The values as an array, made one if they were all the same.
    fn each(&mut self) -> &mut Vec<T> {
        if let PerDisc::Same { value, len } = *self {
            *self = PerDisc::Each(vec![value; len]);
        }
        match self {
            PerDisc::Each(v) => v,
            PerDisc::Same { .. } => unreachable!("made an array above"),
        }
    }
}

impl<T> Index<usize> for PerDisc<T> {
    type Output = T;

    #[inline(always)]
    fn index(&self, i: usize) -> &T {
        match self {
            PerDisc::Same { value, len } => {
                assert!(i < *len, "disc {i} of {len}");
                value
            }
            PerDisc::Each(v) => &v[i],
        }
    }
}

impl<T: Copy + PartialEq> IndexMut<usize> for PerDisc<T> {
    fn index_mut(&mut self, i: usize) -> &mut T {
        &mut self.each()[i]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_values_are_held_once_and_read_as_an_array() {
        let mut p = PerDisc::from_vec(vec![2.0; 5]);
        assert_eq!(p.memory_bytes(), 0);
        assert_eq!(p.len(), 5);
        assert_eq!(p[4], 2.0);
        p[1] = 3.0;
        assert_eq!(p.to_vec(), vec![2.0, 3.0, 2.0, 2.0, 2.0]);
        assert_eq!(p.memory_bytes(), 5 * 8);
    }

    #[test]
    fn a_differing_value_makes_an_array_in_order() {
        let mut p = PerDisc::new();
        for x in [1u16, 1, 1, 2, 1] {
            p.push(x);
        }
        assert_eq!(p.to_vec(), vec![1, 1, 1, 2, 1]);
        p.reverse();
        assert_eq!(p.to_vec(), vec![1, 2, 1, 1, 1]);
    }

    #[test]
    #[should_panic(expected = "disc 3 of 3")]
    fn reading_past_the_end_panics_as_an_array_does() {
        let p = PerDisc::from_vec(vec![7u8; 3]);
        let _ = p[3];
    }
}
