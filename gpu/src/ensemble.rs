//! N chains of Algorithm 1 resident on the device: building them, stepping
//! them many steps per dispatch, and the device-side reductions (the best,
//! the empirical probability, the run's failures).

use hrla::{Float, Sampler, Schedule, chain_seed};
use rand_core::SeedableRng;
use rand_xoshiro::Xoshiro128PlusPlus;

use crate::device::{Gpu, bytes_of, words};
use crate::error::GpuError;
use crate::potential::DevicePotential;
use crate::precision::Precision;
use crate::shader::{Layout, Program, Settings, WORKGROUP, Ziggurat, settings_setters};
use crate::start::Start;
use crate::step::{DeviceKernel, StepCoefficients, StepKind};

/// The most eps values one [`Ensemble::probability`] call takes.
pub const MAX_EPS: usize = 64;

/// The largest dimension the backend compiles (each chain keeps three
/// points in registers).
pub const MAX_DIM: usize = 1024;

/// Status flags, as in `chains.wgsl`.
const DIVERGED: u32 = 1;
const UNBOUNDED: u32 = 2;
const BAD_START_POSITION: u32 = 4;
const BAD_START_VALUE: u32 = 8;
const BAD_START_GRADIENT: u32 = 16;

/// Words of one chain's status (value, best, best iterate, flags, stopped,
/// starts; in f64, the two values take two words each).
fn status_words(precision: Precision) -> usize {
    match precision {
        Precision::F32 => 6,
        Precision::F64 => 8,
    }
}

/// The settings of an [`Ensemble`], before it is on a device: a potential,
/// a sampler (the kernel's [`hrla::Hrla`], [`hrla::Ula`], [`hrla::Ola`] or
/// [`hrla::AnySampler`], in `f64` for the most accurate coefficients), a
/// schedule and a start; then, optionally, a seed, a stride, the number of
/// chains and the steps per dispatch.
///
/// ```no_run
/// use hrla::Hrla;
/// use hrla_gpu::{DevicePotential, EnsembleBuilder, Gpu, Start};
///
/// let gpu = Gpu::new()?;
/// let mut ensemble = EnsembleBuilder::new(
///     DevicePotential::Rastrigin,
///     Hrla::paper(0.01)?,
///     4.0,
///     Start::paper(10),
/// )
/// .chains(1_000_000)
/// .seed(1)
/// .build(&gpu)?;
/// ensemble.run(14_000)?;
/// let best = ensemble.best()?;
/// println!("U = {} at {:?}", best.value, best.x);
/// // The paper's empirical probability: runs of 10 chains within eps = 2.
/// let p = ensemble.probability(10, 0.0, &[2.0])?;
/// println!("P(best of 10 within 2 of U*) = {}", p[0].current);
/// # Ok::<(), hrla_gpu::GpuError>(())
/// ```
pub struct EnsembleBuilder<F, S, C> {
    potential: DevicePotential,
    sampler: S,
    schedule: C,
    start: Start,
    seed: u64,
    stride: u64,
    chains: usize,
    steps_per_dispatch: u32,
    settings: Settings,
    run_seeds: Option<Vec<u64>>,
    float: core::marker::PhantomData<F>,
}

impl<F, S, C> EnsembleBuilder<F, S, C>
where
    F: Float,
    S: Sampler<F> + 'static,
    S::Kernel: DeviceKernel,
    C: Schedule<F> + 'static,
{
    /// The required pieces; seed 0, stride 1, 1024 chains, 100 steps per
    /// dispatch.
    pub fn new(potential: DevicePotential, sampler: S, schedule: C, start: Start) -> Self {
        Self {
            potential,
            sampler,
            schedule,
            start,
            seed: 0,
            stride: 1,
            chains: 1024,
            steps_per_dispatch: 100,
            settings: Settings::default(),
            run_seeds: None,
            float: core::marker::PhantomData,
        }
    }

    /// The run's seed: chain `c` draws from
    /// `Xoshiro128PlusPlus::seed_from_u64(chain_seed(seed, c))`.
    pub fn seed(mut self, seed: u64) -> Self {
        self.seed = seed;
        self
    }

    /// The chains as runs of Algorithm 1, each with its own seed: with
    /// `m = seeds.len()` runs of `g = chains / m` chains, chain `j` of run
    /// `r` (chain `r g + j` of the ensemble) draws from
    /// `Xoshiro128PlusPlus::seed_from_u64(chain_seed(seeds[r], j))`, the
    /// words of chain `j` of a CPU optimiser of that run seeded with
    /// `seeds[r]`. So a run's chains do not depend on which other runs
    /// share the ensemble (a study's runs may be batched or sharded
    /// freely). Replaces [`seed`](Self::seed); `m` must divide the chains
    /// ([`build`](Self::build) says so otherwise).
    pub fn run_seeds(mut self, seeds: Vec<u64>) -> Self {
        self.run_seeds = Some(seeds);
        self
    }

    /// Records the running best only at iterates that are multiples of
    /// `stride >= 1`.
    pub fn stride(mut self, stride: u64) -> Self {
        self.stride = stride;
        self
    }

    /// The number of chains.
    pub fn chains(mut self, chains: usize) -> Self {
        self.chains = chains;
        self
    }

    /// Steps each chain takes in registers per dispatch (>= 1): more
    /// amortise the loads and stores of the state; fewer keep each
    /// dispatch short (a desktop's display driver may reset a GPU whose
    /// dispatch runs for seconds).
    pub fn steps_per_dispatch(mut self, steps: u32) -> Self {
        self.steps_per_dispatch = steps;
        self
    }

    settings_setters!();

    /// Compiles the program, seeds every chain's generator, draws the
    /// initial points on the device and evaluates the potential there.
    ///
    /// Errors: [`GpuError::Shader`] with the compiler's message when the
    /// potential's WGSL does not compile; [`GpuError::Kernel`] for zero
    /// chains or dimension or stride or steps per dispatch
    /// ([`hrla::Error::Zero`]), more chains or a larger dimension than the
    /// backend takes ([`hrla::Error::Count`]), the sampler's error at
    /// `a_0`, a start whose position, value or gradient is not finite
    /// after [`hrla::START_TRIES`] points drawn from the chain's generator,
    /// as the CPU's builder redraws them ([`hrla::Error::NonFiniteStart`],
    /// the first such chain); a start below `-sqrt(MAX)`
    /// ([`hrla::Error::UnboundedBelow`], the first such chain);
    /// [`GpuError::Dimension`] when the potential's dimension is not the
    /// start's; [`GpuError::TooLarge`] when a buffer exceeds the device's
    /// limit.
    pub fn build(self, gpu: &Gpu) -> Result<Ensemble<'_>, GpuError> {
        let dim = self.start.dimension();
        let n = self.chains;
        for (name, value) in [
            ("chains", n as u64),
            ("dimension D", dim as u64),
            ("stride", self.stride),
            ("steps per dispatch", u64::from(self.steps_per_dispatch)),
        ] {
            if value == 0 {
                return Err(hrla::Error::Zero { name }.into());
            }
        }
        if dim > MAX_DIM {
            return Err(hrla::Error::Count {
                name: "dimension D",
                value: dim,
                max: MAX_DIM,
            }
            .into());
        }
        // Chain indices, iterates and strides are 32-bit on the device.
        let max_chains = u32::MAX as usize / 2;
        if n > max_chains {
            return Err(hrla::Error::Count {
                name: "chains",
                value: n,
                max: max_chains,
            }
            .into());
        }
        if let Some(seeds) = &self.run_seeds
            && (seeds.is_empty() || !n.is_multiple_of(seeds.len()))
        {
            return Err(hrla::Error::Count {
                name: "run seeds (a divisor of the chains)",
                value: seeds.len(),
                max: n,
            }
            .into());
        }
        let stride = u32::try_from(self.stride).map_err(|_| hrla::Error::Count {
            name: "stride",
            value: self.stride as usize,
            max: u32::MAX as usize,
        })?;
        let program = Program::new(&self.potential, &self.start)?.settings(self.settings);
        let precision = self.settings.precision;
        if precision == Precision::F64 && !gpu.supports_f64() {
            return Err(GpuError::Unsupported(format!(
                "f64: the adapter {} has no SHADER_F64",
                gpu.info().name
            )));
        }
        if !self.potential.supports(precision) {
            return Err(GpuError::Unsupported(format!(
                "{:?} in {:?}: the device has no sin, cos or exp in that type",
                self.potential, precision
            )));
        }
        let (sampler, schedule) = (self.sampler, self.schedule);
        let coefficients: Box<dyn Fn(u64) -> Result<StepCoefficients, hrla::Error>> =
            Box::new(move |k| Ok(sampler.at(schedule.inverse_temperature(k))?.coefficients()));
        let first = coefficients(0)?;
        let source = program.step(first.kind()).wgsl();
        let mut ensemble = Ensemble::allocate(
            gpu,
            &source,
            dim,
            n,
            stride,
            self.steps_per_dispatch,
            first.kind(),
            precision,
            coefficients,
        )?;
        let seeds = match &self.run_seeds {
            Some(seeds) => Seeds::Runs(seeds),
            None => Seeds::One(self.seed),
        };
        ensemble.initialise(seeds, &self.start)?;
        Ok(ensemble)
    }
}

/// Chains of Algorithm 1 on a device: built by [`EnsembleBuilder`].
///
/// Each chain keeps its state in the device's memory between calls; within
/// one dispatch it keeps its position, velocity, gradient, value, running
/// best and generator in registers for
/// [`steps_per_dispatch`](EnsembleBuilder::steps_per_dispatch) steps, and
/// writes back only the point of an improved running best and, at the end,
/// its state. Iterate `k` of a chain is its state after `k` steps; the step
/// from `k` to `k + 1` runs at `a_k` of the schedule, as in
/// [`hrla::Optimizer`], and a chain whose position, value or gradient goes
/// non-finite is frozen (no more steps, no more draws) and excluded from
/// the current best, its running best kept.
pub struct Ensemble<'g> {
    gpu: &'g Gpu,
    dim: usize,
    chains: usize,
    steps_per_dispatch: u32,
    stride: u32,
    iteration: u64,
    coefficients: Box<dyn Fn(u64) -> Result<StepCoefficients, hrla::Error>>,
    kind: StepKind,
    precision: Precision,
    layout: Layout,
    coef_offset: u32,
    params: wgpu::Buffer,
    tables: wgpu::Buffer,
    rngs: wgpu::Buffer,
    xs: wgpu::Buffer,
    ys: wgpu::Buffer,
    best_xs: wgpu::Buffer,
    status: wgpu::Buffer,
    candidates: wgpu::Buffer,
    counts: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    pipelines: Pipelines,
    /// The error that ended the run, returned again by every later call.
    failed: Option<GpuError>,
}

impl core::fmt::Debug for Ensemble<'_> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Ensemble")
            .field("gpu", self.gpu)
            .field("dim", &self.dim)
            .field("chains", &self.chains)
            .field("iteration", &self.iteration)
            .field("failed", &self.failed)
            .finish_non_exhaustive()
    }
}

struct Pipelines {
    init: wgpu::ComputePipeline,
    step: wgpu::ComputePipeline,
    argmin: wgpu::ComputePipeline,
    groups: wgpu::ComputePipeline,
    census: wgpu::ComputePipeline,
    first_unbounded: wgpu::ComputePipeline,
    normals: wgpu::ComputePipeline,
}

/// The uniform parameters of one dispatch, as `Params` in `chains.wgsl`.
#[derive(Clone, Copy, Default)]
struct Params {
    chains: u32,
    steps: u32,
    first_step: u32,
    stride: u32,
    group_size: u32,
    groups: u32,
    eps_count: u32,
    pass_len: u32,
    pass_in: u32,
    pass_out: u32,
    coef_offset: u32,
    row: u32,
}

impl Params {
    fn bytes(&self) -> Vec<u8> {
        // `zero`, `negative_zero`, `one` and the padding to 64 bytes follow
        // the twelve words.
        bytes_of(&[
            self.chains,
            self.steps,
            self.first_step,
            self.stride,
            self.group_size,
            self.groups,
            self.eps_count,
            self.pass_len,
            self.pass_in,
            self.pass_out,
            self.coef_offset,
            self.row,
            0,
            (-0f32).to_bits(),
            1f32.to_bits(),
            0,
        ])
    }
}

/// The best point of a run: Algorithm 1's answer.
#[derive(Clone, Debug, PartialEq)]
pub struct BestPoint {
    /// The chain that holds it.
    pub chain: usize,
    /// `U(x)`.
    pub value: f64,
    /// The iterate at which the chain visited it.
    pub iteration: u64,
    /// The point.
    pub x: Vec<f64>,
}

/// One chain's state read back from the device.
#[derive(Clone, Debug, PartialEq)]
pub struct ChainSnapshot {
    /// Current position.
    pub x: Vec<f64>,
    /// Current velocity (zero for OLA).
    pub y: Vec<f64>,
    /// `U(x)` (for a diverged chain, the value at the step that stopped it).
    pub value: f64,
    /// The running best's value.
    pub best_value: f64,
    /// The running best's point.
    pub best_x: Vec<f64>,
    /// The iterate of the running best.
    pub best_iteration: u64,
    /// Whether the chain diverged.
    pub diverged: bool,
    /// The chain's generator, in its current state.
    pub rng: Xoshiro128PlusPlus,
}

/// One run's summary, from [`Ensemble::group_bests`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GroupBest {
    /// The best current value of its live chains (`+inf` when none is).
    pub current: f64,
    /// The best of its chains' running bests (`+inf` before any iterate
    /// on the stride when the start is not in the running best).
    pub running: f64,
    /// Its chains that diverged.
    pub diverged: usize,
    /// Its evaluations of the potential and gradient: one per point its
    /// starts drew (one, unless a start was infeasible and drawn again),
    /// one per step taken.
    pub evaluations: u64,
}

/// The paper's empirical probability at one eps: the share of groups of
/// chains (runs of Algorithm 1) whose best lies within eps of `U*`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Probability {
    /// The eps.
    pub eps: f64,
    /// By each group's best current value (live chains): the paper's
    /// "best chain at iterate k".
    pub current: f64,
    /// By each group's running best.
    pub running: f64,
}

impl<'g> Ensemble<'g> {
    #[allow(clippy::too_many_arguments)]
    fn allocate(
        gpu: &'g Gpu,
        source: &str,
        dim: usize,
        n: usize,
        stride: u32,
        steps_per_dispatch: u32,
        kind: StepKind,
        precision: Precision,
        coefficients: Box<dyn Fn(u64) -> Result<StepCoefficients, hrla::Error>>,
    ) -> Result<Self, GpuError> {
        let device = &gpu.device;
        // Buffers first: a size the device refuses is known before the
        // program is compiled.
        let layout = Layout::new(dim);
        let coef_offset = (layout.u_star as usize + 1 + MAX_EPS).next_multiple_of(8) as u32;
        let tables_len = coef_offset as u64 + 8 * u64::from(steps_per_dispatch);
        let (n64, d64, b) = (n as u64, dim as u64, precision.bytes());
        let params = gpu.checked(GpuError::Device, || {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("params"),
                size: 64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        })?;
        let tables = gpu.storage("constants", b * tables_len)?;
        let rngs = gpu.storage("generators", 16 * n64)?;
        let xs = gpu.storage("positions", b * n64 * d64)?;
        let ys = gpu.storage("velocities", b * n64 * d64)?;
        let best_xs = gpu.storage("best points", b * n64 * d64)?;
        let status = gpu.storage("status", 4 * status_words(precision) as u64 * n64)?;
        let partials = n64.div_ceil(u64::from(WORKGROUP));
        let candidates = gpu.storage("candidates", 4 * (2 * partials + 2))?;
        let counts = gpu.storage("counts", 4 * (2 * MAX_EPS as u64 + 8))?;
        let module = gpu.checked(GpuError::Shader, || {
            device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("hrla chains"),
                source: wgpu::ShaderSource::Wgsl(source.into()),
            })
        })?;
        let layout_entries: Vec<wgpu::BindGroupLayoutEntry> = (0..9)
            .map(|binding| wgpu::BindGroupLayoutEntry {
                binding,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer {
                    ty: match binding {
                        0 => wgpu::BufferBindingType::Uniform,
                        1 => wgpu::BufferBindingType::Storage { read_only: true },
                        _ => wgpu::BufferBindingType::Storage { read_only: false },
                    },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            })
            .collect();
        let bind_layout = gpu.checked(GpuError::Device, || {
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("hrla chains"),
                entries: &layout_entries,
            })
        })?;
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("hrla chains"),
            bind_group_layouts: &[Some(&bind_layout)],
            immediate_size: 0,
        });
        let pipeline = |entry: &str| {
            gpu.checked(GpuError::Shader, || {
                device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(entry),
                    layout: Some(&pipeline_layout),
                    module: &module,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    cache: None,
                })
            })
        };
        let pipelines = Pipelines {
            init: pipeline("init")?,
            step: pipeline("step")?,
            argmin: pipeline("argmin")?,
            groups: pipeline("groups")?,
            census: pipeline("census")?,
            first_unbounded: pipeline("first_unbounded")?,
            normals: pipeline("normals")?,
        };

        let buffers = [
            &params,
            &tables,
            &rngs,
            &xs,
            &ys,
            &best_xs,
            &status,
            &candidates,
            &counts,
        ];
        let entries: Vec<wgpu::BindGroupEntry> = buffers
            .iter()
            .enumerate()
            .map(|(i, b)| wgpu::BindGroupEntry {
                binding: i as u32,
                resource: b.as_entire_binding(),
            })
            .collect();
        let bind_group = gpu.checked(GpuError::Device, || {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("hrla chains"),
                layout: &bind_layout,
                entries: &entries,
            })
        })?;
        Ok(Self {
            gpu,
            dim,
            chains: n,
            steps_per_dispatch,
            stride,
            iteration: 0,
            coefficients,
            kind,
            precision,
            layout,
            coef_offset,
            params,
            tables,
            rngs,
            xs,
            ys,
            best_xs,
            status,
            candidates,
            counts,
            bind_group,
            pipelines,
            failed: None,
        })
    }

    /// Seeds the generators on the host (the kernel's `chain_seed` and
    /// rand_xoshiro's seeding, so the words are the CPU's), uploads the
    /// constants, and runs `init`.
    fn initialise(&mut self, seeds: Seeds<'_>, start: &Start) -> Result<(), GpuError> {
        let z = Ziggurat::from_kernel();
        let mut constants: Vec<f64> = match self.precision {
            Precision::F32 => z.x.iter().chain(&z.f).map(|&v| f64::from(v)).collect(),
            Precision::F64 => z.x64.iter().chain(&z.f64).copied().collect(),
        };
        constants.extend(start.constants());
        self.gpu
            .queue
            .write_buffer(&self.tables, 0, &self.bytes(&constants));
        self.seed_generators(seeds)?;
        self.dispatch(&self.pipelines.init, self.chains, Params::default())?;
        self.gpu.wait()?;
        // The first chain whose start is refused, as the CPU's builder
        // finds it.
        let status = self.read_status()?;
        for (c, s) in status.iter().enumerate() {
            if s.flags & UNBOUNDED != 0 {
                return Err(hrla::Error::UnboundedBelow {
                    chain: c,
                    value: s.value,
                }
                .into());
            }
            let what = if s.flags & BAD_START_POSITION != 0 {
                "position"
            } else if s.flags & BAD_START_VALUE != 0 {
                "value"
            } else if s.flags & BAD_START_GRADIENT != 0 {
                "gradient"
            } else {
                continue;
            };
            return Err(hrla::Error::NonFiniteStart {
                chain: c,
                what,
                tries: s.starts,
            }
            .into());
        }
        Ok(())
    }

    fn seed_generators(&self, seeds: Seeds<'_>) -> Result<(), GpuError> {
        let seed_of = |c: usize| match seeds {
            Seeds::One(seed) => chain_seed(seed, c as u64),
            Seeds::Runs(runs) => {
                let g = self.chains / runs.len();
                chain_seed(runs[c / g], (c % g) as u64)
            }
        };
        // In slices, so that 10^7 chains do not need 160 MB on the host.
        const SLICE: usize = 1 << 16;
        for first in (0..self.chains).step_by(SLICE) {
            let last = (first + SLICE).min(self.chains);
            let bytes: Vec<u8> = (first..last)
                .flat_map(|c| Xoshiro128PlusPlus::seed_from_u64(seed_of(c)).state())
                .collect();
            self.gpu
                .queue
                .write_buffer(&self.rngs, 16 * first as u64, &bytes);
        }
        self.gpu.take_uncaptured()
    }

    /// Runs `pipeline` over `invocations` invocations with `params` (its
    /// `chains`, `coef_offset` and `row` filled in).
    fn dispatch(
        &self,
        pipeline: &wgpu::ComputePipeline,
        invocations: usize,
        mut params: Params,
    ) -> Result<(), GpuError> {
        let groups = invocations.div_ceil(WORKGROUP as usize).max(1) as u32;
        let x = groups.min(65_535);
        let y = groups.div_ceil(x);
        params.chains = self.chains as u32;
        params.coef_offset = self.coef_offset;
        params.row = x * WORKGROUP;
        self.gpu
            .queue
            .write_buffer(&self.params, 0, &params.bytes());
        let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, &self.bind_group, &[]);
            pass.dispatch_workgroups(x, y, 1);
        }
        self.gpu.queue.submit([encoder.finish()]);
        self.gpu.take_uncaptured()
    }

    /// Advances every live chain by `steps` steps, in dispatches of at
    /// most [`steps_per_dispatch`](EnsembleBuilder::steps_per_dispatch).
    ///
    /// Errors: [`hrla::Error::Count`] for a run that would pass iterate
    /// `2^32 - 2` (the device counts iterates in 32 bits), before any
    /// step; the sampler's, if it refuses some `a_k` of the schedule
    /// (the chains then stand at iterate `k`, as the CPU optimiser's do);
    /// [`hrla::Error::UnboundedBelow`] if a chain's potential fell below
    /// `-sqrt(MAX)` of the device's float type (the earliest such iterate,
    /// then the lowest chain, as the CPU optimiser reports it);
    /// [`hrla::Error::AllDiverged`] once every chain has diverged. After
    /// either of the last two, every later call returns the same error.
    pub fn run(&mut self, steps: u64) -> Result<(), GpuError> {
        if let Some(e) = &self.failed {
            return Err(e.clone());
        }
        // Iterates are 32-bit on the device; a sum past u64 is as far out.
        let Some(end) = self
            .iteration
            .checked_add(steps)
            .filter(|&end| end < u64::from(u32::MAX))
        else {
            let end = self.iteration.saturating_add(steps);
            return Err(hrla::Error::Count {
                name: "iterations",
                value: usize::try_from(end).unwrap_or(usize::MAX),
                max: u32::MAX as usize - 1,
            }
            .into());
        };
        let per = u64::from(self.steps_per_dispatch);
        while self.iteration < end {
            let s = (end - self.iteration).min(per);
            // This dispatch's coefficients; a refused a_k ends it (and the
            // run) before step k, where the CPU optimiser stops.
            let mut table = Vec::with_capacity(8 * s as usize);
            let mut refused = None;
            for k in self.iteration..self.iteration + s {
                match (self.coefficients)(k) {
                    Ok(c) if c.kind() == self.kind => table.extend(c.to_device()),
                    Ok(_) => {
                        refused = Some(GpuError::Device(format!(
                            "the sampler changed its kind of step at iterate {k}"
                        )));
                        break;
                    }
                    Err(e) => {
                        refused = Some(e.into());
                        break;
                    }
                }
            }
            let s = (table.len() / 8) as u64;
            if let Some(e) = refused.take_if(|_| s == 0) {
                self.gpu.wait()?;
                return Err(e);
            }
            self.gpu.queue.write_buffer(
                &self.tables,
                self.precision.bytes() * u64::from(self.coef_offset),
                &self.bytes(&table),
            );
            let params = Params {
                steps: s as u32,
                first_step: self.iteration as u32,
                stride: self.stride,
                ..Params::default()
            };
            self.dispatch(&self.pipelines.step, self.chains, params)?;
            self.iteration += s;
            if let Some(e) = refused {
                self.finish()?;
                return Err(e);
            }
        }
        self.finish()
    }

    /// Waits for the queue, then fails the run for good if its chains
    /// show a failure (which comes before any later refusal, as on the CPU).
    fn finish(&mut self) -> Result<(), GpuError> {
        self.gpu.wait()?;
        if let Err(e) = self.check_failures() {
            self.failed = Some(e.clone());
            return Err(e);
        }
        Ok(())
    }

    /// After a run: counts the diverged chains and finds the first that
    /// fell below the floor, on the device.
    fn check_failures(&self) -> Result<(), GpuError> {
        // counts[0]: diverged chains; counts[1]: the earliest iterate at
        // which a chain fell below the floor; counts[2]: the lowest such
        // chain at that iterate.
        self.gpu
            .queue
            .write_buffer(&self.counts, 0, &bytes_of(&[0, u32::MAX, u32::MAX]));
        self.dispatch(&self.pipelines.census, self.chains, Params::default())?;
        self.dispatch(
            &self.pipelines.first_unbounded,
            self.chains,
            Params::default(),
        )?;
        let c = words(&self.gpu.read(&self.counts, &[(0, 12)])?);
        if c[2] != u32::MAX {
            let chain = c[2] as usize;
            let s = self.read_status_of(chain)?;
            return Err(hrla::Error::UnboundedBelow {
                chain,
                value: s.value,
            }
            .into());
        }
        if c[0] as usize == self.chains {
            return Err(hrla::Error::AllDiverged {
                chains: self.chains,
            }
            .into());
        }
        Ok(())
    }

    /// Algorithm 1's answer: the lowest running best over all chains (the
    /// earliest iterate, then the lowest chain, on ties), reduced on the
    /// device.
    pub fn best(&self) -> Result<BestPoint, GpuError> {
        if let Some(e) = &self.failed {
            return Err(e.clone());
        }
        let partials = self.chains.div_ceil(WORKGROUP as usize) as u32;
        let (mut len, mut input, mut output) = (self.chains as u32, u32::MAX, 0u32);
        loop {
            let params = Params {
                pass_len: len,
                pass_in: input,
                pass_out: output,
                ..Params::default()
            };
            self.dispatch(&self.pipelines.argmin, len as usize, params)?;
            len = len.div_ceil(WORKGROUP);
            if len == 1 {
                break;
            }
            input = output;
            output = if output == 0 { partials + 1 } else { 0 };
        }
        let chain = words(
            &self
                .gpu
                .read(&self.candidates, &[(4 * u64::from(output), 4)])?,
        )[0] as usize;
        let s = self.read_status_of(chain)?;
        let (n, b) = (self.chains as u64, self.precision.bytes());
        let ranges: Vec<(u64, u64)> = (0..self.dim as u64)
            .map(|i| (b * (i * n + chain as u64), b))
            .collect();
        let x = self.floats(&self.gpu.read(&self.best_xs, &ranges)?);
        Ok(BestPoint {
            chain,
            value: s.best,
            iteration: u64::from(s.best_iter),
            x,
        })
    }

    /// The paper's empirical probability at each of `eps` (at most
    /// [`MAX_EPS`] values): chains `m g .. (m + 1) g` form run `m` of
    /// Algorithm 1 with `g = group_size` chains, and the share of runs
    /// whose best lies within eps of `u_star` is counted on the device,
    /// by the runs' best current values and by their running bests. One
    /// invocation reads one run's chains: runs of a few to a few thousand
    /// chains (the paper's) spread over the device, one run of all the
    /// chains does not.
    ///
    /// Errors: [`hrla::Error::Zero`] or [`hrla::Error::Count`] when
    /// `group_size` does not divide the chains into whole runs, or for
    /// too many eps; [`hrla::Error::NotFinite`] for a non-finite `u_star`
    /// or eps.
    pub fn probability(
        &self,
        group_size: usize,
        u_star: f64,
        eps: &[f64],
    ) -> Result<Vec<Probability>, GpuError> {
        if let Some(e) = &self.failed {
            return Err(e.clone());
        }
        let groups = self.groups(group_size)?;
        if eps.len() > MAX_EPS {
            return Err(hrla::Error::Count {
                name: "eps values",
                value: eps.len(),
                max: MAX_EPS,
            }
            .into());
        }
        for (name, v) in [("U*", u_star)]
            .into_iter()
            .chain(eps.iter().map(|&e| ("eps", e)))
        {
            if !v.is_finite() {
                return Err(hrla::Error::NotFinite { name, value: v }.into());
            }
        }
        let mut values = vec![u_star];
        values.extend(eps);
        self.gpu.queue.write_buffer(
            &self.tables,
            self.precision.bytes() * u64::from(self.layout.u_star),
            &self.bytes(&values),
        );
        self.gpu
            .queue
            .write_buffer(&self.counts, 0, &vec![0u8; 8 * eps.len().max(1)]);
        let params = Params {
            group_size: group_size as u32,
            groups: groups as u32,
            eps_count: eps.len() as u32,
            ..Params::default()
        };
        self.dispatch(&self.pipelines.groups, groups, params)?;
        let counts = words(
            &self
                .gpu
                .read(&self.counts, &[(0, 8 * eps.len().max(1) as u64)])?,
        );
        Ok(eps
            .iter()
            .enumerate()
            .map(|(e, &eps)| Probability {
                eps,
                current: f64::from(counts[2 * e]) / groups as f64,
                running: f64::from(counts[2 * e + 1]) / groups as f64,
            })
            .collect())
    }

    /// The runs of `group_size` consecutive chains: [`hrla::Error::Zero`]
    /// or [`hrla::Error::Count`] unless they divide the chains.
    fn groups(&self, group_size: usize) -> Result<usize, GpuError> {
        if group_size == 0 {
            return Err(hrla::Error::Zero { name: "group size" }.into());
        }
        if !self.chains.is_multiple_of(group_size) {
            return Err(hrla::Error::Count {
                name: "group size (a divisor of the chains)",
                value: group_size,
                max: self.chains,
            }
            .into());
        }
        Ok(self.chains / group_size)
    }

    /// Per group of `group_size` consecutive chains (one run of Algorithm
    /// 1, as in [`probability`](Self::probability)), in order: its best
    /// current value, its best running best, its diverged chains and its
    /// evaluations. Reduced on the host from the chains' scalars (4 to 8
    /// words a chain are read back), and readable after a failed run too
    /// (the chains keep what they reached).
    ///
    /// Errors: [`hrla::Error::Zero`] or [`hrla::Error::Count`] when
    /// `group_size` does not divide the chains into whole runs.
    pub fn group_bests(&self, group_size: usize) -> Result<Vec<GroupBest>, GpuError> {
        self.groups(group_size)?;
        let status = self.read_status()?;
        Ok(status
            .chunks_exact(group_size)
            .map(|run| {
                let mut g = GroupBest {
                    current: f64::INFINITY,
                    running: f64::INFINITY,
                    diverged: 0,
                    evaluations: 0,
                };
                for s in run {
                    let diverged = s.flags & DIVERGED != 0;
                    if !diverged {
                        g.current = g.current.min(s.value);
                    }
                    g.running = g.running.min(s.best);
                    g.diverged += usize::from(diverged);
                    // The start's points, then one evaluation per step taken
                    // (a diverged chain's last at the step that stopped it).
                    let steps = if diverged {
                        u64::from(s.stopped)
                    } else {
                        self.iteration
                    };
                    g.evaluations += u64::from(s.starts) + steps;
                }
                g
            })
            .collect())
    }

    /// Every chain's state, read back (for checks and small runs: this
    /// copies the whole ensemble to the host).
    pub fn snapshot(&self) -> Result<Vec<ChainSnapshot>, GpuError> {
        let (n, d) = (self.chains, self.dim);
        let whole = |buffer: &wgpu::Buffer| {
            self.gpu
                .read(buffer, &[(0, self.precision.bytes() * (n * d) as u64)])
                .map(|v| self.floats(&v))
        };
        let (xs, ys, best_xs) = (whole(&self.xs)?, whole(&self.ys)?, whole(&self.best_xs)?);
        let rngs = self.gpu.read(&self.rngs, &[(0, 16 * n as u64)])?;
        let status = self.read_status()?;
        let gather = |v: &[f64], c: usize| (0..d).map(|i| v[i * n + c]).collect();
        Ok((0..n)
            .map(|c| {
                let mut seed = [0u8; 16];
                seed.copy_from_slice(&rngs[16 * c..16 * c + 16]);
                ChainSnapshot {
                    x: gather(&xs, c),
                    y: gather(&ys, c),
                    value: status[c].value,
                    best_value: status[c].best,
                    best_x: gather(&best_xs, c),
                    best_iteration: u64::from(status[c].best_iter),
                    diverged: status[c].flags & DIVERGED != 0,
                    rng: Xoshiro128PlusPlus::from_seed(seed),
                }
            })
            .collect())
    }

    /// Iterates taken so far.
    pub fn iteration(&self) -> u64 {
        self.iteration
    }

    /// The number of chains.
    pub fn len(&self) -> usize {
        self.chains
    }

    /// Always `false`: an ensemble has at least one chain.
    pub fn is_empty(&self) -> bool {
        self.chains == 0
    }

    /// The dimension.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// `count` normals (or pairs) of every chain into the positions'
    /// buffer, which must hold them: see [`Gpu::normals`].
    pub(crate) fn draw_normals(&self, count: u32, pairs: bool) -> Result<Vec<f64>, GpuError> {
        let width = u64::from(count) * if pairs { 2 } else { 1 };
        let params = Params {
            steps: count,
            stride: if pairs { 2 } else { 1 },
            ..Params::default()
        };
        self.dispatch(&self.pipelines.normals, self.chains, params)?;
        Ok(self.floats(&self.gpu.read(
            &self.xs,
            &[(0, self.precision.bytes() * width * self.chains as u64)],
        )?))
    }

    fn read_status(&self) -> Result<Vec<Status>, GpuError> {
        let w = status_words(self.precision);
        let bytes = 4 * (w * self.chains) as u64;
        Ok(words(&self.gpu.read(&self.status, &[(0, bytes)])?)
            .chunks_exact(w)
            .map(|s| Status::from_words(s, self.precision))
            .collect())
    }

    fn read_status_of(&self, chain: usize) -> Result<Status, GpuError> {
        let w = status_words(self.precision);
        let at = 4 * (w * chain) as u64;
        let words = words(&self.gpu.read(&self.status, &[(at, 4 * w as u64)])?);
        Ok(Status::from_words(&words, self.precision))
    }

    /// `values` in the device's float type, as bytes.
    fn bytes(&self, values: &[f64]) -> Vec<u8> {
        match self.precision {
            Precision::F32 => values
                .iter()
                .flat_map(|&v| (v as f32).to_le_bytes())
                .collect(),
            Precision::F64 => values.iter().flat_map(|v| v.to_le_bytes()).collect(),
        }
    }

    /// Bytes of the device's float type, as values.
    fn floats(&self, bytes: &[u8]) -> Vec<f64> {
        match self.precision {
            Precision::F32 => words(bytes)
                .into_iter()
                .map(|w| f64::from(f32::from_bits(w)))
                .collect(),
            Precision::F64 => bytes
                .chunks_exact(8)
                .map(|b| f64::from_le_bytes(b.try_into().unwrap_or([0; 8])))
                .collect(),
        }
    }
}

/// Whose seeds the chains' generators take.
#[derive(Clone, Copy)]
enum Seeds<'a> {
    /// Chain `c` from `chain_seed(seed, c)`.
    One(u64),
    /// Chain `j` of run `r` from `chain_seed(runs[r], j)`.
    Runs(&'a [u64]),
}

/// A chain's scalars, as `Status` in `chains.wgsl`.
struct Status {
    value: f64,
    best: f64,
    best_iter: u32,
    flags: u32,
    stopped: u32,
    starts: u32,
}

impl Status {
    fn from_words(w: &[u32], precision: Precision) -> Self {
        match precision {
            Precision::F32 => Self {
                value: f64::from(f32::from_bits(w[0])),
                best: f64::from(f32::from_bits(w[1])),
                best_iter: w[2],
                flags: w[3],
                stopped: w[4],
                starts: w[5],
            },
            Precision::F64 => {
                let wide = |lo: u32, hi: u32| f64::from_bits(u64::from(lo) | u64::from(hi) << 32);
                Self {
                    value: wide(w[0], w[1]),
                    best: wide(w[2], w[3]),
                    best_iter: w[4],
                    flags: w[5],
                    stopped: w[6],
                    starts: w[7],
                }
            }
        }
    }
}

impl Gpu {
    /// `count` standard normals from each of `chains` generators seeded as
    /// an ensemble's are (chain `c` from
    /// `Xoshiro128PlusPlus::seed_from_u64(chain_seed(seed, c))`), drawn on
    /// the device with the kernel's Ziggurat: single draws as a start
    /// draws them, or, with `pairs`, pairs as one coordinate of an HRLA or
    /// ULA step draws them. Chain `c`'s draws are `[c w, (c + 1) w)` with
    /// `w = count` (or `2 count` for pairs). In `precision`: `f32`
    /// normals (widened) or `f64` ones.
    ///
    /// For checking the device's streams against the kernel's
    /// [`hrla::StandardNormal`].
    pub fn normals(
        &self,
        seed: u64,
        chains: usize,
        count: u32,
        pairs: bool,
        precision: Precision,
    ) -> Result<Vec<f64>, GpuError> {
        let width = count as usize * if pairs { 2 } else { 1 };
        if width == 0 {
            return Err(hrla::Error::Zero { name: "normals" }.into());
        }
        // An ensemble whose positions hold the draws; its start draws none.
        let ensemble = EnsembleBuilder::new(
            DevicePotential::DoubleWell,
            hrla::Hrla::paper(0.01)?,
            1.0,
            Start::point(vec![0.0; width])?,
        )
        .chains(chains)
        .seed(seed)
        .precision(precision)
        .build(self)?;
        ensemble.draw_normals(count, pairs)
    }
}
