//! Fisher-KPP's travelling wave at the minimal speed, the mean profile's comparison.

/// Fisher-KPP's travelling wave at the minimal speed, `u'' + 2 u' + u (1 - u) = 0` (lengths
/// in `xi`), from `u = 1` on the left to 0 on the right, placed with its A-mass position at
/// 0: `(z, u)` every 0.05, and `integral u (1 - u) dz`. Integrated (RK4) from the unstable
/// manifold of `u = 1`, where `1 - u` grows as `exp((sqrt 2 - 1) z)`.
pub(super) fn kpp_wave() -> (Vec<(f64, f64)>, f64) {
    let f = |u: f64, q: f64| (q, -2.0 * q - u * (1.0 - u));
    let (h, w0) = (1e-3, 1e-9);
    let lambda = std::f64::consts::SQRT_2 - 1.0;
    let (mut z, mut u, mut q) = (0.0, 1.0 - w0, -lambda * w0);
    // The A mass ahead of the start (trapezoids), and the width's integral.
    let (mut ahead, mut width) = (0.0, 0.0);
    let mut wave = Vec::new();
    let mut k = 0u64;
    while u > 1e-12 && z < 200.0 {
        if k.is_multiple_of(50) {
            wave.push((z, u));
        }
        let (k1u, k1q) = f(u, q);
        let (k2u, k2q) = f(u + 0.5 * h * k1u, q + 0.5 * h * k1q);
        let (k3u, k3q) = f(u + 0.5 * h * k2u, q + 0.5 * h * k2q);
        let (k4u, k4q) = f(u + h * k3u, q + h * k3q);
        let next = u + h / 6.0 * (k1u + 2.0 * k2u + 2.0 * k3u + k4u);
        q += h / 6.0 * (k1q + 2.0 * k2q + 2.0 * k3q + k4q);
        ahead += 0.5 * h * (u + next);
        width += 0.5 * h * (u * (1.0 - u) + next * (1.0 - next));
        u = next;
        z += h;
        k += 1;
    }
    // Behind the start, `1 - u` adds up to `w0 / lambda`, nothing: the wave holds the A mass
    // of a step at `ahead` from the start.
    (
        wave.into_iter().map(|(z, u)| (z - ahead, u)).collect(),
        width,
    )
}

/// The wave's `u` at `z` (in `xi`), linearly interpolated; 1 behind it, 0 ahead.
pub(super) fn kpp_at(wave: &[(f64, f64)], z: f64) -> f64 {
    match wave.iter().position(|p| p.0 > z) {
        None => 0.0,
        Some(0) => 1.0,
        Some(k) => {
            let (a, b) = (wave[k - 1], wave[k]);
            a.1 + (b.1 - a.1) * (z - a.0) / (b.0 - a.0)
        }
    }
}
