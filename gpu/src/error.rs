//! The backend's one error type.

use core::fmt;

/// Why the backend refused its input or the device failed it.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum GpuError {
    /// No adapter (GPU, or a software one such as lavapipe) could be found:
    /// what wgpu said. Without a GPU, install a software Vulkan (Debian's
    /// `mesa-vulkan-drivers` and `libvulkan1`).
    NoAdapter(String),
    /// The adapter refused to open a device, or the device failed later
    /// (lost, out of memory, an internal validation error): wgpu's message.
    Device(String),
    /// The WGSL program did not compile (a user's potential, most often):
    /// the compiler's message, with the offending line of the source.
    Shader(String),
    /// A parameter or a run refused by the kernel's rules: the same error
    /// as the CPU optimiser gives (bad sampler parameters, a non-finite
    /// start, all chains diverged, a potential unbounded below, ...).
    Kernel(hrla::Error),
    /// The dimension of one piece disagrees with another's.
    Dimension {
        /// What fixed the dimension first (the start).
        expected: usize,
        /// The dimension of the piece that disagrees.
        got: usize,
        /// That piece.
        what: &'static str,
    },
    /// What the adapter cannot do: `f64` without `SHADER_F64`, or a
    /// potential that needs functions the device lacks in that type.
    Unsupported(String),
    /// A buffer would exceed what the device allows in one binding.
    TooLarge {
        /// The buffer.
        what: &'static str,
        /// Its size in bytes.
        bytes: u64,
        /// The device's limit in bytes.
        max: u64,
    },
}

impl fmt::Display for GpuError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NoAdapter(m) => write!(
                f,
                "no GPU adapter found ({m}); without a GPU, install a software Vulkan \
                 (Debian: mesa-vulkan-drivers and libvulkan1)"
            ),
            Self::Device(m) => write!(f, "the device failed: {m}"),
            Self::Shader(m) => write!(f, "the WGSL program does not compile: {m}"),
            Self::Kernel(e) => e.fmt(f),
            Self::Unsupported(m) => write!(f, "not supported by the device: {m}"),
            Self::Dimension {
                expected,
                got,
                what,
            } => write!(
                f,
                "the {what} has dimension {got}, the start has {expected}"
            ),
            Self::TooLarge { what, bytes, max } => write!(
                f,
                "the {what} buffer needs {bytes} bytes, above the device's limit of {max} bytes \
                 per binding: use fewer chains"
            ),
        }
    }
}

impl std::error::Error for GpuError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Kernel(e) => Some(e),
            _ => None,
        }
    }
}

impl From<hrla::Error> for GpuError {
    fn from(e: hrla::Error) -> Self {
        Self::Kernel(e)
    }
}
