//! T3's side-by-side comparison of the kernel's samplers with the
//! simulated-annealing peers: the running best of every configuration
//! beside the figures the paper copied from Guilmeau et al., and what each
//! run cost (evaluations of `U`, or of `U` and `∇U`, and wall time).

use std::fmt::Write as _;

use crate::config::{Method, RunSpec, StartSpec};
use crate::exec::{CheckpointResult, ConfigResult, ProtocolResult};

/// Whether the protocol ran any peer (only then are the comparison and
/// cost tables written).
pub fn has_peers(r: &ProtocolResult) -> bool {
    r.configs
        .iter()
        .any(|c| matches!(c.spec.method, Method::Peer { .. }))
}

/// The copied figure for a configuration at `k`: a peer's, whatever its
/// proposal, from `(1, ..., 1)`, where Guilmeau et al. ran them.
pub fn paper_mean(s: &RunSpec, k: u64) -> Option<f64> {
    match s.method {
        Method::Peer { kind, .. } if s.start == StartSpec::Point(1.0) => kind.paper_mean(k),
        _ => None,
    }
}

fn rows(r: &ProtocolResult) -> Vec<(&ConfigResult, &CheckpointResult)> {
    let most = r.configs.iter().map(|c| c.checkpoints.len()).max();
    (0..most.unwrap_or(0))
        .flat_map(|j| {
            r.configs
                .iter()
                .filter_map(move |c| c.checkpoints.get(j).map(|p| (c, p)))
        })
        .collect()
}

/// `comparison.md`: every configuration at every checkpoint, mean, SD and
/// SE over the M runs, the paper's copied mean where it has one and how
/// many of our standard errors ours lies from it, and the evaluations one
/// run made up to that iterate. Deterministic (no timing).
pub fn comparison_markdown(r: &ProtocolResult) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "Running best at k over M = {} runs (SD: sample SD; SE = SD / sqrt(M)). \
         \"paper\": the mean the paper copied from Guilmeau et al. (start (1, ..., 1)); \
         z = (ours - paper) / our SE. Evaluations per run up to k: of U alone (peers) \
         or of U and its gradient together (kernel samplers).\n",
        r.plan.runs
    );
    let _ = writeln!(
        out,
        "| method | k | mean | SD | SE | paper | z | evaluations of U | of U and grad U |"
    );
    let _ = writeln!(out, "|---|---|---|---|---|---|---|---|---|");
    for (c, p) in rows(r) {
        let s = &c.spec;
        let m = &p.summary;
        let (paper, z) = match paper_mean(s, p.k) {
            Some(v) => (format!("{v:.2}"), format!("{:+.1}", (m.mean - v) / m.se)),
            None => ("-".to_string(), "-".to_string()),
        };
        let evals = s.evaluations_to(p.k).to_string();
        let (u, ug) = if s.method.uses_gradient() {
            ("-".to_string(), evals)
        } else {
            (evals, "-".to_string())
        };
        let _ = writeln!(
            out,
            "| {} | {} | {:.4} | {:.4} | {:.4} | {paper} | {z} | {u} | {ug} |",
            s.label(),
            p.k,
            m.mean,
            m.sd,
            m.se
        );
    }
    out
}

/// `cost.md`: per configuration, the evaluations a run made (counted by
/// the runs) and the mean wall time of a run (measured, so it changes from
/// one run of the tool to the next, and with the machine's load).
pub fn cost_markdown(r: &ProtocolResult) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "Cost of one run (K = full length): evaluations counted by the runs, wall time \
         measured per run and averaged over the M = {} runs ({} threads).\n",
        r.plan.runs, r.threads
    );
    let _ = writeln!(
        out,
        "| method | evaluations per run | of | wall ms per run |"
    );
    let _ = writeln!(out, "|---|---|---|---|");
    for (c, wall) in r.configs.iter().zip(&r.run_wall) {
        let what = if c.spec.method.uses_gradient() {
            "U and grad U"
        } else {
            "U"
        };
        let runs = r.plan.runs as f64;
        let _ = writeln!(
            out,
            "| {} | {} | {what} | {:.2} |",
            c.spec.label(),
            c.evaluations as f64 / runs,
            wall.as_secs_f64() * 1e3 / runs
        );
    }
    out
}
