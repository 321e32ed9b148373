//! # edmd-draw: one picture of a hard-disc system
//!
//! Spheres (3D systems) are drawn by [`draw3`] from a [`Scene3`]: shaded, back to front, in an
//! orthographic [`View`] from any direction, or as a slice. Rods on a line (1D systems) are
//! drawn by [`draw_line`] from a [`SceneLine`]: a strip with each rod a bar.
//!
//! The viewer window and the offline renderer both call [`draw`], so they show the same
//! picture: the box, every disc to scale in its colour (or coloured by speed, species or
//! potential energy), the bonds of a stepped potential's pairs (optional,
//! [`Scene::with_bonds`]), the internal barriers with their doors, and the trails of tagged
//! discs. Drawing only reads a
//! [`Scene`], a snapshot built from a simulation ([`Scene::capture`]); rendering never lives in
//! the engine.
//!
//! ```
//! use edmd_core::{Disc, Options, SimBox, Simulation, Vector};
//! use edmd_draw::{draw, Colouring, Scene};
//!
//! let discs = [Disc::new(Vector::new([0.5, 0.5]), Vector::ZERO, 0.1)];
//! let sim = Simulation::new(&discs, SimBox::unit(), Options::default()).unwrap();
//! let pixmap = draw(&Scene::capture(&sim, Colouring::File), 200, 200);
//! assert_eq!((pixmap.width(), pixmap.height()), (200, 200));
//! ```

#![forbid(unsafe_code)]

mod rods;
mod spheres;
pub use rods::{draw_line, draw_line_into, pick_line, LineViewport, SceneLine};
pub use spheres::{draw3, draw3_into, slice, Scene3, View};

/// A scene of either kind, for code that shows both (the viewer).
#[derive(Clone, Debug)]
pub enum AnyScene {
    /// Discs.
    Flat(Scene),
    /// Spheres, and how to look at them.
    Solid(Scene3, View),
    /// Rods on a line.
    Line(SceneLine),
}

impl Default for AnyScene {
    fn default() -> Self {
        AnyScene::Flat(Scene::default())
    }
}

/// Draws either kind of scene into an existing image.
pub fn draw_any_into(scene: &AnyScene, pm: &mut Pixmap) {
    match scene {
        AnyScene::Flat(s) => draw_into(s, pm),
        AnyScene::Solid(s, view) => draw3_into(s, *view, pm),
        AnyScene::Line(s) => draw_line_into(s, pm),
    }
}

use edmd_core::{Barrier, Simulation, Vector};
pub use tiny_skia::Pixmap;
use tiny_skia::{Color, Paint, PathBuilder, Rect, Stroke, Transform};

/// How discs are coloured.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Colouring {
    /// The colours from the file.
    #[default]
    File,
    /// By speed, blue (slow) to red (fast), relative to the root mean square speed.
    Speed,
    /// By species, in the colours reaction products take ([`edmd_core::species_colour`]).
    Species,
    /// By potential energy (stepped potentials): each disc's
    /// [`Simulation::potential_energy_of`] on a diverging scale centred on zero, grey for a disc
    /// in no pair's well or shoulder, blue for bound (negative), red for repelled (positive),
    /// darkest at [`energy_scale`]. The scale comes from the potential alone, so a colour means
    /// the same energy in every frame of a film. All grey without a stepped potential.
    Energy,
}

/// Colour of the bonds between the discs of a pair inside a well or shoulder (drawn
/// semi-transparent, with [`BOND_ALPHA`]).
pub const BOND: [u8; 3] = [230, 110, 20];
/// Opacity of bonds, 0 to 255.
pub const BOND_ALPHA: u8 = 200;

/// Background colour of the box.
pub const BACKGROUND: [u8; 3] = [255, 255, 255];
/// Colour outside the box.
pub const OUTSIDE: [u8; 3] = [236, 236, 240];
/// Colour of walls and barriers.
pub const WALL: [u8; 3] = [40, 40, 40];

/// A snapshot of what to draw.
#[derive(Clone, Debug, Default)]
pub struct Scene {
    /// Box edge lengths.
    pub lengths: [f64; 2],
    /// Which axes are periodic (drawn with dashed edges; discs near them also drawn wrapped).
    pub periodic: [bool; 2],
    /// Disc centres.
    pub positions: Vec<Vector>,
    /// Disc radii.
    pub radii: Vec<f64>,
    /// Disc colours.
    pub colours: Vec<[u8; 3]>,
    /// Internal barriers.
    pub barriers: Vec<Barrier>,
    /// Paths of tagged discs (oldest first), drawn as lines.
    pub trails: Vec<Vec<Vector>>,
    /// Discs to outline (tagged).
    pub highlighted: Vec<usize>,
    /// Pairs of discs (indices into `positions`) joined by a bond: a line between their
    /// centres, towards the nearest periodic image (see [`Scene::with_bonds`]).
    pub bonds: Vec<[usize; 2]>,
}

impl Scene {
    /// The simulation at its current time, coloured as asked (for a 3D simulation, its
    /// projection on the xy plane; [`Scene3`] draws spheres properly).
    pub fn capture<const D: usize>(sim: &Simulation<D>, colouring: Colouring) -> Self {
        let n = sim.len();
        let colours = colours(sim, colouring);
        let b = sim.sim_box();
        Scene {
            lengths: [b.lengths[0], b.lengths[1]],
            periodic: [b.is_periodic(0), b.is_periodic(1)],
            positions: (0..n)
                .map(|i| {
                    let p = sim.position(i);
                    Vector::new([p[0], p[1]])
                })
                .collect(),
            radii: (0..n).map(|i| sim.radius(i)).collect(),
            colours,
            barriers: sim.barriers().to_vec(),
            trails: Vec::new(),
            highlighted: Vec::new(),
            bonds: Vec::new(),
        }
    }

    /// The scene with a bond for every pair of `sim` inside at least one step of its stepped
    /// potential ([`bonds`]; none for hard discs). `sim` must be the simulation captured.
    pub fn with_bonds<const D: usize>(mut self, sim: &Simulation<D>) -> Self {
        self.bonds = bonds(sim);
        self
    }
}

/// The pairs of discs inside at least one step of `sim`'s stepped potential (a well or a
/// shoulder), each once, `[i, j]` with `i < j`; empty for hard discs.
pub fn bonds<const D: usize>(sim: &Simulation<D>) -> Vec<[usize; 2]> {
    if !sim.is_stepped() {
        return Vec::new();
    }
    let mut out = Vec::new();
    for i in 0..sim.len() {
        for (j, _) in sim.partners_of(i) {
            if j > i {
                out.push([i, j]);
            }
        }
    }
    out
}

/// The colour of every disc of `sim` for `colouring`.
pub(crate) fn colours<const D: usize>(sim: &Simulation<D>, colouring: Colouring) -> Vec<[u8; 3]> {
    let n = sim.len();
    match colouring {
        Colouring::File => (0..n).map(|i| sim.colour(i)).collect(),
        Colouring::Species => (0..n)
            .map(|i| edmd_core::species_colour(sim.species(i)))
            .collect(),
        Colouring::Speed => {
            let rms =
                ((0..n).map(|i| sim.velocity(i).norm2()).sum::<f64>() / n.max(1) as f64).sqrt();
            (0..n)
                .map(|i| {
                    speed_colour(
                        sim.velocity(i).norm2().sqrt() / (2.0 * rms).max(f64::MIN_POSITIVE),
                    )
                })
                .collect()
        }
        Colouring::Energy => {
            let scale = energy_scale(sim);
            (0..n)
                .map(|i| energy_colour(sim.potential_energy_of(i) / scale))
                .collect()
        }
    }
}

/// The potential energy of one disc at which [`Colouring::Energy`] reaches its darkest
/// colours: the largest magnitude a pair's energy can have (over the shells of every pair of
/// species of the potential) times 6 in 2D or 12 in 3D, the neighbours of a disc in a close
/// packing. A square-well disc with six partners in 2D (twelve in 3D) is the darkest blue.
/// 1 without a stepped potential (every energy is 0 then).
pub fn energy_scale<const D: usize>(sim: &Simulation<D>) -> f64 {
    let Some(potential) = sim.potential() else {
        return 1.0;
    };
    // A pair inside the outermost k steps has the sum of their energies.
    let mut most: f64 = 0.0;
    for pair in &potential.pairs {
        let mut u = 0.0;
        for step in pair.steps.iter().rev() {
            u += step.energy;
            most = most.max(u.abs());
        }
    }
    let neighbours = if D == 3 { 12.0 } else { 6.0 };
    if most > 0.0 && most.is_finite() {
        most * neighbours
    } else {
        1.0
    }
}

/// The viridis colormap from 0 to 0.9, sampled at equal steps: dark purple, blue, teal, green,
/// yellow-green. Every colour stays visible on the white background (viridis' last tenth, bright
/// yellow, would not), and lightness rises steadily, so speeds read the same in grey.
const SPEED_STOPS: [[f64; 3]; 10] = [
    [68.0, 1.0, 84.0],
    [72.0, 40.0, 120.0],
    [62.0, 74.0, 137.0],
    [49.0, 104.0, 142.0],
    [38.0, 130.0, 142.0],
    [31.0, 158.0, 137.0],
    [53.0, 183.0, 121.0],
    [110.0, 206.0, 88.0],
    [160.0, 218.0, 57.0],
    [189.0, 223.0, 38.0],
];

/// The speed colour for `x` from 0 (slow, dark purple) to 1 (fast, yellow-green), clamped: the
/// viridis colormap up to 0.9 (see `SPEED_STOPS`). The old blue-white-red scale drew
/// mid-speed discs nearly white, invisible on the white background.
pub fn speed_colour(x: f64) -> [u8; 3] {
    let x = if x.is_nan() { 0.0 } else { x.clamp(0.0, 1.0) };
    ramp(&SPEED_STOPS, x)
}

/// The diverging potential-energy scale: from the bound end (`x = -1`, dark blue) through
/// grey (`x = 0`, a disc in no pair's step) to the repelled end (`x = 1`, dark red), clamped.
/// The grey and the palest tints stay visible on the white background.
const ENERGY_NEGATIVE: [[f64; 3]; 5] = [
    [165.0, 165.0, 170.0],
    [115.0, 155.0, 205.0],
    [55.0, 115.0, 190.0],
    [30.0, 70.0, 155.0],
    [15.0, 30.0, 100.0],
];
const ENERGY_POSITIVE: [[f64; 3]; 5] = [
    [165.0, 165.0, 170.0],
    [225.0, 145.0, 115.0],
    [210.0, 75.0, 55.0],
    [165.0, 25.0, 35.0],
    [100.0, 0.0, 25.0],
];

/// The energy colour for `x` from -1 (most bound, dark blue) through 0 (grey) to 1 (most
/// repelled, dark red), clamped; `x` is a disc's potential energy over [`energy_scale`].
pub fn energy_colour(x: f64) -> [u8; 3] {
    let x = if x.is_nan() { 0.0 } else { x.clamp(-1.0, 1.0) };
    let stops = if x < 0.0 {
        &ENERGY_NEGATIVE
    } else {
        &ENERGY_POSITIVE
    };
    ramp(stops, x.abs())
}

/// Linear interpolation along equally spaced colour stops, `x` in `[0, 1]`.
fn ramp(stops: &[[f64; 3]], x: f64) -> [u8; 3] {
    let f = x * (stops.len() - 1) as f64;
    let k = (f.floor() as usize).min(stops.len() - 2);
    let t = f - k as f64;
    let (a, b) = (stops[k], stops[k + 1]);
    let lerp = |c: usize| (a[c] + (b[c] - a[c]) * t).round() as u8;
    [lerp(0), lerp(1), lerp(2)]
}

/// Where the box lands in an image: world `(x, y)` (y up) to pixels (y down), and back.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Viewport {
    /// Pixels per box length unit.
    pub scale: f64,
    /// Pixel x of world x = 0.
    pub x0: f64,
    /// Pixel y of world y = 0.
    pub y0: f64,
}

impl Viewport {
    /// The largest view of the box that fits `width` x `height` pixels with a small margin.
    pub fn fit(lengths: [f64; 2], width: u32, height: u32) -> Self {
        let margin = 4.0;
        let (w, h) = (width as f64 - 2.0 * margin, height as f64 - 2.0 * margin);
        let scale = (w / lengths[0]).min(h / lengths[1]).max(f64::MIN_POSITIVE);
        let x0 = (width as f64 - scale * lengths[0]) / 2.0;
        let y0 = (height as f64 + scale * lengths[1]) / 2.0;
        Viewport { scale, x0, y0 }
    }

    /// Pixel coordinates of a world point.
    pub fn to_pixel(&self, p: Vector) -> (f32, f32) {
        (
            (self.x0 + p[0] * self.scale) as f32,
            (self.y0 - p[1] * self.scale) as f32,
        )
    }

    /// World coordinates of a pixel.
    pub fn to_world(&self, px: f64, py: f64) -> Vector {
        Vector::new([(px - self.x0) / self.scale, (self.y0 - py) / self.scale])
    }
}

pub(crate) fn paint(rgb: [u8; 3]) -> Paint<'static> {
    let mut p = Paint::default();
    p.set_color_rgba8(rgb[0], rgb[1], rgb[2], 255);
    p.anti_alias = true;
    p
}

/// Draws `scene` into a new `width` x `height` image.
pub fn draw(scene: &Scene, width: u32, height: u32) -> Pixmap {
    let mut pm = Pixmap::new(width.max(1), height.max(1)).expect("non-zero size");
    draw_into(scene, &mut pm);
    pm
}

/// Draws `scene` into an existing image (the viewer reuses one per frame).
pub fn draw_into(scene: &Scene, pm: &mut Pixmap) {
    let [or, og, ob] = OUTSIDE;
    pm.fill(Color::from_rgba8(or, og, ob, 255));
    let vp = Viewport::fit(scene.lengths, pm.width(), pm.height());
    let (x0, y1) = vp.to_pixel(Vector::ZERO);
    let (x1, y0) = vp.to_pixel(Vector::new(scene.lengths));
    if let Some(r) = Rect::from_ltrb(x0, y0, x1, y1) {
        pm.fill_rect(r, &paint(BACKGROUND), Transform::identity(), None);
    }
    // Discs, with their periodic images where they stick out of the box. Filled by hand:
    // coverage from the distance to the centre, which for thousands of small discs is many
    // times cheaper than filling a path per disc (measured: 47 ms -> a few ms per frame at
    // N = 10^4, see the viewer's draw_bench example).
    for (i, &p) in scene.positions.iter().enumerate() {
        let colour = scene.colours.get(i).copied().unwrap_or([0, 0, 0]);
        let r = scene.radii[i];
        let rp = (r * vp.scale).max(0.5);
        for shift in images(p, r, scene) {
            let (cx, cy) = vp.to_pixel(p + shift);
            fill_disc(pm, cx as f64, cy as f64, rp, colour);
        }
    }
    draw_bonds(scene, &vp, pm);
    // Trails and highlighted discs.
    for trail in &scene.trails {
        let mut pb = PathBuilder::new();
        let mut last: Option<Vector> = None;
        for &p in trail {
            let (x, y) = vp.to_pixel(p);
            // A jump across a periodic boundary is not a line across the box.
            if last.is_none_or(|q| {
                (p - q).norm2().sqrt() > 0.5 * scene.lengths[0].min(scene.lengths[1])
            }) {
                pb.move_to(x, y);
            } else {
                pb.line_to(x, y);
            }
            last = Some(p);
        }
        if let Some(path) = pb.finish() {
            let stroke = Stroke {
                width: 1.5,
                ..Stroke::default()
            };
            pm.stroke_path(
                &path,
                &paint([200, 30, 30]),
                &stroke,
                Transform::identity(),
                None,
            );
        }
    }
    for &i in &scene.highlighted {
        if let (Some(&p), Some(&r)) = (scene.positions.get(i), scene.radii.get(i)) {
            let (cx, cy) = vp.to_pixel(p);
            if let Some(path) = PathBuilder::from_circle(cx, cy, (r * vp.scale) as f32 + 1.5) {
                let stroke = Stroke {
                    width: 2.0,
                    ..Stroke::default()
                };
                pm.stroke_path(
                    &path,
                    &paint([0, 0, 0]),
                    &stroke,
                    Transform::identity(),
                    None,
                );
            }
        }
    }
    // Walls (solid) or periodic edges (thin), then barriers with their doors.
    let edge = |periodic: bool| Stroke {
        width: if periodic { 0.5 } else { 2.0 },
        ..Stroke::default()
    };
    for (axis, &periodic) in scene.periodic.iter().enumerate() {
        let mut pb = PathBuilder::new();
        let (ax, ay) = vp.to_pixel(Vector::ZERO);
        let far = if axis == 0 {
            Vector::new([0.0, scene.lengths[1]])
        } else {
            Vector::new([scene.lengths[0], 0.0])
        };
        let (bx, by) = vp.to_pixel(far);
        // Axis 0's walls are the vertical edges x = 0 and x = L.
        let shift = if axis == 0 {
            Vector::new([scene.lengths[0], 0.0])
        } else {
            Vector::new([0.0, scene.lengths[1]])
        };
        let (cx, cy) = vp.to_pixel(shift);
        let (dx, dy) = vp.to_pixel(far + shift);
        pb.move_to(ax, ay);
        pb.line_to(bx, by);
        pb.move_to(cx, cy);
        pb.line_to(dx, dy);
        if let Some(path) = pb.finish() {
            pm.stroke_path(
                &path,
                &paint(WALL),
                &edge(periodic),
                Transform::identity(),
                None,
            );
        }
    }
    for b in &scene.barriers {
        let other = 1 - b.axis;
        let len = scene.lengths[other];
        let pieces = match b.door {
            None => vec![(0.0, len)],
            Some((lo, hi)) => vec![(0.0, lo), (hi, len)],
        };
        let mut pb = PathBuilder::new();
        for (s, e) in pieces {
            let mut p = Vector::ZERO;
            p[b.axis] = b.position;
            p[other] = s;
            let mut q = p;
            q[other] = e;
            let (ax, ay) = vp.to_pixel(p);
            let (bx, by) = vp.to_pixel(q);
            pb.move_to(ax, ay);
            pb.line_to(bx, by);
        }
        if let Some(path) = pb.finish() {
            let stroke = Stroke {
                width: 3.0,
                ..Stroke::default()
            };
            let colour = if b.demon.is_some() {
                [120, 40, 160]
            } else {
                WALL
            };
            pm.stroke_path(&path, &paint(colour), &stroke, Transform::identity(), None);
        }
    }
}

/// Draws the bonds of `scene` over its discs: thin, semi-transparent, from centre to centre.
/// A bond across a periodic edge is drawn as two halves, from each disc towards its partner's
/// nearest image, each cut at the edge of the box.
fn draw_bonds(scene: &Scene, vp: &Viewport, pm: &mut Pixmap) {
    if scene.bonds.is_empty() {
        return;
    }
    let mut pieces = Vec::new();
    for &[i, j] in &scene.bonds {
        let (Some(p), Some(q)) = (scene.positions.get(i), scene.positions.get(j)) else {
            continue;
        };
        bond_pieces(
            p.0,
            q.0,
            [0.0, 0.0],
            scene.lengths,
            scene.periodic,
            &mut pieces,
        );
    }
    let mut pb = PathBuilder::new();
    for (a, b) in pieces {
        let (ax, ay) = vp.to_pixel(Vector::new(a));
        let (bx, by) = vp.to_pixel(Vector::new(b));
        pb.move_to(ax, ay);
        pb.line_to(bx, by);
    }
    let mean_r = scene.radii.iter().sum::<f64>() / scene.radii.len().max(1) as f64;
    stroke_bonds(pb, bond_width(mean_r * vp.scale), pm);
}

/// Width in pixels of the bonds between discs of radius `r` pixels.
pub(crate) fn bond_width(r: f64) -> f32 {
    (0.3 * r).clamp(1.0, 4.0) as f32
}

/// Strokes the segments of `pb` as bonds (one path: where bonds cross, the colour is not laid
/// twice).
pub(crate) fn stroke_bonds(pb: PathBuilder, width: f32, pm: &mut Pixmap) {
    if let Some(path) = pb.finish() {
        // A faint light edge under the line keeps it apart from discs of a like colour.
        for (rgb, alpha, w) in [
            ([255, 255, 255], 90, width + 1.2),
            (BOND, BOND_ALPHA, width),
        ] {
            let mut paint = paint(rgb);
            paint.set_color_rgba8(rgb[0], rgb[1], rgb[2], alpha);
            let stroke = Stroke {
                width: w,
                line_cap: tiny_skia::LineCap::Round,
                ..Stroke::default()
            };
            pm.stroke_path(&path, &paint, &stroke, Transform::identity(), None);
        }
    }
}

/// The segments to draw for a bond between centres `p` and `q` in a box of edge `lengths`,
/// trimmed by `trim[0]` at `p`'s end and `trim[1]` at `q`'s (the radii, to start the bond at
/// the surfaces; 0 for centre to centre). The bond runs from `p` towards `q`'s nearest image;
/// when that image lies across a periodic face, the bond is drawn twice, from `p` and from `q`
/// towards each other's image, each cut at the box's faces.
pub(crate) fn bond_pieces<const N: usize>(
    p: [f64; N],
    q: [f64; N],
    trim: [f64; 2],
    lengths: [f64; N],
    periodic: [bool; N],
    out: &mut Vec<([f64; N], [f64; N])>,
) {
    let mut d: [f64; N] = std::array::from_fn(|a| q[a] - p[a]);
    let mut wrapped = false;
    for a in 0..N {
        if periodic[a] && lengths[a] > 0.0 {
            let k = (d[a] / lengths[a]).round();
            if k != 0.0 {
                d[a] -= k * lengths[a];
                wrapped = true;
            }
        }
    }
    let dist = d.iter().map(|c| c * c).sum::<f64>().sqrt();
    if dist.is_nan() || dist <= trim[0] + trim[1] {
        return;
    }
    let u: [f64; N] = std::array::from_fn(|a| d[a] / dist);
    let from: [f64; N] = std::array::from_fn(|a| p[a] + trim[0] * u[a]);
    let to: [f64; N] = std::array::from_fn(|a| p[a] + d[a] - trim[1] * u[a]);
    if !wrapped {
        out.push((from, to));
        return;
    }
    // The same bond seen from `q`: shifted by the periodic translation between `q` and the
    // image of it that `p` is bonded to.
    let back = |v: [f64; N]| -> [f64; N] { std::array::from_fn(|a| v[a] + q[a] - p[a] - d[a]) };
    for (a, b) in [(from, to), (back(from), back(to))] {
        if let Some(piece) = clip_to_box(a, b, lengths) {
            out.push(piece);
        }
    }
}

/// The part of the segment from `a` to `b` inside the box `[0, L]` on every axis, if any
/// (Liang and Barsky's clipping).
fn clip_to_box<const N: usize>(
    a: [f64; N],
    b: [f64; N],
    lengths: [f64; N],
) -> Option<([f64; N], [f64; N])> {
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for k in 0..N {
        let d = b[k] - a[k];
        // The segment is inside where p t <= q for each side.
        for (p, q) in [(-d, a[k]), (d, lengths[k] - a[k])] {
            if p == 0.0 {
                if q < 0.0 {
                    return None;
                }
            } else if p < 0.0 {
                t0 = t0.max(q / p);
            } else {
                t1 = t1.min(q / p);
            }
        }
    }
    let at = |t: f64| -> [f64; N] {
        std::array::from_fn(|k| (a[k] + (b[k] - a[k]) * t).clamp(0.0, lengths[k]))
    };
    (t0 < t1).then(|| (at(t0), at(t1)))
}

/// Fills a disc of radius `r` pixels centred at `(cx, cy)` (pixel `(x, y)` covers
/// `[x, x + 1) x [y, y + 1)`), antialiased by the covered fraction `r + 1/2 - d` of each pixel,
/// `d` the distance of the pixel's centre from the disc's; opaque colours over opaque pixels.
fn fill_disc(pm: &mut Pixmap, cx: f64, cy: f64, r: f64, colour: [u8; 3]) {
    let (w, h) = (pm.width() as i64, pm.height() as i64);
    let x0 = ((cx - r - 1.0).floor() as i64).max(0);
    let x1 = ((cx + r + 1.0).ceil() as i64).min(w - 1);
    let y0 = ((cy - r - 1.0).floor() as i64).max(0);
    let y1 = ((cy + r + 1.0).ceil() as i64).min(h - 1);
    if x0 > x1 || y0 > y1 {
        return;
    }
    let pixels = pm.pixels_mut();
    for y in y0..=y1 {
        let dy = y as f64 + 0.5 - cy;
        let row = (y * w) as usize;
        for x in x0..=x1 {
            let dx = x as f64 + 0.5 - cx;
            let cov = (r + 0.5 - (dx * dx + dy * dy).sqrt()).clamp(0.0, 1.0);
            if cov <= 0.0 {
                continue;
            }
            let dst = &mut pixels[row + x as usize];
            let mix = |s: u8, d: u8| (s as f64 * cov + d as f64 * (1.0 - cov)).round() as u8;
            let c = [
                mix(colour[0], dst.red()),
                mix(colour[1], dst.green()),
                mix(colour[2], dst.blue()),
            ];
            if let Some(p) = tiny_skia::PremultipliedColorU8::from_rgba(c[0], c[1], c[2], 255) {
                *dst = p;
            }
        }
    }
}

/// The image shifts at which a disc must be drawn: itself, plus images across each periodic
/// edge it overlaps.
fn images(p: Vector, r: f64, scene: &Scene) -> Vec<Vector> {
    let mut shifts = vec![Vector::ZERO];
    for a in 0..2 {
        if !scene.periodic[a] {
            continue;
        }
        let l = scene.lengths[a];
        let extra = if p[a] < r {
            Some(l)
        } else if p[a] > l - r {
            Some(-l)
        } else {
            None
        };
        if let Some(s) = extra {
            let more: Vec<Vector> = shifts
                .iter()
                .map(|v| {
                    let mut w = *v;
                    w[a] += s;
                    w
                })
                .collect();
            shifts.extend(more);
        }
    }
    shifts
}

/// Index of the disc under the pixel `(px, py)` of a `width` x `height` image, if any.
pub fn pick(scene: &Scene, width: u32, height: u32, px: f64, py: f64) -> Option<usize> {
    let vp = Viewport::fit(scene.lengths, width, height);
    let w = vp.to_world(px, py);
    scene
        .positions
        .iter()
        .zip(&scene.radii)
        .enumerate()
        .filter(|(_, (p, r))| (**p - w).norm2() <= *r * *r)
        .map(|(i, _)| i)
        .next()
}

/// The image as straight (not premultiplied) RGBA bytes.
pub fn rgba(pm: &Pixmap) -> Vec<u8> {
    pm.clone().take_demultiplied()
}

#[cfg(test)]
mod tests {
    use super::*;
    use edmd_core::{Disc, Options, SimBox};

    fn rgb_at(pm: &Pixmap, x: u32, y: u32) -> [u8; 3] {
        let c = pm.pixel(x, y).unwrap().demultiply();
        [c.red(), c.green(), c.blue()]
    }

    fn scene(discs: &[Disc]) -> Scene {
        let sim = Simulation::new(discs, SimBox::unit(), Options::default()).unwrap();
        Scene::capture(&sim, Colouring::File)
    }

    #[test]
    fn a_disc_covers_the_pixels_it_should() {
        // Unit box in 208 x 208 pixels: margin 4, scale 200. Disc at (0.25, 0.75), r = 0.1:
        // centre pixel (54, 54), radius 20 pixels.
        let mut d = Disc::new(Vector::new([0.25, 0.75]), Vector::ZERO, 0.1);
        d.colour = [200, 30, 60];
        let pm = draw(&scene(&[d]), 208, 208);
        let vp = Viewport::fit([1.0, 1.0], 208, 208);
        assert_eq!(vp.to_pixel(Vector::new([0.25, 0.75])), (54.0, 54.0));
        for (x, y) in [(54, 54), (54 + 18, 54), (54, 54 - 18), (54 - 13, 54 + 13)] {
            assert_eq!(rgb_at(&pm, x, y), [200, 30, 60], "inside at ({x}, {y})");
        }
        for (x, y) in [(54 + 22, 54), (54, 54 + 22), (54 + 16, 54 + 16), (150, 150)] {
            assert_eq!(rgb_at(&pm, x, y), BACKGROUND, "outside at ({x}, {y})");
        }
        // The covered area is the disc's, pi r^2 = 1257 pixels, within antialiasing.
        let covered = (0..208)
            .flat_map(|x| (0..208).map(move |y| (x, y)))
            .filter(|&(x, y)| {
                let c = rgb_at(&pm, x, y);
                c[0] > 150 && c[1] < 128
            })
            .count();
        assert!(
            (covered as f64 - std::f64::consts::PI * 400.0).abs() < 60.0,
            "{covered}"
        );
    }

    #[test]
    fn an_empty_box_is_empty() {
        let pm = draw(&scene(&[]), 208, 208);
        for x in 10..198 {
            for y in 10..198 {
                assert_eq!(rgb_at(&pm, x, y), BACKGROUND);
            }
        }
        // The walls are drawn at the edges of the box, and outside is a different shade.
        assert_eq!(rgb_at(&pm, 4, 100), WALL);
        assert_eq!(rgb_at(&pm, 1, 100), OUTSIDE);
    }

    #[test]
    fn colour_by_speed_and_species() {
        let mut a = Disc::new(Vector::new([0.25, 0.5]), Vector::new([0.0, 0.0]), 0.1);
        let mut b = Disc::new(Vector::new([0.75, 0.5]), Vector::new([1.0, 0.0]), 0.1);
        a.species = 1;
        b.species = 2;
        let sim = Simulation::new(&[a, b], SimBox::unit(), Options::default()).unwrap();
        let s = Scene::capture(&sim, Colouring::Speed);
        assert_eq!(s.colours[0], speed_colour(0.0));
        assert_eq!(s.colours[1], speed_colour(1.0 / (2.0 * 0.5f64.sqrt())));
        let s = Scene::capture(&sim, Colouring::Species);
        // The colours reaction products take, so both views agree.
        assert_eq!(
            s.colours,
            vec![edmd_core::species_colour(1), edmd_core::species_colour(2)]
        );
    }

    /// Regression: `--colour speed` drew mid-speed discs nearly white on the white background.
    #[test]
    fn speed_colours_stay_visible_on_white() {
        for k in 0..=100 {
            let [r, g, b] = speed_colour(k as f64 / 100.0);
            let luma = 0.2126 * r as f64 + 0.7152 * g as f64 + 0.0722 * b as f64;
            assert!(luma < 215.0, "speed {k}%: ({r}, {g}, {b}) is too light");
        }
        assert_ne!(speed_colour(0.0), speed_colour(1.0));
    }

    /// A periodic box 10 x 10 (in 208 x 208 pixels: 20 pixels per unit) with a square well
    /// out to 1.5 between discs of radius 0.5: `discs` are `(x, y)`.
    fn well(discs: &[[f64; 2]]) -> Simulation {
        let discs: Vec<Disc> = discs
            .iter()
            .map(|&p| Disc::new(Vector::new(p), Vector::ZERO, 0.5))
            .collect();
        let potential = edmd_core::Potential::single(0, 0, 1.5, -1.0);
        Simulation::with_potential_at(
            &discs,
            SimBox::periodic([10.0, 10.0]),
            &[],
            &potential,
            Options::default(),
            0.0,
        )
        .unwrap()
    }

    fn is_bond(c: [u8; 3]) -> bool {
        c[0] > 180 && c[1] > 80 && c[1] < 160 && c[2] < 100
    }

    #[test]
    fn energy_colours_are_grey_at_zero_and_visible_on_white() {
        assert_eq!(energy_colour(0.0), [165, 165, 170]);
        assert_eq!(energy_colour(f64::NAN), energy_colour(0.0));
        let (bound, repelled) = (energy_colour(-1.0), energy_colour(1.0));
        assert!(bound[2] > bound[0] + 50, "{bound:?} is not blue");
        assert!(repelled[0] > repelled[2] + 50, "{repelled:?} is not red");
        assert_eq!(energy_colour(-5.0), bound);
        for k in -100..=100 {
            let [r, g, b] = energy_colour(k as f64 / 100.0);
            let luma = 0.2126 * r as f64 + 0.7152 * g as f64 + 0.0722 * b as f64;
            assert!(luma < 215.0, "energy {k}%: ({r}, {g}, {b}) is too light");
        }
    }

    #[test]
    fn energy_colouring_follows_each_discs_pairs() {
        // 0 and 1 are 1.2 apart (inside the well), 1 and 2 too; 3 is alone.
        let sim = well(&[[2.0, 5.0], [3.2, 5.0], [4.4, 5.0], [8.0, 8.0]]);
        assert_eq!(energy_scale(&sim), 6.0);
        let s = Scene::capture(&sim, Colouring::Energy);
        assert_eq!(
            s.colours,
            vec![
                energy_colour(-1.0 / 6.0),
                energy_colour(-2.0 / 6.0),
                energy_colour(-1.0 / 6.0),
                energy_colour(0.0)
            ]
        );
        assert_eq!(bonds(&sim), vec![[0, 1], [1, 2]]);
        assert!(s.bonds.is_empty());
        assert_eq!(s.with_bonds(&sim).bonds, vec![[0, 1], [1, 2]]);
        // Hard discs: no bonds, every disc grey.
        let hard = Simulation::new(
            &[Disc::new(Vector::new([0.5, 0.5]), Vector::ZERO, 0.1)],
            SimBox::unit(),
            Options::default(),
        )
        .unwrap();
        assert_eq!(energy_scale(&hard), 1.0);
        let s = Scene::capture(&hard, Colouring::Energy).with_bonds(&hard);
        assert!(s.bonds.is_empty());
        assert_eq!(s.colours, vec![energy_colour(0.0)]);
    }

    #[test]
    fn a_bond_is_drawn_between_the_discs() {
        let sim = well(&[[3.0, 5.0], [4.4, 5.0]]);
        let plain = draw(&Scene::capture(&sim, Colouring::File), 208, 208);
        let bonded = draw(
            &Scene::capture(&sim, Colouring::File).with_bonds(&sim),
            208,
            208,
        );
        // The gap between the surfaces, x from 3.5 to 3.9 (pixels 74 to 82) at y = 5 (104).
        assert_eq!(rgb_at(&plain, 78, 104), BACKGROUND);
        assert!(
            is_bond(rgb_at(&bonded, 78, 104)),
            "{:?}",
            rgb_at(&bonded, 78, 104)
        );
        // Thin: a few pixels above the line is background.
        assert_eq!(rgb_at(&bonded, 78, 109), BACKGROUND);
        // Nowhere else.
        assert_eq!(rgb_at(&bonded, 150, 104), BACKGROUND);
    }

    #[test]
    fn a_bond_across_a_periodic_edge_is_two_halves_at_the_edges() {
        // 0.3 and 9.5 are 0.8 apart across x = 0.
        let sim = well(&[[0.6, 5.0], [9.4, 5.0]]);
        let mut pieces = Vec::new();
        bond_pieces(
            [0.6, 5.0],
            [9.4, 5.0],
            [0.0, 0.0],
            [10.0, 10.0],
            [true, true],
            &mut pieces,
        );
        assert_eq!(
            pieces,
            vec![([0.6, 5.0], [0.0, 5.0]), ([10.0, 5.0], [9.4, 5.0])]
        );
        let pm = draw(
            &Scene::capture(&sim, Colouring::File).with_bonds(&sim),
            208,
            208,
        );
        // Inside the box next to both edges, between the disc and the edge: bond; across the
        // middle of the box: nothing.
        for x in [5, 202] {
            assert!(
                is_bond(rgb_at(&pm, x, 104)),
                "x = {x}: {:?}",
                rgb_at(&pm, x, 104)
            );
        }
        for x in [40, 104, 170] {
            assert_eq!(rgb_at(&pm, x, 104), BACKGROUND, "x = {x}");
        }
        // Not across a wall: one piece, the segment itself.
        let mut pieces = Vec::new();
        bond_pieces(
            [0.6, 5.0],
            [1.4, 5.5],
            [0.0, 0.0],
            [10.0, 10.0],
            [false, false],
            &mut pieces,
        );
        assert_eq!(pieces, vec![([0.6, 5.0], [1.4, 5.5])]);
    }

    #[test]
    fn clipping_keeps_the_part_inside_the_box() {
        let c = clip_to_box([-1.0, 1.0], [1.0, 1.0], [2.0, 2.0]).unwrap();
        assert_eq!(c, ([0.0, 1.0], [1.0, 1.0]));
        assert!(clip_to_box([-1.0, 1.0], [-0.5, 1.0], [2.0, 2.0]).is_none());
        let c = clip_to_box([1.0, 1.0, 1.0], [3.0, 1.0, 3.0], [2.0, 2.0, 2.0]).unwrap();
        assert_eq!(c, ([1.0, 1.0, 1.0], [2.0, 1.0, 2.0]));
    }

    #[test]
    fn picking_finds_the_disc_under_the_pointer() {
        let d = Disc::new(Vector::new([0.25, 0.75]), Vector::ZERO, 0.1);
        let s = scene(&[d]);
        assert_eq!(pick(&s, 208, 208, 60.0, 50.0), Some(0));
        assert_eq!(pick(&s, 208, 208, 150.0, 150.0), None);
    }
}
