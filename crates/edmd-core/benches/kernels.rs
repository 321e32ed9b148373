//! Criterion benchmarks of the kernels and the event queue (`cargo bench -p edmd-core`).
//! Whole-run speed is `edmd bench`, recorded in BENCHMARKS.md.

#![allow(missing_docs)] // criterion's macros generate undocumented items

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use edmd_core::predict::{contact_root, contact_terms, contact_time_or_inf, interval_exit};
use edmd_core::schedule::{CalendarQueue, EventQueue, TournamentQueue};
use edmd_core::Vector;

fn kernels(c: &mut Criterion) {
    // A mix of approaching, separating and missing pairs.
    let pairs: Vec<(Vector, Vector)> = (0..1024)
        .map(|k| {
            let a = k as f64 * 0.37;
            (
                Vector::new([1.5 * a.cos(), 1.5 * a.sin()]),
                Vector::new([(a * 1.7).sin(), (a * 2.3).cos()]),
            )
        })
        .collect();
    c.bench_function("disc_disc_1024_pairs", |b| {
        b.iter(|| {
            let mut best = f64::INFINITY;
            for &(dr, dv) in &pairs {
                best = best.min(contact_time_or_inf(black_box(dr), black_box(dv), 1.0));
            }
            best
        })
    });
    // As a prediction does it (`simulation/predict.rs`, `Nearest`): every pair's terms, then
    // the roots of those that meet only.
    c.bench_function("disc_disc_1024_pairs_terms_then_roots", |b| {
        b.iter(|| {
            let mut best = f64::INFINITY;
            for &(dr, dv) in &pairs {
                let terms = contact_terms::<2, false>(black_box(dr), black_box(dv), 1.0);
                if terms.meets() {
                    best = best.min(contact_root(terms));
                }
            }
            best
        })
    });
    c.bench_function("interval_exit", |b| {
        b.iter(|| interval_exit(black_box(0.3), black_box(-0.7), 0.1, 0.9))
    });
}

/// Pops the front disc and reschedules it, and moves another disc's time on, as an event does.
fn pop_and_reschedule<Q: EventQueue>(c: &mut Criterion, name: &str, n: usize) {
    let mut q = Q::with_len(n);
    q.begin_bulk();
    for i in 0..n {
        q.set(i, (i as f64 * 0.618).fract());
    }
    q.end_bulk(0.0);
    let mut k = 0usize;
    c.bench_function(&format!("{name}_pop_and_reschedule_{n}"), |b| {
        b.iter(|| {
            let (i, t) = q.min().unwrap();
            k = (k + 7919) % n;
            q.set(i, t + 1.0 + (k as f64 * 1e-6));
            q.set(k, q.get(k) + 1e-3);
        })
    });
}

fn queue(c: &mut Criterion) {
    for n in [10_000usize, 1_000_000] {
        pop_and_reschedule::<TournamentQueue>(c, "tournament", n);
        pop_and_reschedule::<CalendarQueue>(c, "calendar", n);
    }
}

criterion_group!(benches, kernels, queue);
criterion_main!(benches);
