//! Pictures of 3D systems: shaded spheres in an orthographic view, or a slice.
//!
//! [`View::Orbit`] looks at the box from a direction given by an azimuth (about the z axis,
//! from the x axis) and an elevation (above the xy plane), with z up on the screen. Spheres are
//! drawn back to front by their depth along the view direction, each shaded by hand (Lambert
//! diffuse light with an ambient term and a specular highlight from a light above, left and in
//! front of the viewer), with a darker rim so that touching spheres stay apart. The box is a
//! wireframe: the three edges hidden behind the spheres are drawn thin and light, the others
//! over everything. [`View::Slice`] cuts the box with a plane perpendicular to an axis and
//! draws the circles where the plane cuts the spheres, in the 2D picture's style, seen along
//! that axis.

use edmd_core::{Simulation, Vector};
use tiny_skia::{Color, PathBuilder, Pixmap, Stroke, Transform};

use crate::{
    bond_pieces, bond_width, colours, paint, stroke_bonds, Colouring, Scene, OUTSIDE, WALL,
};

/// A snapshot of a 3D system.
#[derive(Clone, Debug, Default)]
pub struct Scene3 {
    /// Box edge lengths.
    pub lengths: [f64; 3],
    /// Which axes are periodic.
    pub periodic: [bool; 3],
    /// Sphere centres (wrapped into the box).
    pub positions: Vec<[f64; 3]>,
    /// Sphere radii.
    pub radii: Vec<f64>,
    /// Sphere colours.
    pub colours: Vec<[u8; 3]>,
    /// Pairs of spheres (indices into `positions`) joined by a bond (see
    /// [`Scene3::with_bonds`]).
    pub bonds: Vec<[usize; 2]>,
}

impl Scene3 {
    /// The simulation at its current time, coloured as asked (as [`Scene::capture`]); a 2D
    /// simulation lies in the plane `z = 0` of a box of depth 0.
    pub fn capture<const D: usize>(sim: &Simulation<D>, colouring: Colouring) -> Self {
        let n = sim.len();
        let colours = colours(sim, colouring);
        let b = sim.sim_box();
        let pick = |v: &[f64], a: usize| if a < D { v[a] } else { 0.0 };
        Scene3 {
            lengths: std::array::from_fn(|a| pick(&b.lengths, a)),
            periodic: std::array::from_fn(|a| a < D && b.is_periodic(a)),
            positions: (0..n)
                .map(|i| {
                    let p = sim.position(i);
                    std::array::from_fn(|a| pick(&p.0, a))
                })
                .collect(),
            radii: (0..n).map(|i| sim.radius(i)).collect(),
            colours,
            bonds: Vec::new(),
        }
    }

    /// The scene with a bond for every pair of `sim` inside at least one step of its stepped
    /// potential ([`crate::bonds`]). In an orbit view a bond is a line between the spheres'
    /// surfaces, drawn in depth order with them; in a slice, a line between the centres of
    /// two circles cut from bonded spheres.
    pub fn with_bonds<const D: usize>(mut self, sim: &Simulation<D>) -> Self {
        self.bonds = crate::bonds(sim);
        self
    }
}

/// How a 3D scene is looked at.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum View {
    /// An orthographic view of the whole box from the direction at `azimuth` degrees about the
    /// z axis (0: from +x, 90: from +y) and `elevation` degrees above the xy plane (90: from
    /// above), z up on the screen.
    Orbit {
        /// Degrees about the z axis, from the x axis.
        azimuth: f64,
        /// Degrees above the xy plane, in `[-90, 90]`.
        elevation: f64,
    },
    /// The plane perpendicular to `axis` (0, 1, 2) at `position`, seen along that axis.
    Slice {
        /// The axis the plane is perpendicular to.
        axis: usize,
        /// Where the plane cuts that axis.
        position: f64,
    },
}

impl Default for View {
    /// An oblique view that shows three faces of the box.
    fn default() -> Self {
        View::Orbit {
            azimuth: 30.0,
            elevation: 20.0,
        }
    }
}

/// An orthographic camera: screen axes `right` and `up`, and `back` towards the viewer.
#[derive(Clone, Copy, Debug)]
struct Camera {
    right: [f64; 3],
    up: [f64; 3],
    back: [f64; 3],
    centre: [f64; 3],
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

impl Camera {
    fn new(lengths: [f64; 3], azimuth: f64, elevation: f64) -> Self {
        let (az, el) = (
            azimuth.to_radians(),
            elevation.clamp(-90.0, 90.0).to_radians(),
        );
        let back = [el.cos() * az.cos(), el.cos() * az.sin(), el.sin()];
        // right = z x back, normalised; straight from above or below, the screen's right is
        // the direction of the azimuth turned by 90 degrees.
        let mut right = [-back[1], back[0], 0.0];
        let norm = dot(right, right).sqrt();
        right = if norm > 1e-9 {
            right.map(|c| c / norm)
        } else {
            [-az.sin(), az.cos(), 0.0]
        };
        let up = [
            back[1] * right[2] - back[2] * right[1],
            back[2] * right[0] - back[0] * right[2],
            back[0] * right[1] - back[1] * right[0],
        ];
        Camera {
            right,
            up,
            back,
            centre: lengths.map(|l| l / 2.0),
        }
    }

    /// `(x right, y up, depth towards the viewer)` of a world point, about the box centre.
    fn project(&self, p: [f64; 3]) -> (f64, f64, f64) {
        let d = [
            p[0] - self.centre[0],
            p[1] - self.centre[1],
            p[2] - self.centre[2],
        ];
        (dot(d, self.right), dot(d, self.up), dot(d, self.back))
    }
}

/// The 8 corners of the box, corner `k` having bit `a` of `k` set where it is at `L_a`.
fn corners(lengths: [f64; 3]) -> [[f64; 3]; 8] {
    std::array::from_fn(|k| std::array::from_fn(|a| if k >> a & 1 == 1 { lengths[a] } else { 0.0 }))
}

/// Draws a 3D scene into a new `width` x `height` image.
pub fn draw3(scene: &Scene3, view: View, width: u32, height: u32) -> Pixmap {
    let mut pm = Pixmap::new(width.max(1), height.max(1)).expect("non-zero size");
    draw3_into(scene, view, &mut pm);
    pm
}

/// Draws a 3D scene into an existing image (the viewer reuses one per frame).
pub fn draw3_into(scene: &Scene3, view: View, pm: &mut Pixmap) {
    match view {
        View::Orbit { azimuth, elevation } => draw_orbit(scene, azimuth, elevation, pm),
        View::Slice { axis, position } => crate::draw_into(&slice(scene, axis, position), pm),
    }
}

/// The 2D scene of the circles where the plane perpendicular to `axis` at `position` cuts the
/// spheres, in the plane's coordinates (the other two axes, in order). Periodic images of
/// spheres that reach across a periodic face are cut too. Two circles cut from bonded spheres
/// (the same periodic images of them) are bonded.
pub fn slice(scene: &Scene3, axis: usize, position: f64) -> Scene {
    let axis = axis.min(2);
    let others: [usize; 2] = match axis {
        0 => [1, 2],
        1 => [0, 2],
        _ => [0, 1],
    };
    let l = scene.lengths[axis];
    let mut out = Scene {
        lengths: others.map(|a| scene.lengths[a]),
        periodic: others.map(|a| scene.periodic[a]),
        ..Scene::default()
    };
    // The circles cut from each sphere: (index in the slice, where the image is on the axis).
    let mut cut: Vec<Vec<(usize, f64)>> = vec![Vec::new(); scene.positions.len()];
    for (i, p) in scene.positions.iter().enumerate() {
        let r = scene.radii[i];
        let shifts: &[f64] = if scene.periodic[axis] {
            &[0.0, l, -l]
        } else {
            &[0.0]
        };
        for s in shifts {
            let d = p[axis] + s - position;
            if d.abs() < r {
                cut[i].push((out.positions.len(), p[axis] + s));
                out.positions
                    .push(Vector::new([p[others[0]], p[others[1]]]));
                out.radii.push((r * r - d * d).sqrt());
                out.colours
                    .push(scene.colours.get(i).copied().unwrap_or([0, 0, 0]));
            }
        }
    }
    for &[i, j] in &scene.bonds {
        let (Some(ci), Some(cj)) = (cut.get(i), cut.get(j)) else {
            continue;
        };
        for &(a, za) in ci {
            for &(b, zb) in cj {
                // Both images the plane cuts lie within a radius of it, so within one bond of
                // each other exactly when they are the pair's nearest images.
                if !scene.periodic[axis] || (zb - za).abs() <= 0.5 * l {
                    out.bonds.push([a, b]);
                }
            }
        }
    }
    out
}

/// Pixels per length unit and the pixel of the box centre, fitting the projected box.
fn fit(cam: &Camera, lengths: [f64; 3], w: f64, h: f64) -> (f64, f64, f64) {
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for c in corners(lengths) {
        let (x, y, _) = cam.project(c);
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    let margin = 8.0;
    let scale = ((w - 2.0 * margin) / (x1 - x0).max(1e-300))
        .min((h - 2.0 * margin) / (y1 - y0).max(1e-300))
        .max(f64::MIN_POSITIVE);
    // Centre the projected box (its own middle, not the world centre's image).
    let cx = w / 2.0 - scale * (x0 + x1) / 2.0;
    let cy = h / 2.0 + scale * (y0 + y1) / 2.0;
    (scale, cx, cy)
}

fn draw_orbit(scene: &Scene3, azimuth: f64, elevation: f64, pm: &mut Pixmap) {
    let [or, og, ob] = OUTSIDE;
    pm.fill(Color::from_rgba8(or, og, ob, 255));
    let cam = Camera::new(scene.lengths, azimuth, elevation);
    let (scale, cx, cy) = fit(&cam, scene.lengths, pm.width() as f64, pm.height() as f64);
    let to_pixel = |x: f64, y: f64| (cx + x * scale, cy - y * scale);
    // The 12 edges join corners that differ in one axis. Seen from outside, the three edges
    // meeting at the corner farthest from the viewer are the ones behind the box.
    let cs = corners(scene.lengths);
    let far = (0..8)
        .min_by(|&a, &b| cam.project(cs[a]).2.total_cmp(&cam.project(cs[b]).2))
        .expect("8 corners");
    let mut hidden = PathBuilder::new();
    let mut visible = PathBuilder::new();
    for k in 0..8usize {
        for a in 0..3 {
            let j = k | 1 << a;
            if j == k {
                continue;
            }
            let (x0, y0, _) = cam.project(cs[k]);
            let (x1, y1, _) = cam.project(cs[j]);
            let (p0, p1) = (to_pixel(x0, y0), to_pixel(x1, y1));
            let pb = if k == far || j == far {
                &mut hidden
            } else {
                &mut visible
            };
            pb.move_to(p0.0 as f32, p0.1 as f32);
            pb.line_to(p1.0 as f32, p1.1 as f32);
        }
    }
    if let Some(path) = hidden.finish() {
        let stroke = Stroke {
            width: 1.0,
            ..Stroke::default()
        };
        pm.stroke_path(
            &path,
            &paint([150, 150, 160]),
            &stroke,
            Transform::identity(),
            None,
        );
    }
    // Spheres and bonds, far to near. A bond runs between the two spheres' surfaces (halves
    // cut at the box's faces when it crosses a periodic one), at the depth of its middle;
    // consecutive bonds are stroked as one path.
    let mut pieces = Vec::new();
    for &[i, j] in &scene.bonds {
        if let (Some(&p), Some(&q)) = (scene.positions.get(i), scene.positions.get(j)) {
            let trim = [scene.radii[i], scene.radii[j]];
            bond_pieces(p, q, trim, scene.lengths, scene.periodic, &mut pieces);
        }
    }
    let mut order: Vec<(f64, Item)> = scene
        .positions
        .iter()
        .enumerate()
        .map(|(i, &p)| (cam.project(p).2, Item::Sphere(i)))
        .collect();
    for (k, (a, b)) in pieces.iter().enumerate() {
        let mid = std::array::from_fn(|c| 0.5 * (a[c] + b[c]));
        order.push((cam.project(mid).2, Item::Bond(k)));
    }
    order.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mean_r = scene.radii.iter().sum::<f64>() / scene.radii.len().max(1) as f64;
    let width = bond_width(0.7 * mean_r * scale);
    let mut bonds = PathBuilder::new();
    // One sprite per size (radii quantised to 1/16 pixel): a fluid of equal spheres shades
    // one sprite and copies it.
    let mut sprites: std::collections::HashMap<i64, Sprite> = std::collections::HashMap::new();
    for (_, item) in order {
        let i = match item {
            Item::Bond(k) => {
                let (a, b) = pieces[k];
                let (xa, ya, _) = cam.project(a);
                let (xb, yb, _) = cam.project(b);
                let (pa, pb) = (to_pixel(xa, ya), to_pixel(xb, yb));
                bonds.move_to(pa.0 as f32, pa.1 as f32);
                bonds.line_to(pb.0 as f32, pb.1 as f32);
                continue;
            }
            Item::Sphere(i) => i,
        };
        stroke_bonds(std::mem::take(&mut bonds), width, pm);
        let (x, y, _) = cam.project(scene.positions[i]);
        let (px, py) = to_pixel(x, y);
        let colour = scene.colours.get(i).copied().unwrap_or([0, 0, 0]);
        let r = (scene.radii[i] * scale).clamp(0.5, 4096.0);
        let key = (r * 16.0).round() as i64;
        sprites
            .entry(key)
            .or_insert_with(|| Sprite::new(key as f64 / 16.0))
            .blit(pm, px, py, colour);
    }
    stroke_bonds(bonds, width, pm);
    if let Some(path) = visible.finish() {
        let periodic = scene.periodic.iter().all(|&p| p);
        let stroke = Stroke {
            width: if periodic { 1.0 } else { 2.0 },
            ..Stroke::default()
        };
        pm.stroke_path(&path, &paint(WALL), &stroke, Transform::identity(), None);
    }
}

/// What the orbit view draws, in depth order.
#[derive(Clone, Copy, Debug)]
enum Item {
    /// Sphere `i`.
    Sphere(usize),
    /// Piece `k` of the bonds.
    Bond(usize),
}

/// Light direction in screen coordinates (x right, y down, z towards the viewer): above, to
/// the left and in front.
const LIGHT: [f64; 3] = [-0.42, -0.58, 0.70];

/// The shading of one sphere size, pixel by pixel, computed once per picture and size: the
/// sphere's normal at each pixel lights it with an ambient term, Lambert's law and a
/// Blinn-Phong highlight; the outermost pixel darkens (a rim) and is antialiased by coverage.
/// Centres are snapped to pixel centres, so one sprite serves every sphere of that size.
struct Sprite {
    /// Half-width in pixels: the sprite covers `-half..=half` in x and y.
    half: i64,
    /// Per pixel: coverage, the factor on the colour, and the white added.
    cells: Vec<[f32; 3]>,
}

impl Sprite {
    fn new(r: f64) -> Self {
        let half = (r + 1.0).ceil() as i64;
        let side = (2 * half + 1) as usize;
        let norm = dot(LIGHT, LIGHT).sqrt();
        let l = LIGHT.map(|c| c / norm);
        // Half vector between the light and the viewer (0, 0, 1).
        let hv = [l[0], l[1], l[2] + 1.0];
        let hn = dot(hv, hv).sqrt();
        let hv = hv.map(|c| c / hn);
        let mut cells = Vec::with_capacity(side * side);
        for y in -half..=half {
            for x in -half..=half {
                let (dx, dy) = (x as f64, y as f64);
                let d = (dx * dx + dy * dy).sqrt();
                let cov = (r + 0.5 - d).clamp(0.0, 1.0);
                if cov <= 0.0 {
                    cells.push([0.0; 3]);
                    continue;
                }
                let (nx, ny) = (dx / r, dy / r);
                let nz = (1.0 - nx * nx - ny * ny).max(0.0).sqrt();
                let n = [nx, ny, nz];
                let diffuse = dot(n, l).max(0.0);
                let spec = dot(n, hv).max(0.0).powi(40);
                // A dark rim in the last pixel or so of the radius.
                let rim = ((r - d) / 1.2).clamp(0.0, 1.0);
                let shade = (0.30 + 0.70 * diffuse) * (0.35 + 0.65 * rim);
                cells.push([cov as f32, shade as f32, (255.0 * 0.45 * spec * rim) as f32]);
            }
        }
        Sprite { half, cells }
    }

    /// Draws the sprite in `colour` with its centre at the pixel nearest `(cx, cy)`. Dark file
    /// colours are lifted a little so that black spheres still show their shading.
    fn blit(&self, pm: &mut Pixmap, cx: f64, cy: f64, colour: [u8; 3]) {
        let (w, h) = (pm.width() as i64, pm.height() as i64);
        let (px, py) = (cx.floor() as i64, cy.floor() as i64);
        let base = colour.map(|c| 40.0 + c as f32 * (215.0 / 255.0));
        let side = 2 * self.half + 1;
        let pixels = pm.pixels_mut();
        for sy in 0..side {
            let y = py + sy - self.half;
            if y < 0 || y >= h {
                continue;
            }
            for sx in 0..side {
                let x = px + sx - self.half;
                if x < 0 || x >= w {
                    continue;
                }
                let [cov, shade, white] = self.cells[(sy * side + sx) as usize];
                if cov <= 0.0 {
                    continue;
                }
                let dst = &mut pixels[(y * w + x) as usize];
                let mix = |k: usize, d: u8| {
                    let s = (base[k] * shade + white).min(255.0);
                    (s * cov + d as f32 * (1.0 - cov)).round() as u8
                };
                let c = [mix(0, dst.red()), mix(1, dst.green()), mix(2, dst.blue())];
                if let Some(p) = tiny_skia::PremultipliedColorU8::from_rgba(c[0], c[1], c[2], 255) {
                    *dst = p;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rgb_at(pm: &Pixmap, x: u32, y: u32) -> [u8; 3] {
        let c = pm.pixel(x, y).unwrap().demultiply();
        [c.red(), c.green(), c.blue()]
    }

    fn scene(spheres: &[([f64; 3], f64, [u8; 3])]) -> Scene3 {
        Scene3 {
            lengths: [10.0; 3],
            periodic: [false; 3],
            positions: spheres.iter().map(|s| s.0).collect(),
            radii: spheres.iter().map(|s| s.1).collect(),
            colours: spheres.iter().map(|s| s.2).collect(),
            bonds: Vec::new(),
        }
    }

    const RED: [u8; 3] = [220, 30, 30];
    const BLUE: [u8; 3] = [30, 30, 220];

    #[test]
    fn the_nearer_sphere_hides_the_farther_whatever_the_order() {
        // Seen from +x (azimuth 0, elevation 0), a sphere at larger x is nearer. Both lie on
        // the line of sight through the box centre, so they project onto the image centre.
        let view = View::Orbit {
            azimuth: 0.0,
            elevation: 0.0,
        };
        for (near, far) in [(RED, BLUE), (BLUE, RED)] {
            for flip in [false, true] {
                let mut s = vec![([8.0, 5.0, 5.0], 2.0, near), ([2.0, 5.0, 5.0], 2.0, far)];
                if flip {
                    s.reverse();
                }
                let pm = draw3(&scene(&s), view, 201, 201);
                let c = rgb_at(&pm, 100, 100);
                let (hot, cold) = if near == RED { (0, 2) } else { (2, 0) };
                assert!(c[hot] > c[cold] + 50, "{c:?}: the far sphere shows through");
            }
        }
    }

    #[test]
    fn a_sphere_is_brighter_on_the_lit_side() {
        let pm = draw3(
            &scene(&[([5.0, 5.0, 5.0], 3.0, [200, 200, 200])]),
            View::Orbit {
                azimuth: 0.0,
                elevation: 0.0,
            },
            201,
            201,
        );
        let sum = |c: [u8; 3]| c.iter().map(|&v| v as u32).sum::<u32>();
        // The light comes from the upper left: the upper-left part of the disc is brighter
        // than the lower-right part, at the same distance from the centre.
        let (lit, dark) = (rgb_at(&pm, 80, 80), rgb_at(&pm, 120, 120));
        assert!(sum(lit) > sum(dark) + 100, "{lit:?} vs {dark:?}");
    }

    #[test]
    fn the_box_fits_from_every_direction_and_an_empty_box_is_drawn() {
        for (az, el) in [
            (0.0, 0.0),
            (30.0, 20.0),
            (135.0, -40.0),
            (10.0, 90.0),
            (0.0, -90.0),
        ] {
            let sc = Scene3 {
                lengths: [4.0, 2.0, 7.0],
                ..Scene3::default()
            };
            let pm = draw3(
                &sc,
                View::Orbit {
                    azimuth: az,
                    elevation: el,
                },
                160,
                120,
            );
            // Every edge pixel of the image is background: the wireframe stays inside.
            for x in 0..160 {
                for y in [0, 119] {
                    assert_eq!(rgb_at(&pm, x, y), OUTSIDE, "({az}, {el}) at ({x}, {y})");
                }
            }
            // Something was drawn: some pixels are dark (the edges).
            let dark = (0..160 * 120)
                .filter(|k| rgb_at(&pm, k % 160, k / 160)[0] < 180)
                .count();
            assert!(dark > 100, "({az}, {el}): only {dark} dark pixels");
        }
    }

    #[test]
    fn a_bond_joins_the_surfaces_and_hides_behind_nearer_spheres() {
        // Seen from +z (from above): two spheres bonded along x with a gap between them.
        let view = View::Orbit {
            azimuth: 0.0,
            elevation: 90.0,
        };
        let mut sc = scene(&[([4.0, 5.0, 5.0], 0.5, BLUE), ([6.0, 5.0, 5.0], 0.5, BLUE)]);
        let plain = draw3(&sc, view, 201, 201);
        sc.bonds = vec![[0, 1]];
        let bonded = draw3(&sc, view, 201, 201);
        let c = rgb_at(&bonded, 100, 100);
        assert_ne!(c, rgb_at(&plain, 100, 100));
        assert!(
            c[0] > 180 && c[2] < 120,
            "{c:?}: no bond between the spheres"
        );
        // A sphere above the gap (nearer the viewer) hides the bond.
        sc.positions.push([5.0, 5.0, 8.0]);
        sc.radii.push(0.6);
        sc.colours.push(RED);
        let hidden = draw3(&sc, view, 201, 201);
        let c = rgb_at(&hidden, 100, 100);
        assert!(
            c[0] > c[1] + 50 && c[0] > c[2] + 50,
            "{c:?}: the bond shows through"
        );
        // Below the gap (farther away) it does not.
        sc.positions[2] = [5.0, 5.0, 2.0];
        let over = draw3(&sc, view, 201, 201);
        let c = rgb_at(&over, 100, 100);
        assert!(
            c[0] > 180 && c[1] > 80 && c[2] < 120,
            "{c:?}: the bond is hidden"
        );
    }

    #[test]
    fn a_slice_keeps_the_bonds_of_the_spheres_it_cuts() {
        let mut sc = scene(&[
            ([5.0, 5.0, 5.0], 1.0, RED),
            ([6.5, 5.0, 5.2], 1.0, BLUE),
            ([5.0, 6.5, 7.5], 1.0, BLUE), // not cut
        ]);
        sc.bonds = vec![[0, 1], [0, 2]];
        assert_eq!(slice(&sc, 2, 5.0).bonds, vec![[0, 1]]);
        // Across a periodic face the plane cuts both images of a sphere at z = 0.1 near the
        // plane z = 0.05 only once each; its partner at z = 9.9 is joined to it.
        let mut p = scene(&[([5.0, 5.0, 0.1], 0.5, RED), ([5.8, 5.0, 9.9], 0.5, BLUE)]);
        p.periodic = [true; 3];
        p.bonds = vec![[0, 1]];
        let s = slice(&p, 2, 0.05);
        assert_eq!(s.positions.len(), 2);
        assert_eq!(s.bonds, vec![[0, 1]]);
    }

    #[test]
    fn a_slice_cuts_exactly_the_spheres_the_plane_meets() {
        let sc = scene(&[
            ([5.0, 5.0, 5.0], 1.0, RED),  // cut through its centre: radius 1
            ([2.0, 2.0, 5.6], 1.0, BLUE), // 0.6 away: radius 0.8
            ([8.0, 8.0, 7.0], 1.0, BLUE), // 2 away: not cut
        ]);
        let s = slice(&sc, 2, 5.0);
        assert_eq!(s.positions.len(), 2);
        assert_eq!(s.radii[0], 1.0);
        assert!((s.radii[1] - 0.8).abs() < 1e-12);
        assert_eq!(s.positions[1], Vector::new([2.0, 2.0]));
        assert_eq!(s.lengths, [10.0, 10.0]);
        // Across a periodic face: a sphere at z = 0.2 is cut by the plane z = 9.9.
        let mut p = scene(&[([5.0, 5.0, 0.2], 0.5, RED)]);
        p.periodic = [true; 3];
        let s = slice(&p, 2, 9.9);
        assert_eq!(s.positions.len(), 1);
        assert!((s.radii[0] - (0.25f64 - 0.09).sqrt()).abs() < 1e-12);
    }
}
