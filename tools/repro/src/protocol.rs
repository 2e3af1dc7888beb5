//! The protocols of spec section 7 as plans: their default parameters, the
//! command-line overrides, and the grid of configurations they expand to.

use hrla::SamplerKind;

use crate::config::{Method, RunSpec, StartSpec, Temperature};
use crate::error::ReproError;
use crate::peers::{DEFAULT_WALK, PeerKind, RandomWalk, Scope};
use crate::split::Shard;

/// The experimental protocols of the paper (spec section 7).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, clap::ValueEnum)]
pub enum ProtocolId {
    /// Empirical probability vs k for a = 1..4, eps = 1..6.
    E1,
    /// Running best vs step size h.
    T1,
    /// OLA vs ULA vs HRLA.
    E2,
    /// Long runs (K = 100000) at a = 4..8.
    E3,
    /// Dimension 10 against 20.
    E4,
    /// Linear annealing.
    E5,
    /// Fixed effort N K = 140000 with annealing.
    T2,
    /// Against simulated-annealing methods (run by the tool), K = 50 and
    /// 500, two starts.
    T3,
}

impl ProtocolId {
    /// Every protocol, in the order of the spec's table.
    pub const ALL: [ProtocolId; 8] = [
        ProtocolId::E1,
        ProtocolId::T1,
        ProtocolId::E2,
        ProtocolId::E3,
        ProtocolId::E4,
        ProtocolId::E5,
        ProtocolId::T2,
        ProtocolId::T3,
    ];

    /// `E1`, `T1`, ...
    pub fn name(self) -> &'static str {
        match self {
            ProtocolId::E1 => "E1",
            ProtocolId::T1 => "T1",
            ProtocolId::E2 => "E2",
            ProtocolId::E3 => "E3",
            ProtocolId::E4 => "E4",
            ProtocolId::E5 => "E5",
            ProtocolId::T2 => "T2",
            ProtocolId::T3 => "T3",
        }
    }

    /// What the protocol shows.
    pub fn title(self) -> &'static str {
        match self {
            ProtocolId::E1 => "empirical probability vs k, HRLA at a = 1..4",
            ProtocolId::T1 => "running best vs step size h",
            ProtocolId::E2 => "OLA vs ULA vs HRLA",
            ProtocolId::E3 => "long runs, K = 100000, a = 4..8",
            ProtocolId::E4 => "dimension: d = 10 against d = 20",
            ProtocolId::E5 => "linear annealing to a_high",
            ProtocolId::T2 => "fixed effort N K = 140000 with annealing",
            ProtocolId::T3 => {
                "best of 250 samples at k = 50 and 500: annealed HRLA beside SA, FSA, SMC-SA and CSA, two starts"
            }
        }
    }

    /// Whether the protocol reports a table (otherwise a figure; every
    /// protocol also writes its running-best summary).
    pub fn is_table(self) -> bool {
        matches!(self, ProtocolId::T1 | ProtocolId::T2 | ProtocolId::T3)
    }

    /// Whether the protocol anneals (takes `a_high`, not `a`).
    pub fn anneals(self) -> bool {
        matches!(self, ProtocolId::E5 | ProtocolId::T2 | ProtocolId::T3)
    }
}

fn parse_pair<A: std::str::FromStr, B: std::str::FromStr>(s: &str) -> Result<(A, B), String> {
    let (a, b) = s
        .split_once(':')
        .ok_or_else(|| format!("expected X:Y, got `{s}`"))?;
    let a = a.trim().parse().map_err(|_| format!("bad number `{a}`"))?;
    let b = b.trim().parse().map_err(|_| format!("bad number `{b}`"))?;
    Ok((a, b))
}

fn parse_f64_pair(s: &str) -> Result<(f64, f64), String> {
    parse_pair(s)
}

fn parse_nk(s: &str) -> Result<(usize, u64), String> {
    parse_pair(s)
}

/// Command-line overrides of a protocol's defaults. Lists are comma
/// separated; every configuration of the grid `sampler x d x h x (N, K) x
/// start x a` is run. Unset options keep the protocol's defaults.
#[derive(Clone, Debug, Default, clap::Args)]
pub struct Overrides {
    /// Samplers: hrla, ula, ola.
    #[arg(long, value_delimiter = ',')]
    pub sampler: Option<Vec<SamplerKind>>,
    /// Dimensions d, any d >= 1.
    #[arg(long, value_delimiter = ',')]
    pub d: Option<Vec<usize>>,
    /// Step sizes h.
    #[arg(long, value_delimiter = ',')]
    pub h: Option<Vec<f64>>,
    /// Numbers of chains N (crossed with --k); N K at most 2^53, and a run's
    /// chains on every worker thread within the machine's memory.
    #[arg(long, value_delimiter = ',')]
    pub n: Option<Vec<usize>>,
    /// Numbers of steps K (crossed with --n), at most 2^53.
    #[arg(long, value_delimiter = ',')]
    pub k: Option<Vec<u64>>,
    /// (N, K) pairs as N:K, e.g. `1:140000,10:14000` (T2's form).
    #[arg(long, value_delimiter = ',', value_parser = parse_nk, conflicts_with_all = ["n", "k"])]
    pub nk: Option<Vec<(usize, u64)>>,
    /// Independent runs M, at most 2^32 - 1; M N K summed over the
    /// configurations at most 2^53.
    #[arg(long)]
    pub m: Option<usize>,
    /// Constant inverse temperatures a (protocols without annealing).
    #[arg(long, value_delimiter = ',')]
    pub a: Option<Vec<f64>>,
    /// Final inverse temperatures a_high (annealing protocols).
    #[arg(long, value_delimiter = ',')]
    pub a_high: Option<Vec<f64>>,
    /// Initial inverse temperature a_low of the annealing (paper: 0.1).
    #[arg(long)]
    pub a_low: Option<f64>,
    /// Gaussian start: every coordinate of the mean (paper: 3).
    #[arg(long)]
    pub start_centre: Option<f64>,
    /// Gaussian start: variance of each coordinate (paper: 10).
    #[arg(long)]
    pub start_var: Option<f64>,
    /// Fixed start: every chain at (v, ..., v) instead of a Gaussian.
    #[arg(long, conflicts_with_all = ["start_centre", "start_var"])]
    pub start_point: Option<f64>,
    /// Stride s of the running best (min over k = s, 2s, ..., K), at most
    /// the first checkpoint.
    #[arg(long)]
    pub stride: Option<u64>,
    /// Tolerances eps of the probability curves.
    #[arg(long, value_delimiter = ',')]
    pub eps: Option<Vec<f64>>,
    /// Figure panels as X:eps pairs: a:eps for E2, d:eps for E4.
    #[arg(long, value_delimiter = ',', value_parser = parse_f64_pair)]
    pub panels: Option<Vec<(f64, f64)>>,
    /// Iterates at which the running best is reported (default: K; T3: 50,500).
    /// Each must be <= every K of the grid.
    #[arg(long, value_delimiter = ',')]
    pub checkpoints: Option<Vec<u64>>,
    /// Record the probability curves every r iterates (default: K / 500).
    #[arg(long)]
    pub curve_every: Option<u64>,
    /// T3's simulated-annealing peers run beside the samplers (default: all
    /// four: sa, fsa, smc-sa, csa).
    #[arg(long, value_delimiter = ',')]
    pub peers: Option<Vec<PeerKind>>,
    /// The peers' random-walk proposal SDs per coordinate (default: 0.25).
    #[arg(long, value_delimiter = ',')]
    pub peer_sd: Option<Vec<f64>>,
    /// Which coordinates a peer's proposal moves: full (all, the default)
    /// or coordinate (one, drawn uniformly).
    #[arg(long, value_delimiter = ',')]
    pub peer_move: Option<Vec<Scope>>,
}

/// Which configurations a figure panel shows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PanelFilter {
    /// All configurations.
    All,
    /// Those at inverse temperature `a` (or `a_high`).
    A(f64),
    /// Those in dimension `d`.
    D(usize),
}

impl PanelFilter {
    /// Whether `spec` belongs in the panel.
    pub fn accepts(self, spec: &RunSpec) -> bool {
        match self {
            PanelFilter::All => true,
            PanelFilter::A(a) => spec.temperature.label_value() == a,
            PanelFilter::D(d) => spec.d == d,
        }
    }
}

/// One panel of a figure: the probability curves at one tolerance.
#[derive(Clone, Debug, PartialEq)]
pub struct Panel {
    /// Its caption.
    pub title: String,
    /// The tolerance.
    pub eps: f64,
    /// The configurations drawn.
    pub filter: PanelFilter,
}

/// What distinguishes the curves of a panel (their legend).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SeriesKey {
    /// `a` or `a_high`.
    Temperature,
    /// The sampler.
    Sampler,
}

/// A protocol expanded into configurations, ready to run.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    /// The protocol.
    pub id: ProtocolId,
    /// Runs per configuration, M.
    pub runs: usize,
    /// The configurations, in table order.
    pub configs: Vec<RunSpec>,
    /// The figure's panels (empty for table protocols).
    pub panels: Vec<Panel>,
    /// The legend of the figure.
    pub series: SeriesKey,
}

impl Plan {
    /// Total chain-steps, `sum over configurations of M N K`.
    pub fn chain_steps(&self) -> u64 {
        self.runs as u64 * self.configs.iter().map(RunSpec::chain_steps).sum::<u64>()
    }
}

/// A protocol's parameters: the paper's defaults, scaled down by `--quick`,
/// then replaced by whatever the command line gives.
struct Params {
    samplers: Vec<SamplerKind>,
    d: Vec<usize>,
    h: Vec<f64>,
    nk: Vec<(usize, u64)>,
    runs: usize,
    /// `a`, or `a_high` for annealing protocols.
    temps: Vec<f64>,
    a_low: f64,
    starts: Vec<StartSpec>,
    stride: u64,
    /// Empty: just K.
    checkpoints: Vec<u64>,
    eps: Vec<f64>,
    panels: Vec<(f64, f64)>,
    /// `None`: K / 500.
    curve_every: Option<u64>,
    peers: Vec<PeerKind>,
    peer_sd: Vec<f64>,
    peer_move: Vec<Scope>,
}

/// The paper's start, N(3·1, 10 I).
const PAPER_CENTRE: f64 = 3.0;
const PAPER_VARIANCE: f64 = 10.0;
const PAPER_START: StartSpec = StartSpec::Gaussian {
    centre: PAPER_CENTRE,
    variance: PAPER_VARIANCE,
};
const A_LOW: f64 = 0.1;

/// The paper's parameters of protocol `id`.
fn defaults(id: ProtocolId) -> Params {
    let mut d = Params {
        samplers: vec![SamplerKind::Hrla],
        d: vec![10],
        h: vec![0.01],
        nk: vec![(10, 14_000)],
        runs: 100,
        temps: vec![1.0, 2.0, 3.0, 4.0],
        a_low: A_LOW,
        starts: vec![PAPER_START],
        stride: 1,
        checkpoints: vec![],
        eps: vec![],
        panels: vec![],
        curve_every: None,
        peers: vec![],
        peer_sd: vec![DEFAULT_WALK.sd],
        peer_move: vec![DEFAULT_WALK.scope],
    };
    let one_to_six = vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
    match id {
        ProtocolId::E1 => d.eps = one_to_six,
        ProtocolId::T1 => {
            d.h = vec![0.001, 0.01, 0.1];
            d.stride = 100;
        }
        ProtocolId::E2 => {
            d.samplers = vec![SamplerKind::Ola, SamplerKind::Ula, SamplerKind::Hrla];
            d.temps = vec![2.0, 3.0, 4.0, 5.0];
            d.panels = vec![(4.0, 2.0), (3.0, 4.0)];
        }
        ProtocolId::E3 => {
            d.nk = vec![(10, 100_000)];
            d.temps = vec![4.0, 5.0, 6.0, 7.0, 8.0];
            d.eps = one_to_six;
        }
        ProtocolId::E4 => {
            d.d = vec![10, 20];
            d.panels = vec![(10.0, 2.0), (20.0, 4.0)];
        }
        ProtocolId::E5 => {
            d.temps = vec![4.0, 12.0, 20.0, 40.0];
            d.eps = vec![0.25, 0.5, 1.0, 2.0];
        }
        ProtocolId::T2 => {
            d.nk = vec![
                (1, 140_000),
                (10, 14_000),
                (100, 1_400),
                (1_000, 140),
                (10_000, 14),
            ];
            d.temps = vec![4.0, 12.0, 20.0, 40.0];
        }
        ProtocolId::T3 => {
            // One run of K = 500 (annealing over 500 steps) read at k = 50
            // and 500, as the authors' code does (compute_tables([50, 500])).
            d.nk = vec![(250, 500)];
            d.checkpoints = vec![50, 500];
            d.runs = 50;
            d.temps = vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
            // The paper's text starts at (1, ..., 1), its code at N(3·1, 10 I).
            d.starts = vec![StartSpec::Point(1.0), PAPER_START];
            d.peers = PeerKind::ALL.to_vec();
        }
    }
    d
}

/// `--quick`'s K (and checkpoint) for the paper's `k`.
fn quick_steps(k: u64) -> u64 {
    (k / 50).max(1)
}

impl Params {
    /// The smoke-test size: M = 4 and every K and checkpoint divided by 50.
    fn quick(mut self) -> Self {
        self.runs = 4;
        for (_, k) in &mut self.nk {
            *k = quick_steps(*k);
        }
        for k in &mut self.checkpoints {
            *k = quick_steps(*k);
        }
        self.checkpoints.dedup();
        self
    }

    /// These parameters with every option given in `o` in place of its
    /// own; a panel's tolerance is added to the tolerances if missing.
    fn overridden(self, o: &Overrides) -> Self {
        let panels = o.panels.clone().unwrap_or(self.panels);
        let mut eps = o.eps.clone().unwrap_or(self.eps);
        for &(_, e) in &panels {
            if !eps.contains(&e) {
                eps.push(e);
            }
        }
        Params {
            samplers: o.sampler.clone().unwrap_or(self.samplers),
            d: o.d.clone().unwrap_or(self.d),
            h: o.h.clone().unwrap_or(self.h),
            nk: chain_lengths(o, self.nk),
            runs: o.m.unwrap_or(self.runs),
            temps: o
                .a
                .clone()
                .or_else(|| o.a_high.clone())
                .unwrap_or(self.temps),
            a_low: o.a_low.unwrap_or(self.a_low),
            starts: starts(o, self.starts),
            stride: o.stride.unwrap_or(self.stride),
            checkpoints: o.checkpoints.clone().unwrap_or(self.checkpoints),
            eps,
            panels,
            curve_every: o.curve_every.or(self.curve_every),
            peers: o.peers.clone().unwrap_or(self.peers),
            peer_sd: o.peer_sd.clone().unwrap_or(self.peer_sd),
            peer_move: o.peer_move.clone().unwrap_or(self.peer_move),
        }
    }
}

/// The (N, K) pairs: `--nk` as given, or `--n` crossed with `--k` (each
/// defaulting to the values of `defaults`), each pair once.
fn chain_lengths(o: &Overrides, defaults: Vec<(usize, u64)>) -> Vec<(usize, u64)> {
    if let Some(nk) = &o.nk {
        return nk.clone();
    }
    if o.n.is_none() && o.k.is_none() {
        return defaults;
    }
    let (default_ns, default_ks): (Vec<usize>, Vec<u64>) = defaults.into_iter().unzip();
    let ns = o.n.clone().unwrap_or(default_ns);
    let ks = o.k.clone().unwrap_or(default_ks);
    let mut pairs = Vec::new();
    for n in ns {
        for &k in &ks {
            if !pairs.contains(&(n, k)) {
                pairs.push((n, k));
            }
        }
    }
    pairs
}

/// The starts: `--start-point`, or a Gaussian from `--start-centre` and
/// `--start-var` (each defaulting to the paper's), or `defaults`.
fn starts(o: &Overrides, defaults: Vec<StartSpec>) -> Vec<StartSpec> {
    match (o.start_point, o.start_centre, o.start_var) {
        (Some(v), _, _) => vec![StartSpec::Point(v)],
        (None, None, None) => defaults,
        (None, c, v) => vec![StartSpec::Gaussian {
            centre: c.unwrap_or(PAPER_CENTRE),
            variance: v.unwrap_or(PAPER_VARIANCE),
        }],
    }
}

/// Refuses options that protocol `id` does not take, so that they are not
/// silently ignored.
fn check_options(id: ProtocolId, o: &Overrides) -> Result<(), ReproError> {
    let usage = |s: String| Err(ReproError::Usage(s));
    if id.anneals() && o.a.is_some() {
        return usage(format!("{} anneals: give --a-high, not --a", id.name()));
    }
    if !id.anneals() && (o.a_high.is_some() || o.a_low.is_some()) {
        return usage(format!(
            "{} runs at constant a: give --a, not --a-high/--a-low",
            id.name()
        ));
    }
    if o.panels.is_some() && !matches!(id, ProtocolId::E2 | ProtocolId::E4) {
        return usage("--panels applies to E2 (a:eps) and E4 (d:eps)".into());
    }
    if (o.peers.is_some() || o.peer_sd.is_some() || o.peer_move.is_some()) && id != ProtocolId::T3 {
        return usage("--peers, --peer-sd and --peer-move apply to T3".into());
    }
    Ok(())
}

/// The figure's panels: E2's (a, eps) and E4's (d, eps) pairs, one per
/// tolerance for the other figures, none for tables.
fn figure_panels(id: ProtocolId, p: &Params) -> Vec<Panel> {
    let panel = |title: String, eps: f64, filter: PanelFilter| Panel { title, eps, filter };
    match id {
        ProtocolId::E2 => p
            .panels
            .iter()
            .map(|&(a, e)| panel(format!("a = {a}, eps = {e}"), e, PanelFilter::A(a)))
            .collect(),
        ProtocolId::E4 => p
            .panels
            .iter()
            .map(|&(d, e)| panel(format!("d = {d}, eps = {e}"), e, PanelFilter::D(d as usize)))
            .collect(),
        _ if !id.is_table() => p
            .eps
            .iter()
            .map(|&e| panel(format!("eps = {e}"), e, PanelFilter::All))
            .collect(),
        _ => vec![],
    }
}

/// Every spec of `specs` once per value of an axis, the axis varying
/// fastest, so that expanding the outermost axis first gives table order.
fn expand<T: Copy>(specs: Vec<RunSpec>, axis: &[T], set: impl Fn(&mut RunSpec, T)) -> Vec<RunSpec> {
    let mut out = Vec::with_capacity(specs.len() * axis.len());
    for spec in &specs {
        for &value in axis {
            let mut s = spec.clone();
            set(&mut s, value);
            out.push(s);
        }
    }
    out
}

/// The grid `sampler x d x h x (N, K) x start x a` of protocol `id`, in
/// that order (the last varying fastest), then the grid `peer x proposal
/// (move x SD) x d x (N, K) x start` of its peers.
fn grid(id: ProtocolId, p: &Params) -> Vec<RunSpec> {
    let figure = !id.is_table();
    let temperature = |t| {
        if id.anneals() {
            Temperature::Linear {
                low: p.a_low,
                high: t,
            }
        } else {
            Temperature::Constant(t)
        }
    };
    // The placeholders are overwritten by the axes: every spec of the grid
    // has been through each `expand`.
    let template = RunSpec {
        method: Method::Kernel(SamplerKind::Hrla),
        d: 0,
        h: 0.0,
        chains: 0,
        steps: 0,
        temperature: Temperature::Constant(0.0),
        start: PAPER_START,
        stride: p.stride,
        checkpoints: vec![],
        eps: if figure { p.eps.clone() } else { vec![] },
        curve_every: None,
    };
    let lengths = |s: &mut RunSpec, (n, k): (usize, u64)| {
        s.chains = n;
        s.steps = k;
        s.checkpoints = if p.checkpoints.is_empty() {
            vec![k]
        } else {
            p.checkpoints.clone()
        };
        s.curve_every = figure.then(|| p.curve_every.unwrap_or_else(|| (k / 500).max(1)));
    };
    let mut specs = vec![template.clone()];
    specs = expand(specs, &p.samplers, |s, v| s.method = Method::Kernel(v));
    specs = expand(specs, &p.d, |s, v| s.d = v);
    specs = expand(specs, &p.h, |s, v| s.h = v);
    specs = expand(specs, &p.nk, lengths);
    specs = expand(specs, &p.starts, |s, v| s.start = v);
    specs = expand(specs, &p.temps, |s, t| s.temperature = temperature(t));
    // A peer has no step size or inverse temperature of the kernel's: the
    // template's placeholders stay.
    let mut peers = vec![template];
    let mut walks = Vec::new();
    for &scope in &p.peer_move {
        for &sd in &p.peer_sd {
            walks.push(RandomWalk { sd, scope });
        }
    }
    peers = expand(peers, &p.peers, |s, kind| {
        s.method = Method::Peer {
            kind,
            walk: DEFAULT_WALK,
        }
    });
    peers = expand(peers, &walks, |s, walk| {
        if let Method::Peer { kind, .. } = s.method {
            s.method = Method::Peer { kind, walk };
        }
    });
    peers = expand(peers, &p.d, |s, v| s.d = v);
    peers = expand(peers, &p.nk, lengths);
    peers = expand(peers, &p.starts, |s, v| s.start = v);
    specs.extend(peers);
    specs
}

impl Plan {
    /// The `(configuration, run)` pairs of `shard`, in plan order: those
    /// whose index in the list of every configuration's runs `0..M` is
    /// the shard's.
    pub fn tasks(&self, shard: Shard) -> Vec<(usize, usize)> {
        (0..self.configs.len())
            .flat_map(|c| (0..self.runs).map(move |i| (c, i)))
            .enumerate()
            .filter(|&(t, _)| shard.has(t))
            .map(|(_, task)| task)
            .collect()
    }
}

/// The plan of protocol `id`: its defaults (scaled down by `quick`), then
/// the overrides; its sizes within [`limits`](crate::limits) and every
/// configuration validated.
pub fn plan(id: ProtocolId, o: &Overrides, quick: bool) -> Result<Plan, ReproError> {
    let mut params = defaults(id);
    if quick {
        params = params.quick();
    }
    check_options(id, o)?;
    let params = params.overridden(o);
    if params.runs == 0 {
        return Err(ReproError::Usage("M must be at least 1".into()));
    }
    let configs = grid(id, &params);
    if configs.is_empty() {
        return Err(ReproError::Usage("the parameter grid is empty".into()));
    }
    let mut panels = figure_panels(id, &params);
    // A listed pair whose a or d was overridden away would draw an empty
    // panel.
    panels.retain(|p| configs.iter().any(|c| p.filter.accepts(c)));
    let series = if id == ProtocolId::E2 {
        SeriesKey::Sampler
    } else {
        SeriesKey::Temperature
    };
    let plan = Plan {
        id,
        runs: params.runs,
        configs,
        panels,
        series,
    };
    // Sizes first: a huge K is named as such, not as a stride beyond it.
    crate::limits::check_counts(&plan.configs, plan.runs)?;
    for spec in &plan.configs {
        spec.validate()?;
    }
    Ok(plan)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::limits::{Footprint, MAX_CHAIN_STEPS, MAX_RUNS, check_memory, machine_memory};

    #[test]
    fn defaults_follow_the_spec_table() {
        let none = Overrides::default();
        let t1 = plan(ProtocolId::T1, &none, false).unwrap();
        assert_eq!(t1.configs.len(), 12);
        assert_eq!(t1.runs, 100);
        assert!(t1.configs.iter().all(|c| c.stride == 100 && c.chains == 10));
        assert_eq!(t1.chain_steps(), 12 * 100 * 10 * 14_000);
        let t2 = plan(ProtocolId::T2, &none, false).unwrap();
        assert!(t2.configs.iter().all(|c| c.chain_steps() == 140_000));
        assert_eq!(t2.configs.len(), 20);
        let t3 = plan(ProtocolId::T3, &none, false).unwrap();
        // HRLA at 6 a_high and the 4 peers, from both starts.
        assert_eq!(t3.configs.len(), 2 * 6 + 4 * 2);
        assert!(
            t3.configs[12..]
                .iter()
                .all(|c| matches!(c.method, Method::Peer { .. }) && c.chains == 250)
        );
        assert_eq!(t3.runs, 50);
        assert!(t3.configs.iter().all(|c| c.checkpoints == [50, 500]));
        let t3_quick = plan(ProtocolId::T3, &none, true).unwrap();
        assert!(t3_quick.configs.iter().all(|c| c.checkpoints == [1, 10]));
        let e2 = plan(ProtocolId::E2, &none, false).unwrap();
        assert_eq!(e2.panels.len(), 2);
        assert_eq!(e2.configs.len(), 12);
        assert_eq!(e2.configs[0].eps, vec![2.0, 4.0]);
        let e4_d10 = Overrides {
            d: Some(vec![10]),
            ..Overrides::default()
        };
        assert_eq!(
            plan(ProtocolId::E4, &e4_d10, false).unwrap().panels.len(),
            1
        );
        let e3 = plan(ProtocolId::E3, &none, false).unwrap();
        assert_eq!(e3.configs[0].curve_every, Some(200));
        assert_eq!(e3.panels.len(), 6);
    }

    #[test]
    fn overrides_replace_defaults_and_wrong_ones_are_refused() {
        let o = Overrides {
            a: Some(vec![2.5]),
            start_point: Some(1.0),
            m: Some(7),
            ..Overrides::default()
        };
        let p = plan(ProtocolId::E1, &o, true).unwrap();
        assert_eq!(p.runs, 7);
        assert_eq!(p.configs.len(), 1);
        assert_eq!(p.configs[0].start, StartSpec::Point(1.0));
        assert_eq!(p.configs[0].steps, 280);
        assert!(matches!(
            plan(ProtocolId::E5, &o, false),
            Err(ReproError::Usage(_))
        ));
        let d = |d| Overrides {
            d: Some(vec![d]),
            ..Overrides::default()
        };
        assert_eq!(plan(ProtocolId::E1, &d(3), false).unwrap().configs[0].d, 3);
        assert!(matches!(
            plan(ProtocolId::E1, &d(0), false),
            Err(ReproError::Flag { flag: "--d", .. })
        ));
    }

    #[test]
    fn the_grid_varies_the_last_axis_fastest_and_crosses_n_with_k_once() {
        let o = Overrides {
            n: Some(vec![5, 5, 7]),
            k: Some(vec![20, 40]),
            ..Overrides::default()
        };
        let e2 = plan(ProtocolId::E2, &o, true).unwrap();
        let order: Vec<(Method, usize, u64, f64)> = e2
            .configs
            .iter()
            .map(|c| (c.method, c.chains, c.steps, c.temperature.label_value()))
            .collect();
        // (5, 20), (5, 40), (7, 20), (7, 40): the repeated 5 counts once.
        assert_eq!(order.len(), 3 * 4 * 4);
        assert_eq!(order[0], (Method::Kernel(SamplerKind::Ola), 5, 20, 2.0));
        assert_eq!(order[1], (Method::Kernel(SamplerKind::Ola), 5, 20, 3.0));
        assert_eq!(order[4], (Method::Kernel(SamplerKind::Ola), 5, 40, 2.0));
        assert_eq!(order[8], (Method::Kernel(SamplerKind::Ola), 7, 20, 2.0));
        assert_eq!(order[16], (Method::Kernel(SamplerKind::Ula), 5, 20, 2.0));
    }

    fn t1(o: Overrides) -> Result<Plan, ReproError> {
        plan(ProtocolId::T1, &o, true)
    }

    fn named(r: Result<impl std::fmt::Debug, ReproError>) -> &'static str {
        match r {
            Err(ReproError::Flag { flag, .. }) => flag,
            other => panic!("not refused by an option: {other:?}"),
        }
    }

    #[test]
    fn counts_at_the_limits() {
        let at = |m, n, k| Overrides {
            m: Some(m),
            n: Some(vec![n]),
            k: Some(vec![k]),
            a: Some(vec![1.0]),
            h: Some(vec![0.01]),
            ..Overrides::default()
        };
        // One configuration: M N K = 2^53 exactly is allowed, one more is not.
        assert!(t1(at(1, 1, MAX_CHAIN_STEPS)).is_ok());
        assert!(t1(at(2, 1 << 26, 1 << 26)).is_ok());
        assert_eq!(named(t1(at(1, 1, MAX_CHAIN_STEPS + 1))), "--k");
        assert_eq!(named(t1(at(1, 1 << 53, 2))), "--n");
        assert_eq!(named(t1(at(3, 1 << 26, 1 << 26))), "--m");
        assert_eq!(named(t1(at(MAX_RUNS + 1, 1, 1))), "--m");
        assert_eq!(named(t1(at(usize::MAX, 1, 1))), "--m");
        assert_eq!(named(t1(at(1, usize::MAX, 1))), "--n");
        assert_eq!(named(t1(at(1, 1, u64::MAX))), "--k");
    }

    #[test]
    fn memory_is_checked_against_the_machine() {
        let p = t1(Overrides::default()).unwrap();
        let f = Footprint::of(&p.configs, p.runs);
        let chain = crate::kernel::chain_bytes(10).unwrap() as u64;
        assert_eq!(f.chains, Some(10 * chain));
        assert_eq!(f.counts, Some(0));
        let need = f.total(Some(2)).unwrap();
        assert_eq!(need, 2 * 10 * chain + f.runs.unwrap());
        assert!(check_memory(&p.configs, p.runs, Some(2), need).is_ok());
        assert_eq!(
            named(check_memory(&p.configs, p.runs, Some(2), need - 1)),
            "--m/--n/--k"
        );
        assert_eq!(
            named(check_memory(&p.configs, p.runs, Some(2), 10 * chain)),
            "--n/--d"
        );
        assert_eq!(named(check_memory(&p.configs, p.runs, None, 1)), "--m");
        // More workers than runs hold no more chains.
        assert_eq!(
            check_memory(&p.configs, p.runs, Some(10_000), need).is_ok(),
            check_memory(&p.configs, p.runs, Some(p.runs * p.configs.len()), need).is_ok()
        );
        let e1 = plan(
            ProtocolId::E1,
            &Overrides {
                curve_every: Some(1),
                ..Overrides::default()
            },
            true,
        )
        .unwrap();
        assert_eq!(
            named(check_memory(&e1.configs, e1.runs, None, 1000)),
            "--curve-every"
        );
        assert!(machine_memory() > 1 << 20);
    }
}
