//! The simulation side of the viewer, free of GUI types so that it can be tested without a
//! window: the running simulation and its initial state, the tagged discs and their trails, and
//! the live measurements (temperature, pressure, speed histogram), and on a line the phase
//! plane.

use edmd_core::measure::{kinetic_temperature, Pressure, Speeds, Temperature};
use edmd_core::{EventKind, EventRecord, Observer, Simulation, Vector};
use edmd_draw::{AnyScene, Colouring, Scene, Scene3, SceneLine, View};

/// Most points kept per trail; older points are dropped.
pub const MAX_TRAIL_POINTS: usize = 50_000;

/// Paths of the tagged discs, recorded at every event they take part in (so the drawn polyline
/// is the exact path) and at every frame.
#[derive(Clone, Debug)]
pub struct Trails<const D: usize = 2> {
    tagged: Vec<usize>,
    paths: Vec<Vec<Vector<D>>>,
}

impl<const D: usize> Default for Trails<D> {
    fn default() -> Self {
        Trails {
            tagged: Vec::new(),
            paths: Vec::new(),
        }
    }
}

impl<const D: usize> Trails<D> {
    /// The tagged discs, in the order they were tagged.
    pub fn tagged(&self) -> &[usize] {
        &self.tagged
    }

    /// The recorded path of each tagged disc, oldest point first.
    pub fn paths(&self) -> &[Vec<Vector<D>>] {
        &self.paths
    }

    /// Tags disc `i` (starting its trail where it is now), or untags it if it was tagged.
    /// Returns whether it is tagged now.
    pub fn toggle(&mut self, i: usize, sim: &Simulation<D>) -> bool {
        if let Some(k) = self.tagged.iter().position(|&t| t == i) {
            self.tagged.remove(k);
            self.paths.remove(k);
            false
        } else {
            self.tagged.push(i);
            self.paths.push(vec![sim.position(i)]);
            true
        }
    }

    /// Restarts every trail at the discs' current positions.
    pub fn restart(&mut self, sim: &Simulation<D>) {
        for (path, &i) in self.paths.iter_mut().zip(&self.tagged) {
            path.clear();
            path.push(sim.position(i));
        }
    }

    /// Adds the current position of every tagged disc (called at each frame).
    pub fn record(&mut self, sim: &Simulation<D>) {
        for k in 0..self.tagged.len() {
            self.push(k, sim.position(self.tagged[k]));
        }
    }

    fn push(&mut self, k: usize, p: Vector<D>) {
        let path = &mut self.paths[k];
        if path.last() != Some(&p) {
            path.push(p);
        }
        if path.len() > MAX_TRAIL_POINTS {
            path.drain(..path.len() - MAX_TRAIL_POINTS / 2);
        }
    }
}

impl<const D: usize> Observer<D> for Trails<D> {
    fn on_event(&mut self, e: &EventRecord<D>, sim: &Simulation<D>) {
        if self.tagged.is_empty() {
            return;
        }
        let (a, b) = match e.kind {
            EventKind::DiscDisc { i, j }
            | EventKind::Reaction { i, j, .. }
            | EventKind::Step { i, j, .. } => (i, Some(j)),
            EventKind::Wall { i, .. }
            | EventKind::Barrier { i, .. }
            | EventKind::Thermostat { i }
            | EventKind::NeighbourList { i }
            | EventKind::Slide { i }
            | EventKind::CellCrossing { i, .. } => (i, None),
        };
        for k in 0..self.tagged.len() {
            let t = self.tagged[k];
            if t == a || Some(t) == b {
                self.push(k, sim.position(t));
            }
        }
    }
}

/// One bin of the speed histogram against the Maxwell-Boltzmann law (Rayleigh in 2D); on a
/// line, of the velocity histogram against the Gaussian.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpeedBin {
    /// Speed at the centre of the bin (on a line, the velocity, of either sign).
    pub speed: f64,
    /// Measured probability density.
    pub density: f64,
    /// Density of the law (Gaussian in 1D, Rayleigh in 2D, Maxwell in 3D) at the measured
    /// temperature.
    pub rayleigh: f64,
}

/// The state behind the viewer window.
#[derive(Clone, Debug)]
pub struct Model<const D: usize = 2> {
    initial: Simulation<D>,
    /// The running simulation.
    pub sim: Simulation<D>,
    /// How discs are coloured.
    pub colouring: Colouring,
    /// How a 3D system is looked at (unused in 2D).
    pub view: View,
    /// Whether to draw the bonds of a stepped potential's pairs (see
    /// [`edmd_draw::Scene::with_bonds`]; nothing to draw for hard discs).
    pub bonds: bool,
    trails: Trails<D>,
    pressure: Pressure,
    temperature: Temperature,
    pressure_series: Vec<[f64; 2]>,
    virial_series: Vec<[f64; 2]>,
    speeds: Vec<SpeedBin>,
}

impl<const D: usize> Model<D> {
    /// A viewer model starting from `sim` (kept for restarts).
    pub fn new(sim: Simulation<D>, colouring: Colouring) -> Self {
        let mut m = Model {
            pressure: Pressure::new(&sim),
            initial: sim.clone(),
            sim,
            colouring,
            view: View::default(),
            bonds: false,
            trails: Trails::default(),
            temperature: Temperature::new(),
            pressure_series: Vec::new(),
            virial_series: Vec::new(),
            speeds: Vec::new(),
        };
        m.sample();
        m
    }

    /// Runs the simulation to time `t` exactly: every event up to `t` is processed.
    pub fn run_until(&mut self, t: f64) {
        self.sim
            .run_until(t, &mut (&mut self.pressure, &mut self.trails));
        self.trails.record(&self.sim);
    }

    /// Why the simulation stopped, if it did: its clock stopped advancing, or a multi-disc
    /// collision was given up (`edmd_core::Stall`). The viewer shows this and pauses.
    pub fn stall_message(&self) -> Option<String> {
        self.sim.stalled().map(|s| format!("Stopped: {s}."))
    }

    /// Processes events up to and including the next one that changes a velocity (cell
    /// crossings and neighbour lists made again are bookkeeping and are passed over). Returns it, or `None` if nothing will
    /// ever happen.
    pub fn step_event(&mut self) -> Option<EventRecord<D>> {
        loop {
            let e = self.sim.step(f64::INFINITY)?;
            self.pressure.on_event(&e, &self.sim);
            self.trails.on_event(&e, &self.sim);
            if !e.kind.is_bookkeeping() {
                self.trails.record(&self.sim);
                return Some(e);
            }
        }
    }

    /// Back to the initial state; tagged discs stay tagged, with fresh trails.
    pub fn restart(&mut self) {
        self.sim = self.initial.clone();
        self.pressure = Pressure::new(&self.sim);
        self.temperature = Temperature::new();
        self.pressure_series.clear();
        self.virial_series.clear();
        self.trails.restart(&self.sim);
        self.sample();
    }

    /// Reverses every velocity: the system retraces its path (time-reversal demonstration).
    pub fn reverse(&mut self) {
        self.sim.reverse_velocities();
    }

    /// Tags disc `i` or untags it. Returns whether it is tagged now.
    pub fn toggle_tag(&mut self, i: usize) -> bool {
        self.trails.toggle(i, &self.sim)
    }

    /// The tagged discs and their trails.
    pub fn trails(&self) -> &Trails<D> {
        &self.trails
    }

    /// Closes a measurement block: appends the temperature and the pressure over the time since
    /// the last sample to their series (under self-gravity the virial ratio too), and takes a
    /// new speed histogram. The pressure needs simulated time to have passed since the last
    /// sample.
    pub fn sample(&mut self) {
        let t = self.sim.time();
        if self
            .temperature
            .series()
            .last()
            .is_none_or(|&(t0, _)| t > t0)
        {
            self.temperature.sample(&self.sim);
            if let Some(ratio) = virial_ratio(&self.sim) {
                self.virial_series.push([t, ratio]);
            }
        }
        let before = self.pressure.blocks().len();
        self.pressure.sample(&self.sim);
        if let Some(b) = self.pressure.blocks().get(before) {
            self.pressure_series.push([b.end, b.virial]);
        }
        self.speeds = speed_histogram(&self.sim, 40);
    }

    /// Temperature `kT` against time.
    pub fn temperature_series(&self) -> Vec<[f64; 2]> {
        self.temperature
            .series()
            .iter()
            .map(|&(t, v)| [t, v])
            .collect()
    }

    /// Virial pressure against time (one point per sample, averaged since the previous one).
    pub fn pressure_series(&self) -> &[[f64; 2]] {
        &self.pressure_series
    }

    /// `2K/U` against time under self-gravity (empty without it): the sheets' virial ratio,
    /// which the virial theorem puts at 1 on time averages.
    pub fn virial_series(&self) -> &[[f64; 2]] {
        &self.virial_series
    }

    /// The speed histogram of the last sample (on a line, the velocity histogram).
    pub fn speeds(&self) -> &[SpeedBin] {
        &self.speeds
    }

    /// On a line, the phase plane now: `[x, v]` for every rod, in input order, with `x` the
    /// sheet's position under self-gravity ([`Simulation::sheet_positions`]: the rods' lengths
    /// taken out, so that the sheets pass through each other as the model has them); empty in
    /// 2D and 3D.
    pub fn phase_points(&self) -> Vec<[f64; 2]> {
        if D != 1 {
            return Vec::new();
        }
        let v = (0..self.sim.len()).map(|i| self.sim.velocity(i)[0]);
        match self.sim.sheet_positions() {
            Some(x) => x.into_iter().zip(v).map(|(x, v)| [x, v]).collect(),
            None => (0..self.sim.len())
                .map(|i| self.sim.position(i)[0])
                .zip(v)
                .map(|(x, v)| [x, v])
                .collect(),
        }
    }

    /// What to draw now: discs with the trails of the tagged ones, or spheres in
    /// [`Self::view`], with their bonds if [`Self::bonds`] is set, or rods on a line (as
    /// `edmd render` draws them; no bonds).
    pub fn scene(&self) -> AnyScene {
        if D == 1 {
            return AnyScene::Line(SceneLine::capture(&self.sim, self.colouring));
        }
        if D == 3 {
            let mut scene = Scene3::capture(&self.sim, self.colouring);
            if self.bonds {
                scene = scene.with_bonds(&self.sim);
            }
            return AnyScene::Solid(scene, self.view);
        }
        let mut scene = Scene::capture(&self.sim, self.colouring);
        if self.bonds {
            scene = scene.with_bonds(&self.sim);
        }
        scene.trails = self
            .trails
            .paths()
            .iter()
            .map(|p| p.iter().map(|q| Vector::new([q[0], q[1]])).collect())
            .collect();
        scene.highlighted = self.trails.tagged().to_vec();
        AnyScene::Flat(scene)
    }
}

/// Speed histogram of the current velocities, `bins` bins up to four times the RMS speed, with
/// the Maxwell-Boltzmann density (Rayleigh in 2D) at the current temperature; on a line,
/// [`velocity_histogram`]. Under shear and in a ring patch the speeds and the temperature are
/// those of the peculiar velocities, relative to the streaming flow.
pub fn speed_histogram<const D: usize>(sim: &Simulation<D>, bins: usize) -> Vec<SpeedBin> {
    let n = sim.len();
    if n == 0 {
        return Vec::new();
    }
    let rms = ((0..n)
        .map(|i| sim.peculiar_velocity(i).norm2())
        .sum::<f64>()
        / n as f64)
        .sqrt();
    if rms <= 0.0 || !rms.is_finite() {
        return Vec::new();
    }
    if D == 1 {
        return velocity_histogram(sim, bins, rms);
    }
    let mut speeds = Speeds::new(bins, 4.0 * rms);
    speeds.sample(sim);
    speeds
        .histogram_vs_maxwell(kinetic_temperature(sim))
        .into_iter()
        .map(|(speed, density, rayleigh)| SpeedBin {
            speed,
            density,
            rayleigh,
        })
        .collect()
}

/// On a line the Maxwell-Boltzmann law is the velocity's, a Gaussian of variance `kT/m`
/// (mixed over the rods' masses): `bins` bins of the velocities from `-4 rms` to `4 rms`, with
/// that density at the current temperature.
fn velocity_histogram<const D: usize>(sim: &Simulation<D>, bins: usize, rms: f64) -> Vec<SpeedBin> {
    let n = sim.len();
    let (lo, width) = (-4.0 * rms, 8.0 * rms / bins as f64);
    let mut counts = vec![0usize; bins];
    for i in 0..n {
        let k = ((sim.velocity(i)[0] - lo) / width).floor();
        if k >= 0.0 && k < bins as f64 {
            counts[k as usize] += 1;
        }
    }
    let kt = kinetic_temperature(sim);
    // The rods' masses with how many have each: usually one or two.
    let mut masses: Vec<f64> = (0..n).map(|i| sim.mass(i)).collect();
    masses.sort_by(f64::total_cmp);
    let mut groups: Vec<(f64, usize)> = Vec::new();
    for m in masses {
        match groups.last_mut() {
            Some((last, count)) if *last == m => *count += 1,
            _ => groups.push((m, 1)),
        }
    }
    let gaussian = |v: f64| {
        groups
            .iter()
            .map(|&(m, count)| {
                let a = m / kt;
                count as f64 * (a / (2.0 * std::f64::consts::PI)).sqrt() * (-a * v * v / 2.0).exp()
            })
            .sum::<f64>()
            / n as f64
    };
    counts
        .into_iter()
        .enumerate()
        .map(|(k, c)| {
            let v = lo + (k as f64 + 0.5) * width;
            SpeedBin {
                speed: v,
                density: c as f64 / (n as f64 * width),
                rayleigh: gaussian(v),
            }
        })
        .collect()
}

/// The virial ratio `2K/U` of self-gravitating sheets (`None` without self-gravity, or while
/// `U` is 0).
pub fn virial_ratio<const D: usize>(sim: &Simulation<D>) -> Option<f64> {
    sim.self_gravity()?;
    let u = sim.self_gravity_energy();
    (u > 0.0).then(|| 2.0 * sim.kinetic_energy() / u)
}

/// A default pace: simulated time per second of wall time at which a disc of RMS speed crosses
/// a twentieth of the box's shorter side per second.
pub fn default_speed<const D: usize>(sim: &Simulation<D>) -> f64 {
    let n = sim.len().max(1);
    let rms = ((0..sim.len()).map(|i| sim.velocity(i).norm2()).sum::<f64>() / n as f64).sqrt();
    let l = sim
        .sim_box()
        .lengths
        .iter()
        .copied()
        .fold(f64::INFINITY, f64::min);
    let s = 0.05 * l / rms;
    if s.is_finite() && s > 0.0 {
        s
    } else {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use edmd_core::{Disc, Options, SimBox};

    fn pair() -> Simulation {
        // Head-on at t = 1 (contact distance 2, gap 2, closing speed 2).
        let discs = [
            Disc::new(Vector::new([3.0, 5.0]), Vector::new([1.0, 0.0]), 1.0),
            Disc::new(Vector::new([7.0, 5.0]), Vector::new([-1.0, 0.0]), 1.0),
        ];
        Simulation::new(&discs, SimBox::walls([10.0, 10.0]), Options::default()).unwrap()
    }

    #[test]
    fn a_stalled_run_says_why() {
        // A column of touching discs filling the box's height: every event is at t = 0.
        let discs: Vec<Disc> = (0..10)
            .map(|k| {
                let v = 0.3 - 0.1 * k as f64;
                Disc::new(
                    Vector::new([2.5, 0.5 + k as f64]),
                    Vector::new([0.0, v]),
                    0.5,
                )
            })
            .collect();
        let sim = Simulation::new(&discs, SimBox::walls([5.0, 10.0]), Options::default()).unwrap();
        let mut m = Model::new(sim, Colouring::File);
        assert_eq!(m.stall_message(), None);
        m.run_until(1.0);
        let text = m.stall_message().expect("stalled");
        assert!(
            text.starts_with("Stopped: the clock stopped advancing at t = 0"),
            "{text}"
        );
    }

    #[test]
    fn a_trail_passes_through_every_collision() {
        let mut m = Model::new(pair(), Colouring::File);
        assert!(m.toggle_tag(0));
        m.run_until(1.5);
        let path = &m.trails().paths()[0];
        // Start, the collision point, the frame point.
        assert_eq!(path.first(), Some(&Vector::new([3.0, 5.0])));
        assert!(path.contains(&Vector::new([4.0, 5.0])), "{path:?}");
        assert_eq!(path.last(), Some(&Vector::new([3.5, 5.0])));
        assert!(!m.toggle_tag(0));
        assert!(m.trails().tagged().is_empty() && m.trails().paths().is_empty());
    }

    #[test]
    fn reverse_then_run_returns_and_restart_resets() {
        let mut m = Model::new(pair(), Colouring::File);
        m.run_until(2.0);
        assert_eq!(m.sim.stats().disc_disc, 1);
        m.reverse();
        m.run_until(4.0);
        assert!((m.sim.position(0) - Vector::new([3.0, 5.0])).norm2() < 1e-24);
        m.restart();
        assert_eq!(m.sim.time(), 0.0);
        assert_eq!(m.sim.stats().disc_disc, 0);
        assert!(m.pressure_series().is_empty());
    }

    #[test]
    fn a_step_is_one_velocity_changing_event() {
        let mut m = Model::new(pair(), Colouring::File);
        let e = m.step_event().unwrap();
        assert!(matches!(e.kind, EventKind::DiscDisc { .. }));
        assert_eq!(m.sim.time(), 1.0);
    }

    #[test]
    fn samples_make_series_and_histogram() {
        let mut m = Model::new(pair(), Colouring::Speed);
        for k in 1..=3 {
            m.run_until(k as f64);
            m.sample();
        }
        m.sample(); // no time passed: nothing new
        assert_eq!(m.temperature_series().len(), 4);
        assert_eq!(m.temperature_series()[3], [3.0, 0.5]);
        assert_eq!(m.pressure_series().len(), 3);
        let h = m.speeds();
        assert_eq!(h.len(), 40);
        // Both discs have speed 1 = the RMS speed: all the weight in the bin holding 1.
        let total: f64 = h.iter().map(|b| b.density).sum::<f64>() * (h[1].speed - h[0].speed);
        assert!((total - 1.0).abs() < 1e-12);
        assert!(h.iter().all(|b| b.rayleigh >= 0.0));
        match m.scene() {
            AnyScene::Flat(scene) => assert_eq!(scene.positions.len(), 2),
            _ => panic!("a 2D model drew spheres or rods"),
        }
    }

    #[test]
    fn bonds_are_drawn_when_asked_for_a_stepped_potential() {
        // Three discs in a row 1.2 apart, in a well out to 1.5: two bonds.
        let discs: Vec<Disc> = (0..3)
            .map(|k| Disc::new(Vector::new([3.0 + 1.2 * k as f64, 5.0]), Vector::ZERO, 0.5))
            .collect();
        let potential = edmd_core::Potential::single(0, 0, 1.5, -1.0);
        let sim = Simulation::with_potential_at(
            &discs,
            SimBox::periodic([10.0, 10.0]),
            &[],
            &potential,
            Options::default(),
            0.0,
        )
        .unwrap();
        let mut m = Model::new(sim, Colouring::Energy);
        let bonds = |m: &Model| match m.scene() {
            AnyScene::Flat(s) => s.bonds,
            _ => panic!("a 2D model drew spheres or rods"),
        };
        assert!(bonds(&m).is_empty());
        m.bonds = true;
        assert_eq!(bonds(&m), vec![[0, 1], [1, 2]]);
        // Hard discs have none.
        let mut m = Model::new(pair(), Colouring::File);
        m.bonds = true;
        assert!(bonds(&m).is_empty());
    }

    #[test]
    fn default_speed_crosses_a_twentieth_of_the_box_per_second() {
        assert_eq!(default_speed(&pair()), 0.5);
    }

    /// Two rods head on between walls: contact at t = 1 (gap 2, closing at 2).
    fn rods() -> Simulation<1> {
        let discs = [
            Disc::new(Vector([3.0]), Vector([1.0]), 1.0),
            Disc::new(Vector([7.0]), Vector([-1.0]), 1.0),
        ];
        Simulation::new(&discs, SimBox::walls([10.0]), Options::default()).unwrap()
    }

    #[test]
    fn stepping_a_line_advances_event_by_event_and_reverses_and_restarts() {
        let mut m = Model::new(rods(), Colouring::File);
        let e = m.step_event().unwrap();
        assert_eq!(e.kind, EventKind::DiscDisc { i: 0, j: 1 });
        assert_eq!(m.sim.time(), 1.0);
        assert_eq!(m.phase_points(), vec![[4.0, -1.0], [6.0, 1.0]]);
        // Then each reaches its wall (at 1 and 9) at t = 4: two events.
        for _ in 0..2 {
            let e = m.step_event().unwrap();
            assert!(matches!(e.kind, EventKind::Wall { .. }), "{e:?}");
            assert_eq!(e.time, 4.0);
        }
        assert_eq!(m.sim.stats().disc_disc, 1);
        assert_eq!(m.sim.stats().wall, 2);
        // Reversed at t = 5, the rods retrace their paths: at t = 10 they are where they
        // started, moving the other way, after a second collision.
        m.run_until(5.0);
        m.reverse();
        m.run_until(10.0);
        assert_eq!(m.sim.stats().disc_disc, 2);
        assert_eq!(m.phase_points(), vec![[3.0, -1.0], [7.0, 1.0]]);
        m.restart();
        assert_eq!(m.sim.time(), 0.0);
        assert_eq!(m.phase_points(), vec![[3.0, 1.0], [7.0, -1.0]]);
        match m.scene() {
            AnyScene::Line(s) => assert_eq!(s.positions, vec![3.0, 7.0]),
            _ => panic!("rods drawn as discs or spheres"),
        }
    }

    /// A water bag's phase plane holds its sheets, not its rods: the sheets' positions (the
    /// rods' lengths taken out) and the velocities, in input order, as they move.
    #[test]
    fn a_water_bags_phase_plane_is_its_sheets() {
        use edmd_core::setup::sheets::WaterBag;
        use edmd_core::SelfGravity;
        let n = 40;
        let coupling = 1.0 / n as f64;
        let (discs, sim_box) = WaterBag {
            n,
            width: 1.0,
            speed: 1.0,
            radius: 1e-3,
            coupling,
            seed: 3,
        }
        .build()
        .unwrap();
        let mut sim = Simulation::new(&discs, sim_box, Options::default()).unwrap();
        sim.set_self_gravity(Some(SelfGravity { coupling }))
            .unwrap();
        let mut m = Model::new(sim, Colouring::Speed);
        for k in 1..=4 {
            m.run_until(k as f64);
            m.sample();
        }
        assert!(m.sim.stats().disc_disc > 100, "{:?}", m.sim.stats());
        let sheets = m.sim.sheet_positions().unwrap();
        let expected: Vec<[f64; 2]> = (0..n).map(|i| [sheets[i], m.sim.velocity(i)[0]]).collect();
        assert_eq!(m.phase_points(), expected);
        // Not the rods' positions: those are the sheets' spread by the rods' lengths.
        let rod_x: Vec<f64> = (0..n).map(|i| m.sim.position(i)[0]).collect();
        assert!(m
            .phase_points()
            .iter()
            .zip(&rod_x)
            .any(|(p, x)| (p[0] - x).abs() > 1e-3));
        // The panel beside it follows the virial ratio 2K/U, near 1 for this bag.
        let ratios = m.virial_series();
        assert_eq!(ratios.len(), 5);
        assert!(
            ratios.iter().all(|&[_, r]| r > 0.3 && r < 3.0),
            "{ratios:?}"
        );
        assert!(matches!(m.scene(), AnyScene::Line(_)));
        // Without self-gravity there is no virial ratio.
        assert!(Model::new(rods(), Colouring::File)
            .virial_series()
            .is_empty());
    }

    /// On a line the velocities are compared with the Gaussian, `sqrt(m / (2 pi kT))` at 0,
    /// over bins centred from `-4 rms` to `4 rms` holding every velocity.
    #[test]
    fn a_line_compares_velocities_with_the_gaussian() {
        let mut m = Model::new(rods(), Colouring::File);
        m.sample();
        let h = m.speeds();
        assert_eq!(h.len(), 40);
        let width = h[1].speed - h[0].speed;
        assert!(
            (h[0].speed + 4.0 - width / 2.0).abs() < 1e-12,
            "{}",
            h[0].speed
        );
        let total: f64 = h.iter().map(|b| b.density).sum::<f64>() * width;
        assert!((total - 1.0).abs() < 1e-12);
        // kT = m <v^2> = 1: the weight is in the bins holding -1 and 1, none at 0.
        let at = |v: f64| {
            h.iter()
                .find(|b| (b.speed - v).abs() < width / 2.0)
                .unwrap()
        };
        assert_eq!(at(0.01).density, 0.0);
        assert!(at(1.0 - 1e-9).density + at(1.0 + 1e-9).density > 0.0);
        let peak = (2.0 * std::f64::consts::PI).sqrt().recip();
        let b = at(0.05);
        let expected = peak * (-b.speed * b.speed / 2.0).exp();
        assert!(
            (b.rayleigh - expected).abs() < 1e-12,
            "{} vs {expected}",
            b.rayleigh
        );
    }

    #[test]
    fn a_3d_model_draws_spheres_and_compares_speeds_with_the_3d_law() {
        let discs = [
            edmd_core::Disc::new(
                Vector::new([2.0, 5.0, 5.0]),
                Vector::new([1.0, 0.0, 0.0]),
                0.5,
            ),
            edmd_core::Disc::new(
                Vector::new([8.0, 5.0, 5.0]),
                Vector::new([-1.0, 0.0, 0.0]),
                0.5,
            ),
        ];
        let sim = Simulation::new(&discs, SimBox::walls([10.0; 3]), Options::default()).unwrap();
        let mut m = Model::new(sim, Colouring::File);
        m.run_until(3.5);
        assert_eq!(m.sim.stats().disc_disc, 1);
        match m.scene() {
            AnyScene::Solid(scene, view) => {
                assert_eq!(scene.positions.len(), 2);
                assert_eq!(view, View::default());
            }
            _ => panic!("a 3D model drew discs or rods"),
        }
        m.sample();
        // The law is Maxwell's: its density at the RMS speed 1 for kT = 1/3 (m v^2 = 3 kT).
        let h = m.speeds();
        let b = h
            .iter()
            .min_by(|a, b| (a.speed - 1.0).abs().total_cmp(&(b.speed - 1.0).abs()))
            .unwrap();
        let expected = edmd_core::measure::maxwell_pdf(b.speed, 1.0, 1.0 / 3.0, 3);
        assert!(
            (b.rayleigh - expected).abs() < 1e-12,
            "{} vs {expected}",
            b.rayleigh
        );
    }
}
