//! Any dimension runs: `repro t1 --d 3` (a dimension of none of the
//! paper's protocols) writes the running bests that the kernel's
//! const-generic path, `Chain<f64, 3>`s driven here step by step, gives
//! for the same runs, to the bit.

use std::fs;
use std::process::Command;

use hrla::{
    AnySampler, AnySchedule, Builder, Chain, Constant, Gaussian, Rastrigin, SamplerKind, Stop,
    splitmix64,
};

const SEED: u64 = 2025;
const RUNS: u64 = 3;
const CHAINS: usize = 5;
const STEPS: u64 = 300;

/// The paper's running best at `K` (the best chain at every iterate
/// `1..=K`, stride 1, iterate 0 left out) of run `i`: HRLA, `h = 0.01`,
/// `a = 2`, from `N(3·1, 10 I)` in dimension 3, over `Chain<f64, 3>`s.
fn const_path_running_best(i: u64) -> f64 {
    let mut opt = Builder::new(
        Rastrigin,
        AnySampler::paper(SamplerKind::Hrla, 0.01).unwrap(),
        AnySchedule::Constant(Constant::new(2.0).unwrap()),
        Gaussian::new([3.0; 3], 10f64.sqrt()).unwrap(),
    )
    .seed(SEED ^ splitmix64(i))
    .stride(1)
    .stop(Stop::new().steps(STEPS))
    .build(vec![Chain::<f64, 3>::new(); CHAINS])
    .unwrap();
    let mut best = f64::INFINITY;
    for _ in 0..STEPS {
        opt.step().unwrap();
        best = best.min(opt.current_best().unwrap().1);
    }
    best
}

#[test]
fn d_3_runs_with_the_bits_of_the_const_path() {
    let dir = tempfile::tempdir().unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_repro"))
        .args(["t1", "--d", "3", "--h", "0.01", "--a", "2", "--stride", "1"])
        .args(["--m", &RUNS.to_string()])
        .args(["--n", &CHAINS.to_string(), "--k", &STEPS.to_string()])
        .args(["--seed", &SEED.to_string(), "--threads", "1", "--quiet"])
        .arg("--out")
        .arg(dir.path())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = fs::read_to_string(dir.path().join("t1/summary.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    // One row; the start's label is quoted and holds a comma.
    let row = lines
        .next()
        .unwrap()
        .replace("\"N(3·1, 10 I)\"", "N(3·1 10 I)");
    assert_eq!(lines.next(), None);
    let row: Vec<&str> = row.split(',').collect();
    let column = |name: &str| -> f64 {
        let at = header.iter().position(|h| *h == name).unwrap();
        row[at].parse().unwrap()
    };
    assert_eq!(column("d"), 3.0);
    // With M = 3 runs, the minimum, median and maximum are the three
    // running bests themselves, printed to the bit.
    let mut expected: Vec<f64> = (0..RUNS).map(const_path_running_best).collect();
    expected.sort_by(f64::total_cmp);
    let written = [column("min"), column("median"), column("max")];
    assert_eq!(
        written.map(f64::to_bits),
        [0, 1, 2].map(|j| expected[j].to_bits())
    );
}
