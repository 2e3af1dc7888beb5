//! A protocol (T1, E1, and T3 with its simulated-annealing peers) run as
//! three shards in three processes, then merged, writes
//! the same tables, byte for byte, as one process; a merge refuses shards
//! that are missing, doubled, or of other options.

use std::fs;
use std::path::Path;
use std::process::{Command, Output};

fn repro(args: &[&str], out: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_repro"))
        .args(args)
        .arg("--out")
        .arg(out)
        .arg("--quiet")
        .output()
        .unwrap()
}

fn ok(args: &[&str], out: &Path) {
    let o = repro(args, out);
    assert!(
        o.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// Every output file of a protocol but those with measured times (the
/// metadata, T3's cost table) and the shard files: name and bytes.
fn tables(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut out: Vec<(String, Vec<u8>)> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            let name = p.file_name().unwrap().to_str().unwrap();
            // Measured times: the metadata and T3's cost table.
            name != "meta.txt" && name != "cost.md" && !name.starts_with("shard-")
        })
        .map(|p| {
            let bytes = fs::read(&p).unwrap();
            (p.file_name().unwrap().to_str().unwrap().to_owned(), bytes)
        })
        .collect();
    out.sort();
    out
}

#[test]
fn three_shards_merge_into_the_single_run() {
    let tmp = tempfile::tempdir().unwrap();
    let (single, sharded) = (tmp.path().join("single"), tmp.path().join("sharded"));
    for protocol in ["t1", "e1", "t3"] {
        ok(&[protocol, "--quick"], &single);
        for i in 0..3 {
            ok(
                &[protocol, "--quick", "--shard", &format!("{i}/3")],
                &sharded,
            );
        }
        // Before the merge there are only shard files.
        assert!(tables(&sharded.join(protocol)).is_empty());
        ok(&[protocol, "--quick", "--merge"], &sharded);
        let (a, b) = (
            tables(&single.join(protocol)),
            tables(&sharded.join(protocol)),
        );
        assert!(a.iter().any(|(name, _)| name == "summary.csv"), "{a:?}");
        assert_eq!(
            a.iter().map(|(n, _)| n).collect::<Vec<_>>(),
            b.iter().map(|(n, _)| n).collect::<Vec<_>>()
        );
        for ((name, x), (_, y)) in a.iter().zip(&b) {
            assert!(
                x == y,
                "{protocol}/{name} differs between one process and three shards"
            );
        }
        let meta = fs::read_to_string(sharded.join(protocol).join("meta.txt")).unwrap();
        assert!(meta.contains("wall time: the sum of the shards'"), "{meta}");
    }
}

#[test]
fn a_merge_refuses_incomplete_or_foreign_shards() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path();
    for i in [0, 2] {
        ok(&["t1", "--quick", "--shard", &format!("{i}/3")], out);
    }
    let missing = repro(&["t1", "--quick", "--merge"], out);
    assert!(!missing.status.success());
    assert!(String::from_utf8_lossy(&missing.stderr).contains("shard 1/3 is missing"));
    ok(&["t1", "--quick", "--shard", "1/3"], out);
    // Other options (another seed) are another plan.
    let foreign = repro(&["t1", "--quick", "--merge", "--seed", "7"], out);
    assert!(!foreign.status.success());
    assert!(String::from_utf8_lossy(&foreign.stderr).contains("other options or another seed"));
    // A shard of another count is refused too.
    ok(&["t1", "--quick", "--shard", "0/2"], out);
    let mixed = repro(&["t1", "--quick", "--merge"], out);
    assert!(!mixed.status.success());
    fs::remove_file(out.join("t1").join("shard-0-of-2.txt")).unwrap();
    ok(&["t1", "--quick", "--merge"], out);
    // Bad shard syntax fails before anything runs.
    let bad = repro(&["t1", "--quick", "--shard", "3/3"], out);
    assert!(!bad.status.success());
}

/// The job array's script, run as SLURM would run its three tasks (the
/// task variables set, `srun` a pass-through), then the merge.
#[test]
fn the_sbatch_script_runs_one_shard_per_task() {
    let tmp = tempfile::tempdir().unwrap();
    let bin = tmp.path().join("bin");
    fs::create_dir_all(&bin).unwrap();
    let srun = bin.join("srun");
    fs::write(&srun, "#!/bin/sh\nexec \"$@\"\n").unwrap();
    use std::os::unix::fs::PermissionsExt;
    fs::set_permissions(&srun, fs::Permissions::from_mode(0o755)).unwrap();
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("slurm/repro.sbatch");
    let (out, single) = (tmp.path().join("array"), tmp.path().join("single"));
    let path = format!("{}:{}", bin.display(), std::env::var("PATH").unwrap());
    for task in 0..3 {
        let o = Command::new("bash")
            .arg(&script)
            .env("PATH", &path)
            .env("REPRO", env!("CARGO_BIN_EXE_repro"))
            .env("OUT", &out)
            .env("ARGS", "t1 --quick --quiet")
            .env("SLURM_ARRAY_TASK_ID", task.to_string())
            .env("SLURM_ARRAY_TASK_COUNT", "3")
            .env("SLURM_CPUS_PER_TASK", "1")
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        assert!(
            out.join("t1")
                .join(format!("shard-{task}-of-3.txt"))
                .exists()
        );
    }
    ok(&["t1", "--quick", "--merge"], &out);
    ok(&["t1", "--quick"], &single);
    assert_eq!(tables(&out.join("t1")), tables(&single.join("t1")));
}
