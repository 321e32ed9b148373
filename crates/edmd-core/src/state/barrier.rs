//! Internal walls: flat barriers across the box, optionally with a door and a demon.

/// Maxwell's demon at a door: which discs it lets through.
///
/// A disc reaching the open door from the low side (coordinate below the barrier) passes only
/// if `m v^2 >= fast * <m v^2>`; from the high side only if `m v^2 <= slow * <m v^2>`, where
/// `<m v^2>` is the mean over all discs (constant: the demon never changes kinetic energy).
/// Otherwise the door is shut for it and it bounces as off the wall.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Demon {
    /// Threshold, relative to the mean, for passing from the low to the high side.
    pub fast: f64,
    /// Threshold, relative to the mean, for passing from the high to the low side.
    pub slow: f64,
}

/// A flat wall of zero thickness across the whole box, perpendicular to `axis` at `position`.
///
/// With a `door` `(lo, hi)` (along the other axis), the stretch between `lo` and `hi` is open;
/// the door's two edges are points that discs bounce off. A disc goes through the door only if
/// it does not touch either edge.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Barrier {
    /// Axis the barrier is perpendicular to (0: a vertical barrier at `x = position`).
    pub axis: usize,
    /// Coordinate of the barrier on that axis.
    pub position: f64,
    /// The open stretch `(lo, hi)` along the other axis, if any.
    pub door: Option<(f64, f64)>,
    /// A demon keeping the door, if any (needs a door).
    pub demon: Option<Demon>,
}

impl Barrier {
    /// A solid barrier (a partition) perpendicular to `axis` at `position`.
    pub fn solid(axis: usize, position: f64) -> Self {
        Barrier {
            axis,
            position,
            door: None,
            demon: None,
        }
    }
}
