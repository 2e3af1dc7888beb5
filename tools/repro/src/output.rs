//! Writes a protocol's results into its directory: the formats of the
//! summary CSV and Markdown, the probability curves CSV and the run's
//! metadata (wall time, chain-steps); the figure is drawn by [`crate::plot`].

use std::fmt::{Display, Write as _};
use std::fs;
use std::path::{Path, PathBuf};

use crate::config::{Method, RunSpec, Temperature};
use crate::error::ReproError;
use crate::exec::{CheckpointResult, ConfigResult, ProtocolResult};
use crate::protocol::ProtocolId;

/// Columns of `summary.csv`.
pub const SUMMARY_COLUMNS: [&str; 21] = [
    "protocol",
    "sampler",
    "d",
    "h",
    "N",
    "K",
    "k",
    "schedule",
    "a",
    "a_low",
    "start",
    "stride",
    "M",
    "mean",
    "median",
    "sd",
    "sd_population",
    "se",
    "min",
    "max",
    "diverged_chains",
];

/// Columns of `curves.csv`.
pub const CURVE_COLUMNS: [&str; 14] = [
    "protocol",
    "sampler",
    "d",
    "h",
    "N",
    "K",
    "schedule",
    "a",
    "start",
    "eps",
    "k",
    "hits",
    "M",
    "probability",
];

/// The rows of the summary tables: checkpoint-major (every configuration
/// at the first checkpoint, then at the second, ...), so that a table read
/// at k = 50 and 500 shows two blocks.
fn table_rows(r: &ProtocolResult) -> Vec<(&ConfigResult, &CheckpointResult)> {
    let most = r
        .configs
        .iter()
        .map(|c| c.checkpoints.len())
        .max()
        .unwrap_or(0);
    (0..most)
        .flat_map(|j| {
            r.configs
                .iter()
                .filter_map(move |c| c.checkpoints.get(j).map(|p| (c, p)))
        })
        .collect()
}

/// The CSV columns `schedule`, `a` (or `a_high`) and `a_low` (empty at
/// constant `a`); a peer's own schedule, with `a` and `a_low` empty.
fn schedule_fields(s: &RunSpec) -> (&'static str, String, String) {
    if let Method::Peer { kind, .. } = s.method {
        return (kind.schedule_label(), String::new(), String::new());
    }
    match s.temperature {
        Temperature::Constant(a) => ("constant", a.to_string(), String::new()),
        Temperature::Linear { low, high } => ("linear", high.to_string(), low.to_string()),
    }
}

/// The step size `h` as written in tables (a peer has none).
fn step_size(s: &RunSpec) -> String {
    match s.method {
        Method::Kernel(_) => s.h.to_string(),
        Method::Peer { .. } => String::new(),
    }
}

/// [`schedule_fields`] with the schedule quoted for CSV.
fn csv_schedule(s: &RunSpec) -> (String, String, String) {
    let (schedule, a, a_low) = schedule_fields(s);
    (csv_field(schedule), a, a_low)
}

/// CSV text fields here never contain quotes; only commas need quoting.
fn csv_field(s: &str) -> String {
    if s.contains(',') {
        format!("\"{s}\"")
    } else {
        s.to_string()
    }
}

/// The columns `protocol,sampler,d,h,N,K` that open a row of either CSV
/// file.
fn config_columns(id: ProtocolId, s: &RunSpec) -> String {
    format!(
        "{},{},{},{},{},{}",
        id.name(),
        s.method.label(),
        s.d,
        step_size(s),
        s.chains,
        s.steps
    )
}

/// Appends `fields`, each as its `Display` writes it, as one CSV line.
fn push_row(out: &mut String, fields: &[&dyn Display]) {
    for (i, field) in fields.iter().enumerate() {
        if i > 0 {
            out.push(',');
        }
        let _ = write!(out, "{field}");
    }
    out.push('\n');
}

/// `summary.csv`: one row per configuration and checkpoint `k` (usually
/// just `K`), the running best at `k` over the M runs (sample SD, and the
/// population SD for comparison with numpy-made tables; SE = SD / sqrt(M)).
pub fn summary_csv(r: &ProtocolResult) -> String {
    let mut out = SUMMARY_COLUMNS.join(",");
    out.push('\n');
    for (c, p) in table_rows(r) {
        let s = &c.spec;
        let (schedule, a, a_low) = csv_schedule(s);
        let m = &p.summary;
        push_row(
            &mut out,
            &[
                &config_columns(r.plan.id, s),
                &p.k,
                &schedule,
                &a,
                &a_low,
                &csv_field(&s.start.label()),
                &s.stride,
                &m.n,
                &m.mean,
                &m.median,
                &m.sd,
                &m.sd_population,
                &m.se,
                &m.min,
                &m.max,
                &c.diverged,
            ],
        );
    }
    out
}

/// `curves.csv`: the empirical probability at every grid iterate, per
/// configuration and tolerance (empty body for table protocols).
pub fn curves_csv(r: &ProtocolResult) -> String {
    let mut out = CURVE_COLUMNS.join(",");
    out.push('\n');
    let m = r.plan.runs;
    for c in &r.configs {
        let s = &c.spec;
        let config = config_columns(r.plan.id, s);
        let (schedule, a, _) = csv_schedule(s);
        let start = csv_field(&s.start.label());
        for (e, eps) in s.eps.iter().enumerate() {
            for (k, hits) in c.curve(e) {
                let probability = f64::from(hits) / m as f64;
                push_row(
                    &mut out,
                    &[
                        &config,
                        &schedule,
                        &a,
                        &start,
                        eps,
                        &k,
                        &hits,
                        &m,
                        &probability,
                    ],
                );
            }
        }
    }
    out
}

/// The descriptive columns of a configuration at checkpoint `k`, as shown
/// in Markdown.
fn describe(s: &RunSpec, k: u64) -> [(&'static str, String); 10] {
    let t = s.temperature;
    let (schedule, a) = match (s.method, t) {
        (Method::Peer { kind, .. }, _) => (kind.schedule_label().to_string(), "-".to_string()),
        (Method::Kernel(_), Temperature::Constant(a)) => ("constant".to_string(), a.to_string()),
        (Method::Kernel(_), Temperature::Linear { low, high }) => {
            (format!("linear from {low}"), high.to_string())
        }
    };
    let h = match s.method {
        Method::Kernel(_) => s.h.to_string(),
        Method::Peer { .. } => "-".to_string(),
    };
    [
        ("sampler", s.method.label()),
        ("d", s.d.to_string()),
        ("h", h),
        ("N", s.chains.to_string()),
        ("K", s.steps.to_string()),
        ("at k", k.to_string()),
        ("start", s.start.label()),
        ("stride", s.stride.to_string()),
        ("schedule", schedule),
        (t.label_name(), a),
    ]
}

/// The summary as a Markdown table. Columns that are the same in every row
/// are stated once above the table instead.
pub fn summary_markdown(r: &ProtocolResult) -> String {
    let results = table_rows(r);
    let rows: Vec<_> = results
        .iter()
        .map(|(c, p)| describe(&c.spec, p.k))
        .collect();
    let ncols = rows[0].len();
    let varies: Vec<bool> = (0..ncols)
        .map(|i| rows.iter().any(|row| row[i].1 != rows[0][i].1))
        .collect();
    let any_diverged = r.configs.iter().any(|c| c.diverged > 0);
    let mut out = String::new();
    let fixed: Vec<String> = (0..ncols)
        .filter(|&i| !varies[i])
        .map(|i| format!("{} = {}", rows[0][i].0, rows[0][i].1))
        .collect();
    let _ = writeln!(
        out,
        "Running best at k (min over chains and over iterates s, 2s, ..., k) over M = {} runs; \
         SD is the sample SD (divisor M - 1), SE = SD / sqrt(M). Fixed: {}.\n",
        r.plan.runs,
        fixed.join(", ")
    );
    let mut header: Vec<&str> = (0..ncols)
        .filter(|&i| varies[i])
        .map(|i| rows[0][i].0)
        .collect();
    header.extend(["mean", "median", "SD", "SE"]);
    if any_diverged {
        header.push("diverged chains");
    }
    let _ = writeln!(out, "| {} |", header.join(" | "));
    let _ = writeln!(out, "|{}", "---|".repeat(header.len()));
    for ((c, p), row) in results.iter().zip(&rows) {
        let mut cells: Vec<String> = (0..ncols)
            .filter(|&i| varies[i])
            .map(|i| row[i].1.clone())
            .collect();
        let s = &p.summary;
        cells.extend([s.mean, s.median, s.sd, s.se].map(|v| format!("{v:.4}")));
        if any_diverged {
            cells.push(c.diverged.to_string());
        }
        let _ = writeln!(out, "| {} |", cells.join(" | "));
    }
    out
}

/// `meta.txt`: how the results were made; `notes` are extra `key: value`
/// lines (the command line, the machine's load).
pub fn meta(r: &ProtocolResult, notes: &[(&str, String)]) -> String {
    let mut out = format!(
        "protocol: {}\ntitle: {}\nseed: {}\nruns (M): {}\nconfigurations: {}\n\
         chain-steps: {}\nwall seconds: {:.2}\nthreads: {}\nchain-steps per second: {:.3e}\n",
        r.plan.id.name(),
        r.plan.id.title(),
        r.seed,
        r.plan.runs,
        r.configs.len(),
        r.chain_steps,
        r.wall.as_secs_f64(),
        r.threads,
        r.chain_steps_per_second(),
    );
    for (key, value) in notes {
        let _ = writeln!(out, "{key}: {value}");
    }
    out
}

fn write(path: PathBuf, text: &str) -> Result<PathBuf, ReproError> {
    fs::write(&path, text).map_err(ReproError::io(&path))?;
    Ok(path)
}

/// Writes every output of `r` into `dir/<id>/` (created if needed) and
/// returns the files written: `summary.csv`, `summary.md`, `meta.txt` (with
/// `notes` appended), for figure protocols `curves.csv` and `<id>.svg`, and
/// with peers (T3) `comparison.md`, `cost.md` and `<id>.svg`.
pub fn write_all(
    r: &ProtocolResult,
    dir: &Path,
    notes: &[(&str, String)],
) -> Result<Vec<PathBuf>, ReproError> {
    let dir = dir.join(r.plan.id.name().to_lowercase());
    fs::create_dir_all(&dir).map_err(ReproError::io(&dir))?;
    let mut files = vec![
        write(dir.join("summary.csv"), &summary_csv(r))?,
        write(dir.join("summary.md"), &summary_markdown(r))?,
        write(dir.join("meta.txt"), &meta(r, notes))?,
    ];
    if crate::compare::has_peers(r) {
        files.push(write(
            dir.join("comparison.md"),
            &crate::compare::comparison_markdown(r),
        )?);
        files.push(write(
            dir.join("cost.md"),
            &crate::compare::cost_markdown(r),
        )?);
        let svg = dir.join(format!("{}.svg", r.plan.id.name().to_lowercase()));
        crate::plot::comparison_figure(r, &svg)?;
        files.push(svg);
    }
    if !r.plan.panels.is_empty() {
        files.push(write(dir.join("curves.csv"), &curves_csv(r))?);
        let svg = dir.join(format!("{}.svg", r.plan.id.name().to_lowercase()));
        crate::plot::figure(r, &svg)?;
        files.push(svg);
    }
    Ok(files)
}
