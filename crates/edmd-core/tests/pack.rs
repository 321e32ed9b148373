//! Packings (`edmd_core::pack`): the growing-particle kernels against hand-derived answers,
//! determinism, exactness (no overlaps) and jamming against published values.

use edmd_core::pack::{
    contacts, gap_tolerance, random_start, PackOptions, PackSizes, Packer, Packing, Stop,
};
use edmd_core::{Boundary, Disc, SimBox, Vector};

fn pack<const D: usize>(
    n: usize,
    sizes: PackSizes,
    boundary: Boundary,
    options: PackOptions,
    seed: u64,
) -> Packing<D> {
    let (discs, sim_box) = random_start::<D>(n, sizes, boundary, seed).unwrap();
    Packer::new(&discs, sim_box, options)
        .unwrap()
        .run(|_| true)
        .unwrap()
}

#[test]
#[ignore]
fn timing() {
    for (n, g) in [(1000usize, 0.02), (1000, 0.2)] {
        let t0 = std::time::Instant::now();
        let p = pack::<3>(
            n,
            PackSizes::MONODISPERSE,
            Boundary::Periodic,
            PackOptions {
                growth_rate: g,
                ..PackOptions::default()
            },
            1,
        );
        let s = t0.elapsed().as_secs_f64();
        let c = contacts(
            &p.discs,
            &p.sim_box,
            gap_tolerance(p.reduced_pressure.unwrap(), 3),
        );
        eprintln!(
            "3D n {n} G {g}: phi {:.5} p {:.3e} stop {:?} coll {} events {} rescales {} {:.2}s {:.3e} coll/s rattlers {} z {:.4} min_gap {:.3e}",
            p.packing_fraction, p.reduced_pressure.unwrap(), p.stop, p.collisions, p.events, p.rescales, s,
            p.collisions as f64 / s, c.rattlers, c.mean_contacts, c.min_gap
        );
        for k in 2..16 {
            let tol = 10f64.powi(-k);
            let c = contacts(&p.discs, &p.sim_box, tol);
            let pairs: u64 = c.contacts.iter().map(|&z| z as u64).sum();
            eprintln!(
                "tol 1e-{k}: rattlers {} z {:.4} contacts-of-nonrattlers {}",
                c.rattlers, c.mean_contacts, pairs
            );
        }
    }
}
