//! The text table printed after the runs.

use super::super::common::files_line;
use super::equilibrium::Row;
use super::prigogine_xhrouet::PxRun;
use super::ReactionArgs;

pub(super) fn human(
    args: &ReactionArgs,
    rows: &[Row],
    px: &[PxRun],
    interrupted: bool,
    files: &[std::path::PathBuf],
) -> String {
    let mut s = format!(
        "reactive collisions A + B -> B + A in equilibrium, {} runs of {} discs (spheres), {} collisions per disc each:\n  dim  packing  E*/kT  fraction    error  exp(-E*/kT)   dev/err        k    error   k theory  dev\n",
        args.runs, args.n, args.collisions
    );
    for r in rows {
        let sigmas = if r.reactive_fraction_error > 0.0 {
            format!(
                "{:+8.1}",
                (r.reactive_fraction - r.reactive_fraction_theory) / r.reactive_fraction_error
            )
        } else {
            "       -".into()
        };
        s += &format!(
            "  {:3}  {:7.3}  {:5.2}  {:8.5}  {:7.5}  {:11.5}  {}  {:8.4}  {:7.4}  {:8.4}  {:+.1}%\n",
            r.dim,
            r.packing,
            r.activation,
            r.reactive_fraction,
            r.reactive_fraction_error,
            r.reactive_fraction_theory,
            sigmas,
            r.rate_constant,
            r.rate_constant_error,
            r.rate_constant_theory,
            100.0 * (r.rate_constant / r.rate_constant_theory - 1.0)
        );
    }
    if !px.is_empty() {
        s += &format!(
            "Prigogine-Xhrouet: A + A -> B + B in a closed box, {} discs (spheres), all A at the start, until {} of them are left:\n  dim  packing  E*/kT  fraction    error  exp(-E*/kT)  deficit   error  exp(-E*/kT_A)  lowest kT_A\n",
            args.px_n, args.px_until
        );
        for p in px {
            s += &format!(
                "  {:3}  {:7.3}  {:5.2}  {:8.5}  {:7.5}  {:11.5}  {:6.1}%  {:5.1}%  {:13.5}  {:.3} +- {:.3}\n",
                p.dim,
                p.packing,
                p.activation,
                p.reactive_fraction,
                p.reactive_fraction_error,
                p.reactive_fraction_equilibrium,
                100.0 * p.deficit,
                100.0 * p.deficit_error,
                p.reactive_fraction_temperature,
                p.temperature_a_min,
                p.temperature_a_min_error
            );
        }
    }
    if interrupted {
        s += "interrupted: results so far\n";
    }
    s += &files_line(files);
    s
}
