//! Runs a few configurations with the Rust crate and prints, one JSON
//! object per line, the bits of what they computed: the Python package's
//! tests (`python/tests/test_bits.py`) run the same configurations and
//! compare, bit for bit.
//!
//! ```sh
//! cargo run --release -p hrla-python --example golden
//! ```

use hrla::{
    Ackley, Auto, Builder, Chain, Chains, Gaussian, Geometric, Hrla, Interval, Lbfgs, Levy, Linear,
    Ola, Optimizer, Point, PolishSettings, Potential, Problem, Quadratic, Rastrigin, Sampler,
    Schedule, Start, Stop, Ula,
};

/// A float's bits as the tests read them: 16 hex digits.
fn hex(v: f64) -> String {
    format!("\"{:016x}\"", v.to_bits())
}

fn hexes<'a>(v: impl IntoIterator<Item = &'a f64>) -> String {
    let items: Vec<String> = v.into_iter().map(|&x| hex(x)).collect();
    format!("[{}]", items.join(","))
}

/// The chains of the runs: borrowed from a `Vec`.
type Borrowed<'a, const D: usize> = Chains<f64, &'a mut Vec<Chain<f64, D>>, D>;

/// The state of a run as one JSON object.
fn state<P, S, C, const D: usize, B>(
    case: &str,
    opt: &Optimizer<f64, P, S, C, Borrowed<'_, D>, B>,
    report: &hrla::Report<f64>,
    extra: &str,
) -> String
where
    S: Sampler<f64>,
    C: Schedule<f64>,
{
    let chains = opt.chains();
    format!(
        "{{\"case\":\"{case}\",\"termination\":\"{:?}\",\"iterations\":{},\"evaluations\":{},\
         \"best_chain\":{},\"best_value\":{},\"best_x\":{},\"x\":{},\"y\":{},\"value\":{}{extra}}}",
        report.termination,
        report.iterations,
        report.evaluations,
        opt.best_chain(),
        hex(opt.best().value),
        hexes(opt.best().x),
        hexes(chains.iter().flat_map(|c| c.x())),
        hexes(chains.iter().flat_map(|c| c.y())),
        hexes(chains.iter().map(|c| c.value()).collect::<Vec<_>>().iter()),
    )
}

fn chains<const D: usize>(n: usize) -> Vec<Chain<f64, D>> {
    (0..n).map(|_| Chain::new()).collect()
}

fn run<P, S, C, St, const D: usize>(
    case: &str,
    builder: Builder<f64, P, S, C, St>,
    n: usize,
) -> Result<String, hrla::Error>
where
    P: Potential<f64, D>,
    S: Sampler<f64>,
    C: Schedule<f64>,
    St: Start<f64>,
{
    let mut storage = chains::<D>(n);
    let mut opt = builder.build(&mut storage)?;
    let report = opt.run()?;
    Ok(state(case, &opt, &report, ""))
}

fn main() -> Result<(), hrla::Error> {
    // The paper's T1 setting, shortened.
    println!(
        "{}",
        run::<_, _, _, _, 10>(
            "hrla_linear_rastrigin",
            Builder::new(
                Rastrigin,
                Hrla::paper(0.01)?,
                Linear::new(0.1, 4.0, 500)?,
                Gaussian::new([3.0; 10], 10f64.sqrt())?,
            )
            .seed(7),
            10,
        )?
    );
    println!(
        "{}",
        run::<_, _, _, _, 5>(
            "ula_geometric_levy",
            Builder::new(
                Levy,
                Ula::paper(0.005)?,
                Geometric::new(0.5, 20.0, 400)?,
                Point::new([2.0; 5])?,
            )
            .seed(11)
            .stop(Stop::new().steps(400).target(1e-3).stall(100, 1e-9)),
            4,
        )?
    );
    println!(
        "{}",
        run::<_, _, _, _, 2>(
            "hrla_quadratic",
            Builder::new(
                Quadratic::new(1.0, [0.0, 0.0])?,
                Hrla::paper(0.05)?,
                1.0,
                Gaussian::new([1.0, -1.0], 1.0)?,
            )
            .seed(5)
            .stop(Stop::new().steps(200)),
            8,
        )?
    );

    // OLA in a box, stride 10, then a polish of the best chain.
    let box_ = Interval::new(-5.0, 5.0)?;
    let mut storage = chains::<3>(6);
    let mut opt = Builder::new(Ackley, Ola::paper(0.001)?, 2.0, box_)
        .domain(box_)
        .seed(3)
        .stride(10)
        .stop(Stop::new().steps(300))
        .build(&mut storage)?;
    let report = opt.run()?;
    // The state before the polish, which changes the best point.
    let sampled = state("ola_box_ackley_polish", &opt, &report, "");
    let mut lbfgs: Lbfgs<f64, 3, 8> = Lbfgs::new();
    let polished = opt.polish(opt.best_chain(), &mut lbfgs, PolishSettings::new(200))?;
    let extra = format!(
        ",\"polished_value\":{},\"polished_evaluations\":{},\"polished_end\":\"{:?}\",\
         \"after_best_value\":{},\"after_best_x\":{},\"after_evaluations\":{}",
        hex(polished.value),
        polished.evaluations,
        polished.end,
        hex(opt.best().value),
        hexes(opt.best().x),
        opt.evaluations()
    );
    println!("{}{extra}}}", sampled.trim_end_matches('}'));

    // The default solver.
    let budget = 20_000;
    let mut storage = chains::<4>(Auto::<f64>::chains_for(budget));
    let mut lbfgs: Lbfgs<f64, 4, 8> = Lbfgs::new();
    let s = Auto::default().minimize(
        &Problem::new(&Rastrigin, &Interval::new(-5.12, 5.12)?, budget).seed(5),
        (&mut storage[..], &mut lbfgs),
    )?;
    println!(
        "{{\"case\":\"auto_rastrigin\",\"x\":{},\"value\":{},\"evaluations\":{},\"rounds\":{},\
         \"step\":{},\"inverse_temperature\":{}}}",
        hexes(&s.x),
        hex(s.value),
        s.evaluations,
        s.rounds,
        hex(s.step),
        hex(s.inverse_temperature)
    );
    Ok(())
}
