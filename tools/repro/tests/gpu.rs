//! `--backend gpu` on whatever adapter wgpu finds (lavapipe without a GPU:
//! the test command installs it, and no adapter fails these tests loudly).
//!
//! - Bits: the device's runs are the CPU kernel's optimiser with the
//!   device's generator (xoshiro128++) and the tool's run seeds, driven by
//!   the tool's [`Tracker`]: the same running bests and probability counts,
//!   bit for bit, where the device computes in f64 and rounds as IEEE 754
//!   does (lavapipe does).
//! - Law: against the CPU backend (xoshiro256++, other draws), the mean
//!   running best within standard errors, and the same evaluations.
//! - Shards merge into the single run; T3's peers and a missing adapter
//!   are typed errors.

use std::path::Path;
use std::process::{Command, Output};

use hrla::{Builder, Chain, Gaussian, Rastrigin, Stop};
use hrla_repro::config::RunSpec;
use hrla_repro::exec::{Part, execute, finish};
use hrla_repro::gpu::GpuBackend;
use hrla_repro::protocol::{Overrides, ProtocolId, plan};
use hrla_repro::seed::run_seed;
use hrla_repro::split::Shard;
use hrla_repro::stats::Tracker;
use indicatif::ProgressBar;
use rand_xoshiro::Xoshiro128PlusPlus;

const D: usize = 10;
const SEED: u64 = 2025;

fn device() -> GpuBackend {
    match GpuBackend::open() {
        Ok(gpu) => {
            eprintln!("{}", gpu.describe());
            gpu
        }
        Err(e) => panic!(
            "no GPU adapter for --backend gpu's tests: {e}\n\
             install lavapipe: apt-get install mesa-vulkan-drivers libvulkan1"
        ),
    }
}

/// Run `i` of `spec` on the CPU kernel with the device's generator:
/// its running bests at the checkpoints and its probability counts.
fn cpu_run_with_device_streams(spec: &RunSpec, i: usize) -> (Vec<f64>, Vec<u32>) {
    assert_eq!(spec.d, D);
    let (schedule, sampler) = spec.kernel_setup().unwrap();
    let mut chains: Vec<Chain<f64, D, Xoshiro128PlusPlus>> =
        (0..spec.chains).map(|_| Chain::default()).collect();
    let mut opt = Builder::new(
        Rastrigin,
        sampler,
        schedule,
        Gaussian::new([3.0; D], 10f64.sqrt()).unwrap(),
    )
    .seed(run_seed(SEED, i as u64))
    .stride(spec.stride)
    .stop(Stop::new().steps(spec.steps))
    .build(&mut chains)
    .unwrap();
    let mut counts = vec![0; spec.count_len()];
    let mut tracker = Tracker::new(
        spec.steps,
        spec.stride,
        spec.curve_every,
        &spec.checkpoints,
        &spec.eps,
        0.0,
        &mut counts,
    );
    let now = |best: Option<(usize, f64)>| best.map_or(f64::INFINITY, |(_, v)| v);
    tracker.observe(0, now(opt.current_best()));
    for k in 1..=spec.steps {
        opt.step().unwrap();
        tracker.observe(k, now(opt.current_best()));
    }
    let best = tracker.at_checkpoints().to_vec();
    (best, counts)
}

/// T1 and E3 at a small size on the device: every run's running bests and
/// the curves' counts are the CPU kernel's with the device's generator,
/// bit for bit (the device in f64; lavapipe rounds as IEEE 754 does).
#[test]
fn device_runs_are_the_cpu_kernels_with_the_devices_generator() {
    let gpu = device();
    let t1 = Overrides {
        m: Some(5),
        k: Some(vec![300]),
        stride: Some(7),
        checkpoints: Some(vec![100, 300]),
        ..Overrides::default()
    };
    let e3 = Overrides {
        m: Some(6),
        k: Some(vec![400]),
        a: Some(vec![4.0, 8.0]),
        curve_every: Some(40),
        ..Overrides::default()
    };
    for (id, o) in [(ProtocolId::T1, t1), (ProtocolId::E3, e3)] {
        let p = plan(id, &o, false).unwrap();
        let result = gpu.execute(&p, SEED, &ProgressBar::hidden()).unwrap();
        for config in &result.configs {
            let mut counts = vec![0u32; config.spec.count_len()];
            for i in 0..p.runs {
                let (best, c) = cpu_run_with_device_streams(&config.spec, i);
                for (cp, b) in config.checkpoints.iter().zip(&best) {
                    assert_eq!(cp.running_best[i].to_bits(), b.to_bits(), "{id:?} run {i}");
                }
                for (all, one) in counts.iter_mut().zip(c) {
                    *all += one;
                }
            }
            assert_eq!(config.counts, counts, "{id:?}");
            assert_eq!(config.diverged, 0);
            assert_eq!(
                config.evaluations,
                (p.runs * config.spec.chains) as u64 * (config.spec.steps + 1)
            );
        }
        // E3's curves are neither all 0 nor all M: they test something.
        if id == ProtocolId::E3 {
            let c = &result.configs[0].counts;
            assert!(c.iter().any(|&h| h > 0) && c.iter().any(|&h| (h as usize) < p.runs));
        }
    }
}

/// Against the CPU backend (other draws): T1's mean running best at K for
/// each h within 4 standard errors of the difference (sample SDs over the
/// M runs of each backend, fixed seeds), and the same evaluations.
#[test]
fn device_and_cpu_backends_agree_within_standard_errors() {
    let gpu = device();
    let o = Overrides {
        m: Some(40),
        k: Some(vec![1000]),
        a: Some(vec![4.0]),
        ..Overrides::default()
    };
    let p = plan(ProtocolId::T1, &o, false).unwrap();
    let on_gpu = gpu.execute(&p, SEED, &ProgressBar::hidden()).unwrap();
    let on_cpu = execute(&p, SEED, &ProgressBar::hidden()).unwrap();
    for (g, c) in on_gpu.configs.iter().zip(&on_cpu.configs) {
        let (sg, sc) = (&g.checkpoints[0].summary, &c.checkpoints[0].summary);
        let se = (sg.sd.powi(2) / sg.n as f64 + sc.sd.powi(2) / sc.n as f64).sqrt();
        let h = g.spec.h;
        eprintln!(
            "h = {h}: gpu {:.4} ± {:.4}, cpu {:.4} ± {:.4}",
            sg.mean,
            sg.sd / (sg.n as f64).sqrt(),
            sc.mean,
            sc.sd / (sc.n as f64).sqrt()
        );
        assert!(se > 0.0, "h = {h}: no spread");
        assert!(
            (sg.mean - sc.mean).abs() <= 4.0 * se,
            "h = {h}: {} vs {} (SE {se})",
            sg.mean,
            sc.mean
        );
        assert_eq!(g.evaluations, c.evaluations);
        assert_eq!(g.diverged, c.diverged);
    }
}

/// Three shards on the device, merged in any order, are the single run.
#[test]
fn device_shards_merge_into_the_single_run() {
    let gpu = device();
    let o = Overrides {
        m: Some(5),
        k: Some(vec![200]),
        a: Some(vec![2.0, 6.0]),
        curve_every: Some(20),
        ..Overrides::default()
    };
    let p = plan(ProtocolId::E3, &o, false).unwrap();
    let bar = ProgressBar::hidden();
    let whole = gpu.execute(&p, SEED, &bar).unwrap();
    let shards: Vec<Part> = (0..3)
        .map(|index| {
            gpu.run_shard(&p, SEED, Shard { index, count: 3 }, &bar)
                .unwrap()
        })
        .collect();
    for order in [[0, 1, 2], [2, 1, 0]] {
        let merged = order
            .iter()
            .map(|&i| shards[i].clone())
            .try_fold(Part::empty(&p), Part::merge)
            .unwrap();
        let merged = finish(&p, SEED, merged, 1);
        assert_eq!(merged.configs, whole.configs);
        assert_eq!(merged.chain_steps, whole.chain_steps);
    }
}

fn repro(args: &[&str], out: &Path, env: &[(&str, &str)]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_repro"))
        .args(args)
        .arg("--out")
        .arg(out)
        .arg("--quiet")
        .envs(env.iter().copied())
        .output()
        .unwrap()
}

/// The command line: `--backend gpu` writes the tables and names the
/// device in meta.txt; T3's peers are refused naming the option; its
/// shards merge into the single run's tables with `--backend gpu` and are
/// refused by a CPU merge; with no
/// adapter (wgpu told to look for Metal only, which Linux lacks) the
/// error says there is none, before anything runs.
#[test]
fn the_command_line_runs_on_the_device_and_refuses_what_it_cannot() {
    let tmp = tempfile::tempdir().unwrap();
    let o = repro(&["t2", "--quick", "--backend", "gpu"], tmp.path(), &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let meta = std::fs::read_to_string(tmp.path().join("t2/meta.txt")).unwrap();
    assert!(meta.contains("backend") && meta.contains("gpu: "), "{meta}");
    assert!(tmp.path().join("t2/summary.csv").exists());

    let o = repro(&["t3", "--quick", "--backend", "gpu"], tmp.path(), &[]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("--backend") && err.contains("CPU only"),
        "{err}"
    );

    // A K beyond the device's 32-bit iterates: refused before any step.
    let o = repro(
        &[
            "e3",
            "--backend",
            "gpu",
            "--m",
            "1",
            "--n",
            "1",
            "--k",
            "5000000000",
            "--a",
            "4",
        ],
        tmp.path(),
        &[],
    );
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("--k") && err.contains("32-bit"), "{err}");

    // Shards on the device merge with --backend gpu, never into a CPU
    // merge (other draws).
    let sharded = tmp.path().join("sharded");
    for i in 0..2 {
        let o = repro(
            &[
                "t1",
                "--quick",
                "--backend",
                "gpu",
                "--shard",
                &format!("{i}/2"),
            ],
            &sharded,
            &[],
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let o = repro(&["t1", "--quick", "--merge"], &sharded, &[]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("plan backend gpu"), "{err}");
    let o = repro(
        &["t1", "--quick", "--merge", "--backend", "gpu"],
        &sharded,
        &[],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let single = tmp.path().join("single");
    let o = repro(&["t1", "--quick", "--backend", "gpu"], &single, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let table = |dir: &Path| std::fs::read(dir.join("t1/summary.csv")).unwrap();
    assert_eq!(table(&sharded), table(&single));

    if cfg!(target_os = "linux") {
        let o = repro(
            &["t1", "--quick", "--backend", "gpu"],
            &tmp.path().join("none"),
            &[("WGPU_BACKEND", "metal")],
        );
        assert!(!o.status.success());
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains("no GPU adapter found"), "{err}");
        assert!(!tmp.path().join("none/t1").exists());
    }
}
