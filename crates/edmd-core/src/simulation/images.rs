//! The periodic images each disc has crossed (up less down, per axis), for unwrapped
//! positions. Held as 16-bit counts, 4 bytes a disc in 2D rather than 8, until a count leaves
//! their range: then the whole array is widened to 32-bit counts, which wrap (as they always
//! have) only after 2^31 crossings. A disc crosses a boundary only after a cell crossing, so
//! the test costs nothing in the event loop (BENCHMARKS.md, "Memory at scale").

#[derive(Clone, Debug)]
pub(crate) enum Images<const D: usize> {
    Narrow(Vec<[i16; D]>),
    Wide(Vec<[i32; D]>),
}

impl<const D: usize> Images<D> {
    /// `n` discs, none of which has crossed anything.
    pub(crate) fn new(n: usize) -> Self {
        Images::Narrow(vec![[0; D]; n])
    }

    /// The counts given, narrow if every one fits.
    pub(crate) fn from_vec(v: Vec<[i32; D]>) -> Self {
        if v.iter().flatten().all(|&k| i16::try_from(k).is_ok()) {
            Images::Narrow(v.iter().map(|c| c.map(|k| k as i16)).collect())
        } else {
            Images::Wide(v)
        }
    }

    /// Disc `i`'s counts.
    #[inline]
    pub(crate) fn get(&self, i: usize) -> [i32; D] {
        match self {
            Images::Narrow(v) => v[i].map(i32::from),
            Images::Wide(v) => v[i],
        }
    }

    /// Sets disc `i`'s counts.
    pub(crate) fn set(&mut self, i: usize, c: [i32; D]) {
        if let Images::Narrow(v) = self {
            if c.iter().all(|&k| i16::try_from(k).is_ok()) {
                v[i] = c.map(|k| k as i16);
                return;
            }
            self.widen();
        }
        if let Images::Wide(v) = self {
            v[i] = c;
        }
    }

    /// Adds `k` to disc `i`'s count along `axis` (wrapping at 32 bits).
    #[inline]
    pub(crate) fn add(&mut self, i: usize, axis: usize, k: i32) {
        let mut c = self.get(i);
        c[axis] = c[axis].wrapping_add(k);
        self.set(i, c);
    }

    fn widen(&mut self) {
        if let Images::Narrow(v) = self {
            *self = Images::Wide(v.iter().map(|c| c.map(i32::from)).collect());
        }
    }

    /// Bytes held.
    pub(crate) fn memory_bytes(&self) -> usize {
        match self {
            Images::Narrow(v) => v.capacity() * size_of::<[i16; D]>(),
            Images::Wide(v) => v.capacity() * size_of::<[i32; D]>(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_widen_when_one_leaves_16_bits_and_keep_their_values() {
        let mut im = Images::<2>::new(3);
        for _ in 0..i16::MAX {
            im.add(1, 0, 1);
        }
        im.add(2, 1, -5);
        assert!(matches!(im, Images::Narrow(_)));
        assert_eq!(im.memory_bytes(), 12);
        im.add(1, 0, 1);
        assert!(matches!(im, Images::Wide(_)));
        assert_eq!(im.get(1), [32768, 0]);
        assert_eq!(im.get(2), [0, -5]);
        assert_eq!(im.get(0), [0, 0]);
        im.add(0, 1, i32::MAX);
        im.add(0, 1, 1);
        assert_eq!(im.get(0), [0, i32::MIN], "wraps at 32 bits");
        assert!(matches!(
            Images::<2>::from_vec(vec![[1, -2], [i16::MIN as i32, 3]]),
            Images::Narrow(_)
        ));
        let wide = Images::<2>::from_vec(vec![[1, -2], [40_000, 3]]);
        assert!(matches!(wide, Images::Wide(_)));
        assert_eq!(wide.get(1), [40_000, 3]);
    }
}
