//! The device: an adapter, its device and queue, and the plumbing every
//! ensemble shares (compiling a program, reading buffers back).

use std::sync::{Arc, Mutex};

use crate::error::GpuError;

/// A GPU (or a software adapter such as lavapipe) opened for compute.
///
/// ```no_run
/// let gpu = hrla_gpu::Gpu::new()?;
/// println!("{}", gpu.describe());
/// # Ok::<(), hrla_gpu::GpuError>(())
/// ```
pub struct Gpu {
    pub(crate) device: wgpu::Device,
    pub(crate) queue: wgpu::Queue,
    info: wgpu::AdapterInfo,
    limits: wgpu::Limits,
    features: wgpu::Features,
    /// Errors that no error scope caught (wgpu's default handler would
    /// panic): kept here and returned by the next operation.
    uncaptured: Arc<Mutex<Vec<String>>>,
}

impl core::fmt::Debug for Gpu {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Gpu")
            .field("adapter", &self.info.name)
            .finish()
    }
}

impl Gpu {
    /// The first adapter wgpu offers (a discrete GPU before an integrated
    /// one before a software one; `WGPU_BACKEND` and `WGPU_ADAPTER_NAME`
    /// steer the choice), with the largest storage buffers it allows.
    ///
    /// Errors: [`GpuError::NoAdapter`] when there is none,
    /// [`GpuError::Device`] when it refuses to open.
    pub fn new() -> Result<Self, GpuError> {
        pollster::block_on(Self::open())
    }

    async fn open() -> Result<Self, GpuError> {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapter = instance
            .request_adapter(&wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                force_fallback_adapter: false,
                compatible_surface: None,
                ..Default::default()
            })
            .await
            .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
        let info = adapter.get_info();
        let supported = adapter.limits();
        let limits = wgpu::Limits {
            max_storage_buffer_binding_size: supported.max_storage_buffer_binding_size,
            max_buffer_size: supported.max_buffer_size,
            max_storage_buffers_per_shader_stage: 8,
            ..wgpu::Limits::default()
        };
        // f64 where the adapter has it; ensembles in f32 do not need it.
        let features = adapter.features() & wgpu::Features::SHADER_F64;
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("hrla-gpu"),
                required_features: features,
                required_limits: limits.clone(),
                experimental_features: wgpu::ExperimentalFeatures::disabled(),
                memory_hints: wgpu::MemoryHints::Performance,
                trace: wgpu::Trace::Off,
            })
            .await
            .map_err(|e| GpuError::Device(e.to_string()))?;
        let uncaptured = Arc::new(Mutex::new(Vec::new()));
        let sink = uncaptured.clone();
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            if let Ok(mut errors) = sink.lock() {
                errors.push(e.to_string());
            }
        }));
        Ok(Self {
            device,
            queue,
            info,
            limits,
            features,
            uncaptured,
        })
    }

    /// The adapter: name, backend, driver.
    pub fn info(&self) -> &wgpu::AdapterInfo {
        &self.info
    }

    /// Whether the device computes in `f64` (`SHADER_F64`), for
    /// [`Precision::F64`](crate::Precision).
    pub fn supports_f64(&self) -> bool {
        self.features.contains(wgpu::Features::SHADER_F64)
    }

    /// One line naming the adapter, its backend and driver.
    pub fn describe(&self) -> String {
        let i = &self.info;
        format!(
            "{} ({:?}, {:?}, driver {} {})",
            i.name, i.backend, i.device_type, i.driver, i.driver_info
        )
    }

    /// The largest storage buffer binding, in bytes.
    pub(crate) fn max_binding(&self) -> u64 {
        self.limits
            .max_storage_buffer_binding_size
            .min(self.limits.max_buffer_size)
    }

    /// The first error no scope caught since the last call, if any.
    pub(crate) fn take_uncaptured(&self) -> Result<(), GpuError> {
        let mut errors = self.uncaptured.lock().map_err(|_| {
            GpuError::Device("the error handler of the device panicked".to_string())
        })?;
        match errors.drain(..).next() {
            Some(e) => Err(GpuError::Device(e)),
            None => Ok(()),
        }
    }

    /// Runs `make` inside validation and out-of-memory error scopes, and
    /// returns the first error either caught as `wrap` says.
    pub(crate) fn checked<T>(
        &self,
        wrap: fn(String) -> GpuError,
        make: impl FnOnce() -> T,
    ) -> Result<T, GpuError> {
        let memory = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let validation = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let made = make();
        let invalid = pollster::block_on(validation.pop());
        let out_of_memory = pollster::block_on(memory.pop());
        if let Some(e) = invalid {
            return Err(wrap(e.to_string()));
        }
        if let Some(e) = out_of_memory {
            return Err(GpuError::Device(e.to_string()));
        }
        self.take_uncaptured()?;
        Ok(made)
    }

    /// Waits until the queue is idle.
    pub(crate) fn wait(&self) -> Result<(), GpuError> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| GpuError::Device(e.to_string()))?;
        self.take_uncaptured()
    }

    /// A storage buffer of `bytes` bytes (at least 4), or
    /// [`GpuError::TooLarge`].
    pub(crate) fn storage(&self, what: &'static str, bytes: u64) -> Result<wgpu::Buffer, GpuError> {
        let bytes = bytes.max(4).next_multiple_of(4);
        let max = self.max_binding();
        if bytes > max {
            return Err(GpuError::TooLarge { what, bytes, max });
        }
        self.checked(GpuError::Device, || {
            self.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(what),
                size: bytes,
                usage: wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_DST
                    | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            })
        })
    }

    /// The bytes `ranges` (offset, length; multiples of 4) of `buffer`,
    /// concatenated, once the queue has run.
    pub(crate) fn read(
        &self,
        buffer: &wgpu::Buffer,
        ranges: &[(u64, u64)],
    ) -> Result<Vec<u8>, GpuError> {
        let total: u64 = ranges.iter().map(|r| r.1).sum();
        if total == 0 {
            return Ok(Vec::new());
        }
        let staging = self.checked(GpuError::Device, || {
            self.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("readback"),
                size: total,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        })?;
        let mut encoder = self.device.create_command_encoder(&Default::default());
        let mut at = 0;
        for &(offset, len) in ranges {
            encoder.copy_buffer_to_buffer(buffer, offset, &staging, at, len);
            at += len;
        }
        self.queue.submit([encoder.finish()]);
        let (tx, rx) = std::sync::mpsc::channel();
        staging.map_async(wgpu::MapMode::Read, .., move |r| {
            let _ = tx.send(r);
        });
        self.wait()?;
        rx.recv()
            .map_err(|e| GpuError::Device(e.to_string()))?
            .map_err(|e| GpuError::Device(e.to_string()))?;
        let bytes = staging
            .get_mapped_range(..)
            .map_err(|e| GpuError::Device(e.to_string()))?
            .to_vec();
        staging.unmap();
        Ok(bytes)
    }
}

/// Little-endian words of `bytes`.
pub(crate) fn words(bytes: &[u8]) -> Vec<u32> {
    bytes
        .chunks_exact(4)
        .map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]]))
        .collect()
}

/// `words` as little-endian bytes.
pub(crate) fn bytes_of(words: &[u32]) -> Vec<u8> {
    words.iter().flat_map(|w| w.to_le_bytes()).collect()
}
