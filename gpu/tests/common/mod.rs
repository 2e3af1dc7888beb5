//! What every test file of the backend shares: the device.

use std::sync::OnceLock;

use hrla_gpu::Gpu;

/// The adapter, opened once per test binary. No adapter is a failure, not
/// a skip: the test command installs lavapipe (a software Vulkan), so a
/// machine without any adapter lacks what the tests need, and must say so.
pub fn gpu() -> &'static Gpu {
    static GPU: OnceLock<Gpu> = OnceLock::new();
    GPU.get_or_init(|| match Gpu::new() {
        Ok(gpu) => {
            eprintln!("adapter: {}", gpu.describe());
            gpu
        }
        Err(e) => panic!(
            "no GPU adapter for the backend's tests: {e}\n\
             install lavapipe: apt-get install mesa-vulkan-drivers libvulkan1"
        ),
    })
}
