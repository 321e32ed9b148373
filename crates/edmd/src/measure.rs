//! `edmd run --measure ...`: the library's measurement observers attached to a run, their time
//! series written as CSV files and their summaries added to the run's summary.

use std::path::{Path, PathBuf};

use anyhow::Result;
use clap::ValueEnum;
use edmd_core::measure::shear_stress::ShearStress;
use edmd_core::measure::{
    kinetic_temperature, Collisions, Conductivity, Diffusion, Energy, Kinetics, Pressure, Rdf,
    SpeciesHalves, Speeds, Temperature, Viscosity,
};
use edmd_core::{EventRecord, Observer, Simulation};
use serde::{Deserialize, Serialize};
use serde_json::{json, Value};

use crate::output::write_csv;

/// A measurement `edmd run` can attach.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, ValueEnum, Serialize, Deserialize)]
pub enum Measure {
    /// Temperature over time: kT = sum m v^2 / 2N.
    Temperature,
    /// Pressure from wall impulses and from the collision virial, and Z = PA/(NkT) (PV/(NkT)
    /// for spheres).
    Pressure,
    /// Collision frequency; free path and free time histograms and means.
    Collisions,
    /// Speed histogram against the Maxwell-Boltzmann law (Rayleigh in 2D), with a KS test.
    Speeds,
    /// Mean square displacement of all discs and the diffusion coefficient.
    Msd,
    /// Fraction of each species in the left and right halves over time.
    Species,
    /// Kinetic, potential and total energy per particle; with a thermostat, the heat capacity
    /// from the fluctuations of the total energy.
    Energy,
    /// The radial distribution function g(r), out to 5 of the largest diameters (or half the
    /// box).
    Rdf,
    /// Reaction kinetics: the number of discs of each species over time, and each reaction
    /// rule's reactions and rate constant k (reactions per unit volume and time = k n_A n_B,
    /// k n_A^2 / 2 for like reactants) with its block error.
    Kinetics,
    /// Shear viscosity by the Einstein-Helfand route, <Delta G^2> / (2 V kT tau) over windows up
    /// to 10 mean collision times, with its block error and Enskog's value (periodic boxes
    /// only).
    Viscosity,
    /// Thermal conductivity by the Einstein-Helfand route, <Delta G^2> / (2 V kT^2 tau) over
    /// windows up to 20 mean collision times, with its block error and Enskog's value (periodic
    /// boxes of equal hard particles only).
    Conductivity,
    /// The shear stress P_xy of a sheared run (Lees-Edwards boundaries) and its viscosity
    /// -P_xy / gamma, exact time integrals in blocks at the sample times, with block errors.
    ShearStress,
}

impl Measure {
    /// The CSV files this measurement writes into the measurement folder.
    pub fn files(self) -> &'static [&'static str] {
        match self {
            Measure::Temperature => &["temperature.csv"],
            Measure::Pressure => &["pressure.csv"],
            Measure::Collisions => &[
                "collision_frequency.csv",
                "free_paths.csv",
                "free_times.csv",
            ],
            Measure::Speeds => &["speeds.csv"],
            Measure::Msd => &["msd.csv"],
            Measure::Species => &["species.csv"],
            Measure::Energy => &["energy.csv"],
            Measure::Rdf => &["rdf.csv"],
            Measure::Kinetics => &["kinetics.csv"],
            Measure::Viscosity => &["viscosity.csv"],
            Measure::Conductivity => &["conductivity.csv"],
            Measure::ShearStress => &["shear_stress.csv"],
        }
    }
}

/// The attached measurements (kept in checkpoints, so that a continued run goes on measuring
/// where it stopped).
#[derive(Serialize, Deserialize)]
pub struct Measurements<const D: usize = 2> {
    temperature: Option<Temperature>,
    pressure: Option<Pressure>,
    collisions: Option<Collisions>,
    speeds: Option<Speeds>,
    msd: Option<Diffusion<D>>,
    species: Option<SpeciesHalves>,
    energy: Option<Energy>,
    rdf: Option<Rdf>,
    kinetics: Option<Kinetics>,
    viscosity: Option<Viscosity>,
    conductivity: Option<Conductivity>,
    shear_stress: Option<ShearStress>,
}

/// [`Measurements`] as checkpoints kept them before `shear_stress` was measured: read back,
/// they go on as measurements without it.
#[derive(Deserialize)]
#[serde(bound = "")]
pub(crate) struct MeasurementsBeforeShearStress<const D: usize> {
    temperature: Option<Temperature>,
    pressure: Option<Pressure>,
    collisions: Option<Collisions>,
    speeds: Option<Speeds>,
    msd: Option<Diffusion<D>>,
    species: Option<SpeciesHalves>,
    energy: Option<Energy>,
    rdf: Option<Rdf>,
    kinetics: Option<Kinetics>,
    viscosity: Option<Viscosity>,
    conductivity: Option<Conductivity>,
}

impl<const D: usize> From<MeasurementsBeforeShearStress<D>> for Measurements<D> {
    fn from(m: MeasurementsBeforeShearStress<D>) -> Self {
        Measurements {
            temperature: m.temperature,
            pressure: m.pressure,
            collisions: m.collisions,
            speeds: m.speeds,
            msd: m.msd,
            species: m.species,
            energy: m.energy,
            rdf: m.rdf,
            kinetics: m.kinetics,
            viscosity: m.viscosity,
            conductivity: m.conductivity,
            shear_stress: None,
        }
    }
}

/// [`Measurements`] as checkpoints kept them before `conductivity` was measured: read back,
/// they go on as measurements without it.
#[derive(Deserialize)]
#[serde(bound = "")]
pub(crate) struct MeasurementsBeforeConductivity<const D: usize> {
    temperature: Option<Temperature>,
    pressure: Option<Pressure>,
    collisions: Option<Collisions>,
    speeds: Option<Speeds>,
    msd: Option<Diffusion<D>>,
    species: Option<SpeciesHalves>,
    energy: Option<Energy>,
    rdf: Option<Rdf>,
    kinetics: Option<Kinetics>,
    viscosity: Option<Viscosity>,
}

impl<const D: usize> From<MeasurementsBeforeConductivity<D>> for Measurements<D> {
    fn from(m: MeasurementsBeforeConductivity<D>) -> Self {
        Measurements {
            temperature: m.temperature,
            pressure: m.pressure,
            collisions: m.collisions,
            speeds: m.speeds,
            msd: m.msd,
            species: m.species,
            energy: m.energy,
            rdf: m.rdf,
            kinetics: m.kinetics,
            viscosity: m.viscosity,
            conductivity: None,
            shear_stress: None,
        }
    }
}

/// [`Measurements`] as checkpoints kept them before `viscosity` was measured: read back, they
/// go on as measurements without it.
#[derive(Deserialize)]
#[serde(bound = "")]
pub(crate) struct MeasurementsBeforeViscosity<const D: usize> {
    temperature: Option<Temperature>,
    pressure: Option<Pressure>,
    collisions: Option<Collisions>,
    speeds: Option<Speeds>,
    msd: Option<Diffusion<D>>,
    species: Option<SpeciesHalves>,
    energy: Option<Energy>,
    rdf: Option<Rdf>,
    kinetics: Option<Kinetics>,
}

impl<const D: usize> From<MeasurementsBeforeViscosity<D>> for Measurements<D> {
    fn from(m: MeasurementsBeforeViscosity<D>) -> Self {
        Measurements {
            temperature: m.temperature,
            pressure: m.pressure,
            collisions: m.collisions,
            speeds: m.speeds,
            msd: m.msd,
            species: m.species,
            energy: m.energy,
            rdf: m.rdf,
            kinetics: m.kinetics,
            viscosity: None,
            conductivity: None,
            shear_stress: None,
        }
    }
}

/// [`Measurements`] as checkpoints kept them before `kinetics` was measured: read back, they go
/// on as measurements without it.
#[derive(Deserialize)]
#[serde(bound = "")]
pub(crate) struct MeasurementsBeforeKinetics<const D: usize> {
    temperature: Option<Temperature>,
    pressure: Option<Pressure>,
    collisions: Option<Collisions>,
    speeds: Option<Speeds>,
    msd: Option<Diffusion<D>>,
    species: Option<SpeciesHalves>,
    energy: Option<Energy>,
    rdf: Option<Rdf>,
}

impl<const D: usize> From<MeasurementsBeforeKinetics<D>> for Measurements<D> {
    fn from(m: MeasurementsBeforeKinetics<D>) -> Self {
        Measurements {
            temperature: m.temperature,
            pressure: m.pressure,
            collisions: m.collisions,
            speeds: m.speeds,
            msd: m.msd,
            species: m.species,
            energy: m.energy,
            rdf: m.rdf,
            kinetics: None,
            viscosity: None,
            conductivity: None,
            shear_stress: None,
        }
    }
}

/// [`Measurements`] as checkpoints kept them before `energy` and `rdf` were measured: read
/// back, they go on as measurements with neither.
#[derive(Deserialize)]
#[serde(bound = "")]
pub(crate) struct MeasurementsBefore<const D: usize> {
    temperature: Option<Temperature>,
    pressure: Option<Pressure>,
    collisions: Option<Collisions>,
    speeds: Option<Speeds>,
    msd: Option<Diffusion<D>>,
    species: Option<SpeciesHalves>,
}

impl<const D: usize> From<MeasurementsBefore<D>> for Measurements<D> {
    fn from(m: MeasurementsBefore<D>) -> Self {
        Measurements {
            temperature: m.temperature,
            pressure: m.pressure,
            collisions: m.collisions,
            speeds: m.speeds,
            msd: m.msd,
            species: m.species,
            energy: None,
            rdf: None,
            kinetics: None,
            viscosity: None,
            conductivity: None,
            shear_stress: None,
        }
    }
}

impl<const D: usize> Measurements<D> {
    /// Starts the chosen measurements on `sim` at its current time.
    pub fn new(sim: &Simulation<D>, which: &[Measure]) -> Self {
        let has = |m| which.contains(&m);
        let kt = kinetic_temperature(sim).max(f64::MIN_POSITIVE);
        let m_min = (0..sim.len())
            .map(|i| sim.mass(i))
            .fold(f64::INFINITY, f64::min);
        let v_scale = (kt / m_min).sqrt();
        // Free paths: histogram range from the box size (dilute gases) down to the discs.
        let l = sim
            .sim_box()
            .lengths
            .iter()
            .cloned()
            .fold(f64::INFINITY, f64::min);
        // The histograms need finite positive ranges; a system with no disc, none moving, or
        // masses or a box at the ends of the floating-point range gives none, and then the
        // unit range stands in (the histograms are empty or hold only zeros anyway).
        let range = |x: f64| if x.is_finite() && x > 0.0 { x } else { 1.0 };
        let (max_path, max_time, max_speed) = (range(l), range(l / v_scale), range(5.0 * v_scale));
        Measurements {
            temperature: has(Measure::Temperature).then(Temperature::new),
            pressure: has(Measure::Pressure).then(|| Pressure::new(sim)),
            collisions: has(Measure::Collisions)
                .then(|| Collisions::new(sim, 50, max_path, max_time)),
            speeds: has(Measure::Speeds).then(|| Speeds::new(40, max_speed)),
            msd: has(Measure::Msd).then(|| Diffusion::new(sim)),
            species: has(Measure::Species).then(|| SpeciesHalves::new(sim, 0)),
            energy: has(Measure::Energy).then(Energy::new),
            rdf: has(Measure::Rdf).then(|| {
                let largest = (0..sim.len())
                    .map(|i| 2.0 * sim.radius(i))
                    .fold(0.0, f64::max);
                Rdf::new(sim, range(5.0 * largest), 250)
            }),
            kinetics: has(Measure::Kinetics).then(|| Kinetics::new(sim)),
            viscosity: has(Measure::Viscosity).then(|| Viscosity::for_fluid(sim)),
            conductivity: has(Measure::Conductivity).then(|| Conductivity::for_fluid(sim)),
            shear_stress: has(Measure::ShearStress)
                .then(|| ShearStress::new(sim))
                .flatten(),
        }
    }

    /// Refuses measurements that cannot be taken on `sim` (the viscosity in a box with walls,
    /// the thermal conductivity of a mixture, the shear stress without shear), with a one-line
    /// message; the run's front door calls it before [`Self::new`].
    pub fn check(sim: &Simulation<D>, which: &[Measure]) -> Result<()> {
        if D == 1 {
            for (m, name, why) in [
                (
                    Measure::Speeds,
                    "speeds",
                    "a line's speeds are |v| of a Gaussian, not the Maxwell-Boltzmann law in 2 or 3 dimensions it is compared with",
                ),
                (
                    Measure::Viscosity,
                    "viscosity",
                    "the shear viscosity needs a second axis to shear across",
                ),
                (
                    Measure::Conductivity,
                    "conductivity",
                    "equal hard rods only exchange velocities, so heat is carried ballistically and the conductivity has no finite value",
                ),
                (
                    Measure::ShearStress,
                    "shear-stress",
                    "shear needs a second axis to slide the images across",
                ),
            ] {
                if which.contains(&m) {
                    return crate::user_error(format!(
                        "--measure {name}: not on a line (1D): {why}"
                    ));
                }
            }
        }
        if which.contains(&Measure::Viscosity) {
            if let Some(why) = edmd_core::measure::viscosity::unsupported(sim) {
                return crate::user_error(format!("--measure viscosity: {why}"));
            }
        }
        if which.contains(&Measure::Conductivity) {
            if let Some(why) = edmd_core::measure::conductivity::unsupported(sim) {
                return crate::user_error(format!("--measure conductivity: {why}"));
            }
        }
        if which.contains(&Measure::ShearStress) && ShearStress::new(sim).is_none() {
            return crate::user_error(
                "--measure shear-stress: needs shear (Lees-Edwards boundaries, '# edmd shear RATE' \
                 or edmd gen --shear)",
            );
        }
        Ok(())
    }

    /// Whether these measurements can go on observing `sim` (checked on measurements read back
    /// from a checkpoint).
    pub fn fits(&self, sim: &Simulation<D>) -> bool {
        self.collisions.as_ref().is_none_or(|m| m.fits(sim))
            && self.msd.as_ref().is_none_or(|m| m.fits(sim))
            && self.species.as_ref().is_none_or(|m| m.fits(sim))
            && self.kinetics.as_ref().is_none_or(|m| kinetics_fits(m, sim))
            && self.viscosity.as_ref().is_none_or(|m| m.fits(sim))
            && self.conductivity.as_ref().is_none_or(|m| m.fits(sim))
            && self.shear_stress.as_ref().is_none_or(|m| m.fits(sim))
    }

    /// Takes a sample of every measurement at the simulation's current time.
    pub fn sample(&mut self, sim: &Simulation<D>) {
        if let Some(m) = &mut self.temperature {
            m.sample(sim);
        }
        if let Some(m) = &mut self.pressure {
            m.sample(sim);
        }
        if let Some(m) = &mut self.collisions {
            m.sample(sim);
        }
        if let Some(m) = &mut self.speeds {
            m.sample(sim);
        }
        if let Some(m) = &mut self.msd {
            m.sample(sim);
        }
        if let Some(m) = &mut self.species {
            m.sample(sim);
        }
        if let Some(m) = &mut self.energy {
            m.sample(sim);
        }
        if let Some(m) = &mut self.rdf {
            m.sample(sim);
        }
        if let Some(m) = &mut self.kinetics {
            m.sample(sim);
        }
        if let Some(m) = &mut self.viscosity {
            m.sample(sim);
        }
        if let Some(m) = &mut self.conductivity {
            m.sample(sim);
        }
        if let Some(m) = &mut self.shear_stress {
            m.sample(sim);
        }
    }

    /// Writes the CSV files into `dir` and returns the summaries (as JSON) and the files.
    pub fn finish(&self, sim: &Simulation<D>, dir: &Path) -> Result<(Value, Vec<PathBuf>)> {
        std::fs::create_dir_all(dir).map_err(|e| {
            crate::UserError(format!(
                "{}: cannot create the measurement folder: {e}",
                dir.display()
            ))
        })?;
        let (out, tables) = self.results(sim);
        let mut files = Vec::new();
        for t in tables {
            let p = dir.join(t.file);
            let header: Vec<&str> = t.header.iter().map(String::as_str).collect();
            write_csv(&p, &header, t.rows)?;
            files.push(p);
        }
        Ok((out, files))
    }

    /// The summaries (as JSON) and the time series and histograms, as the tables
    /// [`Self::finish`] writes (the Python package turns them into dicts and arrays).
    pub fn results(&self, sim: &Simulation<D>) -> (Value, Vec<Table>) {
        let mut tables = Vec::new();
        let mut out = serde_json::Map::new();
        let mut csv = |name: &'static str, header: &[&str], rows: Vec<Vec<f64>>| {
            tables.push(Table {
                file: name,
                header: header.iter().map(|h| h.to_string()).collect(),
                rows,
            });
        };
        if let Some(m) = &self.temperature {
            csv(
                "temperature.csv",
                &["time", "kT"],
                m.series().iter().map(|&(t, k)| vec![t, k]).collect(),
            );
            let s = m.summary();
            out.insert(
                "temperature".into(),
                json!({"samples": s.samples, "mean": s.mean, "min": s.min, "max": s.max}),
            );
        }
        if let Some(m) = &self.pressure {
            let rows = m
                .blocks()
                .iter()
                .map(|b| vec![b.start, b.end, b.virial, b.wall.unwrap_or(f64::NAN), b.z])
                .collect();
            csv(
                "pressure.csv",
                &["start", "end", "virial_pressure", "wall_pressure", "Z"],
                rows,
            );
            let s = m.summary();
            let est = |e: &edmd_core::measure::Estimate| json!({"value": e.value, "error": e.error, "blocks": e.blocks});
            let mut j = json!({"kT": s.kt, "virial": est(&s.virial),
                       "wall": s.wall.as_ref().map(est), "Z": est(&s.z), "Z_wall": s.z_wall.as_ref().map(est)});
            // The box's measure: an area in 2D (the names stay as they were), a volume in 3D,
            // a length on a line.
            let size = match D {
                1 => "length",
                3 => "volume",
                _ => "area",
            };
            j[size] = json!(s.area);
            j[format!("effective_{size}")] = json!(s.effective_area);
            out.insert("pressure".into(), j);
        }
        if let Some(m) = &self.collisions {
            csv(
                "collision_frequency.csv",
                &[
                    "time",
                    if D == 3 {
                        "collisions_per_sphere_per_time"
                    } else {
                        "collisions_per_disc_per_time"
                    },
                ],
                m.frequency_series()
                    .iter()
                    .map(|&(t, f)| vec![t, f])
                    .collect(),
            );
            csv(
                "free_paths.csv",
                &["free_path", "density"],
                m.free_path_histogram()
                    .density()
                    .iter()
                    .map(|&(x, y)| vec![x, y])
                    .collect(),
            );
            csv(
                "free_times.csv",
                &["free_time", "density"],
                m.free_time_histogram()
                    .density()
                    .iter()
                    .map(|&(x, y)| vec![x, y])
                    .collect(),
            );
            let s = m.summary();
            out.insert(
                "collisions".into(),
                json!({"disc_disc": s.disc_disc, "wall": s.wall, "frequency": {"value": s.frequency.value, "error": s.frequency.error},
                       "wall_frequency": s.wall_frequency, "flights": s.flights, "mean_free_path": s.mean_free_path, "mean_free_time": s.mean_free_time}),
            );
        }
        if let Some(m) = &self.speeds {
            let kt = kinetic_temperature(sim);
            // The 2D names stay as they were; in 3D the law is Maxwell's.
            let law = if D == 2 { "rayleigh" } else { "maxwell" };
            csv(
                "speeds.csv",
                &["speed", "density", &format!("{law}_density")],
                m.histogram_vs_maxwell(kt)
                    .iter()
                    .map(|&(v, h, r)| vec![v, h, r])
                    .collect(),
            );
            let s = m.summary(kt);
            let mut j = json!({"samples": s.samples, "mean": s.mean, "rms": s.rms,
                       "ks_statistic": s.ks.statistic, "ks_p_value": s.ks.p_value});
            j[format!("mean_{law}")] = json!(s.mean_theory);
            j[format!("rms_{law}")] = json!(s.rms_theory);
            out.insert("speeds".into(), j);
        }
        if let Some(m) = &self.msd {
            csv(
                "msd.csv",
                &["time", "msd"],
                m.series().iter().map(|&(t, d)| vec![t, d]).collect(),
            );
            let fit = m.summary();
            out.insert("msd".into(), json!({"diffusion_coefficient": fit.map(|f| f.coefficient), "fit_from": fit.map(|f| f.from), "fit_to": fit.map(|f| f.to)}));
        }
        if let Some(m) = &self.species {
            let n_species = m.snapshots().first().map_or(0, |s| s.counts.len());
            let mut header = vec!["time".to_string()];
            for s in 0..n_species {
                header.push(format!("species{s}_left"));
                header.push(format!("species{s}_right"));
            }
            let rows = m
                .snapshots()
                .iter()
                .map(|snap| {
                    let mut row = vec![snap.time];
                    for c in &snap.counts {
                        row.extend([c[0] as f64, c[1] as f64]);
                    }
                    row
                })
                .collect();
            let h: Vec<&str> = header.iter().map(String::as_str).collect();
            csv("species.csv", &h, rows);
            let s = m.summary();
            out.insert(
                "species".into(),
                json!({"samples": s.samples, "overall": s.overall, "last": s.last}),
            );
        }
        if let Some(m) = &self.energy {
            let n = sim.len().max(1) as f64;
            csv(
                "energy.csv",
                &[
                    "time",
                    "kinetic_per_particle",
                    "potential_per_particle",
                    "total_per_particle",
                ],
                m.series()
                    .iter()
                    .map(|&(t, k, u)| vec![t, k / n, u / n, (k + u) / n])
                    .collect(),
            );
            let s = m.summary();
            let est = |e: &edmd_core::measure::Estimate| json!({"value": e.value, "error": e.error, "blocks": e.blocks});
            out.insert(
                "energy".into(),
                json!({"samples": s.samples,
                       "potential_per_particle": est(&s.potential_per_particle),
                       "kinetic_per_particle": est(&s.kinetic_per_particle),
                       "total_per_particle": est(&s.total_per_particle),
                       "relative_drift": if s.drift.is_nan() { Value::Null } else { json!(s.drift) },
                       "heat_capacity_per_particle": s.heat_capacity.as_ref().map(est)}),
            );
        }
        if let Some(m) = &self.rdf {
            let curve = m.curve::<D>();
            csv(
                "rdf.csv",
                &["r", "g"],
                curve.iter().map(|&(r, g)| vec![r, g]).collect(),
            );
            // The first peak: where g is largest.
            let peak = curve
                .iter()
                .copied()
                .fold(
                    (f64::NAN, f64::NEG_INFINITY),
                    |a, b| if b.1 > a.1 { b } else { a },
                );
            out.insert(
                "rdf".into(),
                json!({"samples": m.samples(), "r_max": m.r_max(), "bins": curve.len(),
                       "peak_r": peak.0, "peak_g": if curve.is_empty() { Value::Null } else { json!(peak.1) }}),
            );
        }
        if let Some(m) = &self.kinetics {
            let width = m.counts().len();
            let mut header = vec!["time".to_string()];
            header.extend((0..width).map(|s| format!("species{s}")));
            let rows = m
                .series()
                .iter()
                .map(|(t, counts)| {
                    let mut row = vec![*t];
                    row.extend(counts.iter().map(|&c| c as f64));
                    row
                })
                .collect();
            let h: Vec<&str> = header.iter().map(String::as_str).collect();
            csv("kinetics.csv", &h, rows);
            let rules: Vec<Value> = m
                .rates()
                .iter()
                .map(|r| {
                    let [a, b, c, d] = r.rule;
                    let k = &r.rate_constant;
                    json!({"rule": format!("{a} + {b} -> {c} + {d}"), "reactants": [a, b],
                           "products": [c, d], "reactions": r.reactions, "exposure": r.exposure,
                           "rate_constant": {"value": k.value, "error": k.error, "blocks": k.blocks}})
                })
                .collect();
            out.insert(
                "kinetics".into(),
                json!({"samples": m.series().len() - 1, "duration": m.duration(),
                       "counts": m.counts(), "rules": rules}),
            );
        }
        if let Some(m) = &self.viscosity {
            csv(
                "viscosity.csv",
                &["tau", "eta_tau", "mean_square_delta_g"],
                m.curve()
                    .iter()
                    .map(|&(tau, eta, msq)| vec![tau, eta, msq])
                    .collect(),
            );
            let s = m.summary();
            // Before a block closes the values are NaN, which JSON has no word for.
            let num = |x: f64| if x.is_finite() { json!(x) } else { Value::Null };
            out.insert(
                "viscosity".into(),
                json!({"eta": num(s.eta.value), "eta_error": num(s.eta.error), "blocks": s.eta.blocks,
                       "eta_enskog": num(s.eta_enskog), "eta_at_window": num(s.eta_at_window),
                       "window": s.window, "fit_from": s.fit_from, "spacing": s.spacing,
                       "kT": num(s.kt), "elapsed": s.elapsed, "packing": s.packing}),
            );
        }
        if let Some(m) = &self.conductivity {
            csv(
                "conductivity.csv",
                &["tau", "lambda_tau", "mean_square_delta_g"],
                m.curve()
                    .iter()
                    .map(|&(tau, lambda, msq)| vec![tau, lambda, msq])
                    .collect(),
            );
            let s = m.summary();
            let num = |x: f64| if x.is_finite() { json!(x) } else { Value::Null };
            out.insert(
                "conductivity".into(),
                json!({"lambda": num(s.lambda.value), "lambda_error": num(s.lambda.error),
                       "blocks": s.lambda.blocks, "lambda_enskog": num(s.lambda_enskog),
                       "lambda_0": num(s.lambda_0), "lambda_at_window": num(s.lambda_at_window),
                       "window": s.window, "fit_from": s.fit_from, "spacing": s.spacing,
                       "kT": num(s.kt), "elapsed": s.elapsed, "packing": s.packing}),
            );
        }
        if let Some(m) = &self.shear_stress {
            csv(
                "shear_stress.csv",
                &["start", "end", "kinetic", "collisional", "pxy", "kt", "eta"],
                m.blocks()
                    .iter()
                    .map(|b| {
                        let pxy = b.kinetic + b.collisional;
                        vec![b.start, b.end, b.kinetic, b.collisional, pxy, b.kt, b.eta]
                    })
                    .collect(),
            );
            // The reduced rate is taken with the mean diameter and mass.
            let n = sim.len().max(1) as f64;
            let sigma = (0..sim.len()).map(|i| 2.0 * sim.radius(i)).sum::<f64>() / n;
            let mass = (0..sim.len()).map(|i| sim.mass(i)).sum::<f64>() / n;
            let num = |x: f64| if x.is_finite() { json!(x) } else { Value::Null };
            // Before the first block closes there is no summary: nulls, and no blocks.
            let j = match m.summary(sigma, mass) {
                Some(s) => json!({"eta": num(s.eta.value), "eta_error": num(s.eta.error),
                       "pxy": num(s.pxy.value), "pxy_error": num(s.pxy.error),
                       "kt": num(s.kt.value), "kt_error": num(s.kt.error),
                       "kinetic": num(s.kinetic), "collisional": num(s.collisional),
                       "rate": s.rate, "reduced_rate": num(s.reduced_rate),
                       "blocks": s.eta.blocks, "elapsed": s.elapsed}),
                None => json!({"eta": null, "eta_error": null, "pxy": null, "pxy_error": null,
                       "kt": null, "kt_error": null, "kinetic": null, "collisional": null,
                       "rate": sim.shear().map(|s| s.rate), "reduced_rate": null,
                       "blocks": 0, "elapsed": 0.0}),
            };
            out.insert("shear_stress".into(), j);
        }
        (Value::Object(out), tables)
    }
}

/// Whether kinetics read back from a checkpoint can go on observing `sim`: the same rules, and
/// the species counts it has reached those of the simulation's discs (both kept exactly).
fn kinetics_fits<const D: usize>(k: &Kinetics, sim: &Simulation<D>) -> bool {
    let rules: Vec<[u16; 4]> = sim.reactions().map_or_else(Vec::new, |r| {
        r.rules
            .iter()
            .map(|r| [r.reactants.0, r.reactants.1, r.products.0, r.products.1])
            .collect()
    });
    let mut counts = vec![0usize; k.counts().len()];
    for i in 0..sim.len() {
        match counts.get_mut(sim.species(i) as usize) {
            Some(c) => *c += 1,
            None => return false,
        }
    }
    counts == k.counts() && k.rates().iter().map(|r| r.rule).eq(rules)
}

/// One table of results: the CSV file it is written to, its column names and rows.
#[derive(Clone, Debug)]
pub struct Table {
    /// File name in the measurement folder.
    pub file: &'static str,
    /// Column names.
    pub header: Vec<String>,
    /// Rows of numbers.
    pub rows: Vec<Vec<f64>>,
}

impl<const D: usize> Observer<D> for Measurements<D> {
    fn on_event(&mut self, e: &EventRecord<D>, sim: &Simulation<D>) {
        if let Some(m) = &mut self.pressure {
            m.on_event(e, sim);
        }
        if let Some(m) = &mut self.collisions {
            m.on_event(e, sim);
        }
        if let Some(m) = &mut self.kinetics {
            m.on_event(e, sim);
        }
        if let Some(m) = &mut self.viscosity {
            m.on_event(e, sim);
        }
        if let Some(m) = &mut self.conductivity {
            m.on_event(e, sim);
        }
        if let Some(m) = &mut self.shear_stress {
            m.on_event(e, sim);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::checkpoint::{checkpoint_bytes, from_checkpoint_bytes, Measuring};
    use edmd_core::setup::lattice_fluid_in;
    use edmd_core::{Boundary, Options};
    use edmd_io::Format;

    /// A checkpoint written before the thermal conductivity was measured, with the viscosity
    /// under way (its extra bytes end where today's `conductivity` would begin), is read back
    /// with the viscosity it had, which goes on to the same results.
    #[test]
    fn a_viscosity_from_before_the_conductivity_reads_back_and_goes_on() {
        let (discs, bx) = lattice_fluid_in::<3>(64, 0.3, Boundary::Periodic, 1).unwrap();
        let mut sim = Simulation::new(&discs, bx, Options::default()).unwrap();
        let which = [Measure::Viscosity];
        let mut m = Measuring::new(&sim, &which, 0.5);
        assert!(m.run_to(&mut sim, 2.0).unwrap());
        let now = checkpoint_bytes(&sim, Format::Course, Some(&m)).unwrap();
        let (_, extra) = Simulation::<3>::from_checkpoint(&now).unwrap();
        // `conductivity: None` and `shear_stress: None` are the last two bytes, 0.
        assert_eq!(extra[extra.len() - 2..], [0, 0]);
        let before = sim.to_checkpoint(&extra[..extra.len() - 2]);
        let (mut sim2, _, back) = from_checkpoint_bytes::<3>(&before).unwrap();
        let mut back = back.unwrap();
        assert_eq!((back.which.clone(), back.samples), (which.to_vec(), 4));
        assert!(m.run_to(&mut sim, 30.0).unwrap());
        assert!(back.run_to(&mut sim2, 30.0).unwrap());
        let (a, b) = (m.obs.results(&sim).0, back.obs.results(&sim2).0);
        assert!(a["viscosity"]["blocks"].as_u64().unwrap() > 0);
        assert_eq!(a, b);
    }

    /// The conductivity is refused where the viscosity is, and for a mixture, with the
    /// one-line message the front doors print.
    #[test]
    fn the_conductivity_is_refused_in_a_box_with_walls_and_for_a_mixture() {
        let (discs, bx) = lattice_fluid_in::<2>(16, 0.2, Boundary::Walls, 1).unwrap();
        let sim = Simulation::new(&discs, bx, Options::default()).unwrap();
        let e = Measurements::check(&sim, &[Measure::Conductivity]).unwrap_err();
        assert_eq!(
            e.to_string(),
            "--measure conductivity: the thermal conductivity needs a periodic box (no walls on any axis)"
        );
        let (mut discs, bx) = lattice_fluid_in::<2>(16, 0.2, Boundary::Periodic, 1).unwrap();
        discs[0].radius *= 0.9;
        let sim = Simulation::new(&discs, bx, Options::default()).unwrap();
        let e = Measurements::check(&sim, &[Measure::Conductivity]).unwrap_err();
        assert!(e.to_string().contains("one mass and one diameter"), "{e}");
        assert!(Measurements::check(&sim, &[Measure::Viscosity]).is_ok());
    }

    /// A sheared fluid of 64 discs at packing 0.3, rate 0.2 from the streaming profile, held at
    /// kT 1 by the thermostat.
    fn sheared_fluid() -> Simulation<2> {
        let (discs, bx) = lattice_fluid_in::<2>(64, 0.3, Boundary::Periodic, 1).unwrap();
        let mut sim = Simulation::new(&discs, bx, Options::default()).unwrap();
        let rate = 0.2;
        sim.set_shear(Some(edmd_core::Shear::new(rate))).unwrap();
        let ly = bx.lengths[1];
        let ys: Vec<f64> = (0..sim.len()).map(|i| sim.position(i)[1]).collect();
        sim.modify_velocities(|i, mut v| {
            v[0] += rate * (ys[i] - 0.5 * ly);
            v
        });
        sim.set_thermostat(Some(edmd_core::Andersen {
            kt: 1.0,
            rate: 0.5,
            seed: 1,
        }))
        .unwrap();
        sim
    }

    /// The shear stress of a sheared fluid: a block at each sample, a finite positive
    /// viscosity, the CSV table and the summary; a checkpoint carries it on.
    #[test]
    fn the_shear_stress_of_a_sheared_fluid_gives_a_positive_viscosity() {
        let mut sim = sheared_fluid();
        let which = [Measure::ShearStress];
        assert!(Measurements::check(&sim, &which).is_ok());
        let mut m = Measuring::new(&sim, &which, 5.0);
        assert!(m.run_to(&mut sim, 100.0).unwrap());
        let (out, tables) = m.obs.results(&sim);
        let s = &out["shear_stress"];
        assert_eq!(s["blocks"].as_u64(), Some(20), "{s}");
        let (eta, error) = (s["eta"].as_f64().unwrap(), s["eta_error"].as_f64().unwrap());
        assert!(eta.is_finite() && eta > 0.0 && error.is_finite(), "{s}");
        assert!(s["pxy"].as_f64().unwrap() < 0.0, "{s}");
        assert_eq!(s["rate"].as_f64(), Some(0.2));
        let kt = s["kt"].as_f64().unwrap();
        assert!((kt - 1.0).abs() < 0.2, "{s}");
        assert_eq!(tables.len(), 1);
        assert_eq!(tables[0].file, "shear_stress.csv");
        assert_eq!(tables[0].rows.len(), 20);
        assert_eq!(tables[0].header[4], "pxy");
        // Kept in a checkpoint, it goes on.
        let bytes = checkpoint_bytes(&sim, Format::Course, Some(&m)).unwrap();
        let (_, _, back) = from_checkpoint_bytes::<2>(&bytes).unwrap();
        assert_eq!(back.unwrap().obs.results(&sim).0, out);
    }

    /// Without shear, or at rate 0, the shear stress is refused with the one-line message the
    /// front doors print.
    #[test]
    fn the_shear_stress_is_refused_without_shear() {
        let (discs, bx) = lattice_fluid_in::<2>(16, 0.2, Boundary::Periodic, 1).unwrap();
        let mut sim = Simulation::new(&discs, bx, Options::default()).unwrap();
        let want = "--measure shear-stress: needs shear (Lees-Edwards boundaries, '# edmd shear \
                    RATE' or edmd gen --shear)";
        let e = Measurements::check(&sim, &[Measure::ShearStress]).unwrap_err();
        assert_eq!(e.to_string(), want);
        sim.set_shear(Some(edmd_core::Shear::new(0.0))).unwrap();
        let e = Measurements::check(&sim, &[Measure::ShearStress]).unwrap_err();
        assert_eq!(e.to_string(), want);
    }

    /// A checkpoint written before the shear stress was measured (its extra bytes end where
    /// today's `shear_stress` would begin) is read back with the measurements it had.
    #[test]
    fn measurements_from_before_the_shear_stress_read_back() {
        let mut sim = sheared_fluid();
        let which = [Measure::Temperature];
        let mut m = Measuring::new(&sim, &which, 0.5);
        assert!(m.run_to(&mut sim, 2.0).unwrap());
        let now = checkpoint_bytes(&sim, Format::Course, Some(&m)).unwrap();
        let (_, extra) = Simulation::<2>::from_checkpoint(&now).unwrap();
        // `shear_stress: None` is the last byte, 0.
        assert_eq!(extra.last(), Some(&0));
        let before = sim.to_checkpoint(&extra[..extra.len() - 1]);
        let (_, _, back) = from_checkpoint_bytes::<2>(&before).unwrap();
        let back = back.unwrap();
        assert_eq!((back.which, back.samples), (which.to_vec(), 4));
        assert_eq!(back.obs.results(&sim).0, m.obs.results(&sim).0);
    }
}
