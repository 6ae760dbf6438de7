//! Every problem of a problems file solved once with the default flags, in a table: cost
//! against the reference, residuals, certificates, time. Not criterion (one run each is the
//! figure a user sees); run with `cargo bench -p purcell-benches --bench suite [-- FILE]`
//! (default: the public suite, `tests/problems/public.json`).
use purcell_sim::suite::read_suite;
use purcell_solver::problem::Problem;
use purcell_solver::solver::{SolveOptions, solve};
use std::time::Instant;

fn main() {
    let path = std::env::args()
        .skip(1)
        .find(|a| a.ends_with(".json"))
        .unwrap_or_else(|| {
            concat!(env!("CARGO_MANIFEST_DIR"), "/../tests/problems/public.json").into()
        });
    let text = std::fs::read_to_string(&path).expect("problems file");
    let problems = read_suite(&text).expect("problems file parses");
    println!("{path}, default flags, {} thread(s)", rayon_threads());
    println!(
        "| problem | J | reference | J/ref − 1 | residual | KKT | local min | max \\|α\\| (limit) | arcs, min η | starts | time |\n|---|---|---|---|---|---|---|---|---|---|---|"
    );
    let t_all = Instant::now();
    for sp in problems {
        let p = Problem::new(&sp.spec).expect("valid problem");
        let t0 = Instant::now();
        let r = solve(&p, &SolveOptions::default(), &|| {});
        let secs = t0.elapsed().as_secs_f64();
        let reference = sp.reference.map_or("–".into(), |r| format!("{r:.7}"));
        match r {
            Ok(s) => {
                let b = &s.extremals[s.best];
                let rel = sp
                    .reference
                    .filter(|r| *r > 0.0)
                    .map_or("–".into(), |r| format!("{:+.1e}", b.cost / r - 1.0));
                let limit = p.alpha_max.map_or(String::new(), |a| format!(" ({a})"));
                let arcs = b
                    .min_eta
                    .map_or("–".into(), |e| format!("{}, {e:.1e}", b.arcs.len()));
                println!(
                    "| {} | {:.7} | {reference} | {rel} | {:.1e} | {} | {} | {:.4}{limit} | {arcs} | {} | {secs:.2} s |",
                    sp.name,
                    b.cost,
                    b.residual,
                    b.kkt_residual.map_or("–".into(), |k| format!("{k:.1e}")),
                    if b.local_min { "yes" } else { "no" },
                    b.max_abs_alpha,
                    s.search.as_ref().map_or(0, |e| e.starts),
                )
            }
            Err(e) => println!(
                "| {} | {e} | {reference} | expected: {} | | | | | | | {secs:.2} s |",
                sp.name,
                sp.expect.as_deref().unwrap_or("a solution")
            ),
        }
    }
    println!("total {:.1} s", t_all.elapsed().as_secs_f64());
}

fn rayon_threads() -> usize {
    std::env::var("RAYON_NUM_THREADS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
}
