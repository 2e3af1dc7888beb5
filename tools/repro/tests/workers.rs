//! The worker threads: a refused `--threads` starts none, and a command
//! on the GPU backend or a merge starts none at all. Alone in its test
//! binary, so that no other test's threads enter the count.

use hrla_repro::ReproError;
use hrla_repro::gpu::Backend;
use hrla_repro::limits::{THREADS_PER_CORE, cores};

/// The threads of this process (Linux: one entry per thread in
/// `/proc/self/task`).
#[cfg(target_os = "linux")]
fn threads() -> usize {
    std::fs::read_dir("/proc/self/task").unwrap().count()
}

#[cfg(target_os = "linux")]
#[test]
fn threads_are_checked_before_any_starts_and_only_the_cpu_starts_them() {
    let before = threads();
    let too_many = cores() * THREADS_PER_CORE + 1;
    for backend in [Backend::Cpu, Backend::Gpu] {
        for count in [too_many, 100_000] {
            match backend.start_workers(count, false) {
                Err(ReproError::Flag {
                    flag: "--threads",
                    reason,
                }) => assert!(reason.contains(&count.to_string()), "{reason}"),
                other => panic!("{backend:?}, {count} threads: {other:?}"),
            }
        }
    }
    assert_eq!(threads(), before);
    assert_eq!(Backend::Gpu.start_workers(2, false).unwrap(), None);
    assert_eq!(Backend::Cpu.start_workers(2, true).unwrap(), None);
    assert_eq!(threads(), before);
    assert_eq!(Backend::Cpu.start_workers(2, false).unwrap(), Some(2));
    assert_eq!(threads(), before + 2);
}
