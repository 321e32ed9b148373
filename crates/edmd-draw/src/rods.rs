//! Rods on a line (1D systems), drawn as a strip: the line `[0, L]` across the image, each rod
//! a horizontal bar from `x - r` to `x + r` in its colour, a rod too short to show (under two
//! pixels) as a short vertical tick so that it is still seen, walls as heavy end marks and
//! periodic ends as thin ones, a rod that sticks out of a periodic end drawn on both sides.

use edmd_core::Simulation;
use tiny_skia::{Color, PathBuilder, Pixmap, Rect, Stroke, Transform};

use crate::{colours, paint, Colouring, BACKGROUND, OUTSIDE, WALL};

/// A snapshot of a 1D system.
#[derive(Clone, Debug, Default)]
pub struct SceneLine {
    /// The line's length.
    pub length: f64,
    /// Whether the line's ends are periodic (else walls).
    pub periodic: bool,
    /// Rod centres.
    pub positions: Vec<f64>,
    /// Rod half-lengths.
    pub radii: Vec<f64>,
    /// Rod colours.
    pub colours: Vec<[u8; 3]>,
}

impl SceneLine {
    /// The simulation at its current time, coloured as asked (as [`crate::Scene::capture`]);
    /// for a system of more dimensions, its projection on the x axis.
    pub fn capture<const D: usize>(sim: &Simulation<D>, colouring: Colouring) -> Self {
        let n = sim.len();
        let b = sim.sim_box();
        SceneLine {
            length: b.lengths[0],
            periodic: b.is_periodic(0),
            positions: (0..n).map(|i| sim.position(i)[0]).collect(),
            radii: (0..n).map(|i| sim.radius(i)).collect(),
            colours: colours(sim, colouring),
        }
    }
}

/// Where the line lies in an image: pixel x of `x = 0`, pixels per unit length, and the pixel
/// row of the line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineViewport {
    /// Pixel x of world x = 0.
    pub x0: f64,
    /// Pixels per unit length.
    pub scale: f64,
    /// Pixel y of the line.
    pub y: f64,
    /// Half the bars' thickness in pixels.
    pub half_height: f64,
}

impl LineViewport {
    /// The whole line across `width` pixels with a margin, in the middle of `height`.
    pub fn fit(length: f64, width: u32, height: u32) -> Self {
        let margin = 8.0;
        let scale = ((width as f64 - 2.0 * margin) / length).max(f64::MIN_POSITIVE);
        LineViewport {
            x0: margin,
            scale,
            y: height as f64 / 2.0,
            half_height: (height as f64 / 6.0).clamp(1.0, 12.0),
        }
    }

    /// Pixel x of a point on the line.
    pub fn to_pixel(&self, x: f64) -> f32 {
        (self.x0 + x * self.scale) as f32
    }

    /// The point on the line at pixel x.
    pub fn to_world(&self, px: f64) -> f64 {
        (px - self.x0) / self.scale
    }
}

/// Draws `scene` into a new `width` x `height` image (a strip: wide and low suits it).
pub fn draw_line(scene: &SceneLine, width: u32, height: u32) -> Pixmap {
    let mut pm = Pixmap::new(width.max(1), height.max(1)).expect("non-zero size");
    draw_line_into(scene, &mut pm);
    pm
}

/// Draws `scene` into an existing image.
pub fn draw_line_into(scene: &SceneLine, pm: &mut Pixmap) {
    let [or, og, ob] = OUTSIDE;
    pm.fill(Color::from_rgba8(or, og, ob, 255));
    let vp = LineViewport::fit(scene.length, pm.width(), pm.height());
    let (left, right) = (vp.to_pixel(0.0), vp.to_pixel(scene.length));
    let (top, bottom) = (
        (vp.y - 2.0 * vp.half_height) as f32,
        (vp.y + 2.0 * vp.half_height) as f32,
    );
    if let Some(r) = Rect::from_ltrb(left, top, right, bottom) {
        pm.fill_rect(r, &paint(BACKGROUND), Transform::identity(), None);
    }
    // The line itself, thin, under the rods.
    stroke(
        pm,
        [(left, vp.y as f32), (right, vp.y as f32)],
        1.0,
        [150, 150, 150],
    );
    for (i, &x) in scene.positions.iter().enumerate() {
        let colour = scene.colours.get(i).copied().unwrap_or([0, 0, 0]);
        let r = scene.radii.get(i).copied().unwrap_or(0.0);
        let shifts: &[f64] = if scene.periodic {
            &[-1.0, 0.0, 1.0]
        } else {
            &[0.0]
        };
        for &k in shifts {
            let c = x + k * scene.length;
            let (a, b) = (c - r, c + r);
            if b < 0.0 || a > scene.length {
                continue;
            }
            let (pa, pb) = (vp.to_pixel(a.max(0.0)), vp.to_pixel(b.min(scene.length)));
            if (vp.to_pixel(b) - vp.to_pixel(a)) < 2.0 {
                // Too short to see as a bar: a tick across the line.
                let px = vp.to_pixel(c);
                let h = (1.5 * vp.half_height) as f32;
                stroke(
                    pm,
                    [(px, vp.y as f32 - h), (px, vp.y as f32 + h)],
                    1.5,
                    colour,
                );
            } else if let Some(rect) = Rect::from_ltrb(
                pa,
                (vp.y - vp.half_height) as f32,
                pb,
                (vp.y + vp.half_height) as f32,
            ) {
                pm.fill_rect(rect, &paint(colour), Transform::identity(), None);
            }
        }
    }
    // The ends: walls heavy, periodic ends thin.
    let width = if scene.periodic { 0.5 } else { 3.0 };
    for px in [left, right] {
        stroke(pm, [(px, top), (px, bottom)], width, WALL);
    }
}

fn stroke(pm: &mut Pixmap, [a, b]: [(f32, f32); 2], width: f32, colour: [u8; 3]) {
    let mut pb = PathBuilder::new();
    pb.move_to(a.0, a.1);
    pb.line_to(b.0, b.1);
    if let Some(path) = pb.finish() {
        let s = Stroke {
            width,
            ..Stroke::default()
        };
        pm.stroke_path(&path, &paint(colour), &s, Transform::identity(), None);
    }
}

/// The rod under pixel x of a `width` x `height` image of `scene`, if any.
pub fn pick_line(scene: &SceneLine, width: u32, height: u32, px: f64) -> Option<usize> {
    let vp = LineViewport::fit(scene.length, width, height);
    let x = vp.to_world(px);
    let slack = 2.0 / vp.scale;
    scene.positions.iter().enumerate().find_map(|(i, &c)| {
        let r = scene.radii.get(i).copied().unwrap_or(0.0);
        ((x - c).abs() <= r + slack).then_some(i)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use edmd_core::{Disc, Options, SimBox, Vector};

    fn pixel(pm: &Pixmap, x: u32, y: u32) -> [u8; 3] {
        let c = pm.pixel(x, y).unwrap();
        [c.red(), c.green(), c.blue()]
    }

    #[test]
    fn rods_are_bars_on_the_line_and_a_point_is_a_tick() {
        // Line of 10 across 216 pixels: 20 pixels per unit from x = 8.
        let mut a = Disc::new(Vector([2.0]), Vector::ZERO, 1.0);
        a.colour = [200, 0, 0];
        let mut b = Disc::new(Vector([7.0]), Vector::ZERO, 1e-6);
        b.colour = [0, 0, 200];
        let sim = Simulation::new(&[a, b], SimBox::walls([10.0]), Options::default()).unwrap();
        let scene = SceneLine::capture(&sim, Colouring::File);
        let pm = draw_line(&scene, 216, 60);
        // The bar spans x in [1, 3] (pixels 28 to 68) at the line's row (30).
        assert_eq!(pixel(&pm, 48, 30), [200, 0, 0]);
        assert_eq!(pixel(&pm, 30, 36), [200, 0, 0]);
        assert_ne!(pixel(&pm, 80, 30), [200, 0, 0]);
        // The point at x = 7 (pixel 148) is a vertical tick (anti-aliased), taller than the
        // bars.
        let [r, _, b] = pixel(&pm, 148, 30 - 13);
        assert!(b > 150 && r < 100, "{r} {b}");
        assert_eq!(pick_line(&scene, 216, 60, 48.0), Some(0));
        assert_eq!(pick_line(&scene, 216, 60, 148.0), Some(1));
        assert_eq!(pick_line(&scene, 216, 60, 100.0), None);
    }

    #[test]
    fn a_rod_across_a_periodic_end_is_drawn_at_both_ends() {
        let mut a = Disc::new(Vector([9.8]), Vector::ZERO, 0.5);
        a.colour = [0, 150, 0];
        let sim = Simulation::new(&[a], SimBox::periodic([10.0]), Options::default()).unwrap();
        let pm = draw_line(&SceneLine::capture(&sim, Colouring::File), 216, 60);
        // [9.3, 10.3]: pixels 194 to 208 on the right, and [0, 0.3] (8 to 14) on the left.
        assert_eq!(pixel(&pm, 200, 30), [0, 150, 0]);
        assert_eq!(pixel(&pm, 11, 30), [0, 150, 0]);
    }
}
