//! The device side of the step: buffers, pipelines, the dispatch of each step and the copies
//! to and from the host.

use crate::shader::{
    kernel_source, partial_groups, KernelId, ShaderConstants, FLAG_WORDS, STATE_WORDS,
};
use crate::Precision;
use slosh_core::{DeviceSetup, DeviceStepReport, Fluid, SimError, StepDevice, Vector, Walls};
use std::collections::HashMap;
use std::time::Instant;

/// Why the GPU backend cannot run.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    /// No Vulkan adapter on this machine.
    #[error(
        "no Vulkan device found for the GPU backend (backend \"gpu\"): install a Vulkan driver \
         (on Debian, mesa-vulkan-drivers gives a software device, lavapipe) or run on the CPU \
         (backend \"cpu\", the default){0}"
    )]
    NoDevice(String),
    /// The adapter cannot do f64 arithmetic in shaders.
    #[error(
        "the Vulkan device {0} has no 64-bit float shaders (SHADER_F64), which the GPU \
         backend's f64 precision needs"
    )]
    NoF64(String),
    /// The device refused or the limits are too small.
    #[error("the GPU device {device} cannot run the step: {what}")]
    Device {
        /// The device.
        device: String,
        /// What failed.
        what: String,
    },
}

/// The modern step on a wgpu device.
pub struct GpuStep<const D: usize> {
    device: wgpu::Device,
    queue: wgpu::Queue,
    name: String,
    constants: ShaderConstants,
    buffers: HashMap<&'static str, wgpu::Buffer>,
    kernels: Vec<Kernel>,
    /// Staging buffers of the per-step copies: the state words and flags, the wall state.
    staging_step: wgpu::Buffer,
    staging_walls: wgpu::Buffer,
    /// GPU wall order (by cell) → host wall index.
    wall_host_index: Vec<u32>,
    /// Time of each kernel (s) while profiling.
    times: Vec<(String, f64)>,
    /// Time of the whole steps (s) outside profiling.
    step_time: f64,
    /// Submit and wait kernel by kernel, to time each (`slosh bench --backend gpu`).
    profile: bool,
}

struct Kernel {
    id: KernelId,
    pipeline: wgpu::ComputePipeline,
    bind_group: wgpu::BindGroup,
    groups: u32,
}

/// The buffers of the step: (name, element size in bytes, elements); reals take `real`
/// bytes (8 or 4).
fn buffer_list(c: &ShaderConstants) -> Vec<(&'static str, u64, u64)> {
    let real = real_bytes(c);
    let (n, nw, nc, d) = (
        c.n_fluid as u64,
        c.n_wall.max(1) as u64,
        c.n_cells as u64,
        c.dim as u64,
    );
    let groups = partial_groups(c.n_fluid) as u64;
    vec![
        ("pos", real, d * n),
        ("pcell", 4, d * n),
        ("vel", real, d * n),
        ("vel_n", real, d * n),
        ("acc", real, d * n),
        ("rho", real, n),
        ("rho_n", real, n),
        ("drho", real, n),
        ("p", real, n),
        ("rho_h", real, n),
        ("id", 4, n),
        ("cell", 4, n),
        ("order", 4, n),
        ("pos2", real, d * n),
        ("pcell2", 4, d * n),
        ("vel2", real, d * n),
        ("vel_n2", real, d * n),
        ("rho2", real, n),
        ("rho_n2", real, n),
        ("id2", 4, n),
        ("count", 4, nc),
        ("cursor", 4, nc),
        ("start", 4, nc + 1),
        ("wall_pos", real, d * nw),
        ("wall_cell", 4, d * nw),
        ("wall_start", 4, nc + 1),
        ("wall_state", real, 2 * nw),
        ("partial", real, 2 * groups),
        ("state", real, STATE_WORDS as u64),
        ("flags", 4, FLAG_WORDS as u64),
        ("body", real, d),
    ]
}

/// Flattens vectors into D consecutive f64.
fn flat<const D: usize>(v: &[Vector<D>]) -> Vec<f64> {
    v.iter().flat_map(|x| x.iter().copied()).collect()
}

/// Bytes of one real of the device (8 for f64, 4 for f32).
fn real_bytes(c: &ShaderConstants) -> u64 {
    if c.single {
        4
    } else {
        8
    }
}

/// Said in a device's description when it is a software one (Mesa's lavapipe, SwiftShader):
/// the step runs on the CPU's cores through the Vulkan driver.
pub const SOFTWARE_DEVICE: &str = "a software device on the CPU";

/// Real number `k` of bytes read back from the device, as f64.
fn real_at(raw: &[u8], k: usize, single: bool) -> f64 {
    if single {
        bytemuck::cast_slice::<u8, f32>(raw)[k] as f64
    } else {
        bytemuck::cast_slice::<u8, f64>(raw)[k]
    }
}

impl<const D: usize> GpuStep<D> {
    /// The step of `setup`'s simulation on the first Vulkan adapter in `precision`.
    pub fn new(setup: &DeviceSetup<'_, D>, precision: Precision) -> Result<Self, GpuError> {
        let single = precision == Precision::F32;
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
            backends: wgpu::Backends::VULKAN,
            ..wgpu::InstanceDescriptor::new_without_display_handle()
        });
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            ..Default::default()
        }))
        .map_err(|e| GpuError::NoDevice(format!(" ({e})")))?;
        let info = adapter.get_info();
        let software = if info.device_type == wgpu::DeviceType::Cpu {
            format!(", {SOFTWARE_DEVICE}")
        } else {
            String::new()
        };
        let name = format!(
            "{} ({:?}, {}{software})",
            info.name, info.backend, info.driver_info
        );
        let features = if single {
            wgpu::Features::empty()
        } else {
            wgpu::Features::SHADER_F64
        };
        if !adapter.features().contains(features) {
            return Err(GpuError::NoF64(name));
        }
        let limits = adapter.limits();
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("slosh"),
            required_features: features,
            required_limits: limits.clone(),
            ..Default::default()
        }))
        .map_err(|e| GpuError::Device {
            device: name.clone(),
            what: e.to_string(),
        })?;
        let p = setup.params;
        let h = setup.smoothing_length;
        let support = 2.0 * h;
        let mut dims = [1u32; 3];
        let (mut lo, mut hi) = ([0.0; 3], [0.0; 3]);
        for k in 0..D {
            lo[k] = setup.domain_min[k];
            hi[k] = setup.domain_max[k];
            dims[k] = (((hi[k] - lo[k]) / support).ceil() as u32).max(1);
        }
        let n_cells = dims.iter().product::<u32>();
        let constants = ShaderConstants {
            dim: D,
            h,
            support,
            mass: setup.mass,
            rho0: p.rest_density,
            eos_b: p.eos_stiffness,
            gamma: p.eos_gamma as u32,
            c0: setup.sound_speed,
            cfl: p.cfl_number,
            fixed_dt: p.fixed_dt.unwrap_or(0.0),
            viscous_dt: if p.dynamic_viscosity > 0.0 {
                p.cfl_number * h * h * p.rest_density / p.dynamic_viscosity
            } else {
                0.0
            },
            av_alpha: p.av_alpha,
            av_beta: p.av_beta,
            av_c: setup.av_sound_speed,
            k_mu_m: 2.0 * (D as f64 + 2.0) * p.dynamic_viscosity * setup.mass,
            diff_coeff: -2.0 * setup.diffusion_coeff,
            hydrostatic: setup.hydrostatic_diffusion,
            still_level: setup.still_level,
            gravity: p.gravity,
            wall_floor: p.wall_separation,
            domain_min: lo,
            domain_max: hi,
            dims,
            n_fluid: setup.fluid.position.len() as u32,
            n_wall: setup.walls.position.len() as u32,
            n_cells,
            single,
        };
        let most_bindings = [KernelId::Gather, KernelId::Forces]
            .iter()
            .map(|k| k.bindings().len() as u32)
            .max()
            .unwrap_or(0);
        if limits.max_storage_buffers_per_shader_stage < most_bindings {
            return Err(GpuError::Device {
                device: name,
                what: format!(
                    "it binds {} storage buffers per kernel, the step needs {most_bindings}",
                    limits.max_storage_buffers_per_shader_stage
                ),
            });
        }
        let mut buffers = HashMap::new();
        for (buffer, size, count) in buffer_list(&constants) {
            let bytes = (size * count.max(1)).max(8);
            if bytes > limits.max_storage_buffer_binding_size {
                return Err(GpuError::Device {
                    device: name,
                    what: format!(
                        "the buffer {buffer} needs {bytes} bytes, more than the {} a binding may \
                         hold: too many particles for this device",
                        limits.max_storage_buffer_binding_size
                    ),
                });
            }
            buffers.insert(
                buffer,
                device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(buffer),
                    size: bytes.div_ceil(8) * 8,
                    usage: wgpu::BufferUsages::STORAGE
                        | wgpu::BufferUsages::COPY_DST
                        | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                }),
            );
        }
        let order = [
            KernelId::ReducePartial,
            KernelId::ReduceFinal,
            KernelId::Predictor,
            KernelId::CellCount,
            KernelId::CellScan,
            KernelId::CellScatter,
            KernelId::CellOrder,
            KernelId::Gather,
            KernelId::Hydrostatic,
            KernelId::Walls,
            KernelId::Forces,
            KernelId::Corrector,
            KernelId::FirstOutside,
        ];
        let mut kernels = Vec::new();
        for id in order {
            let source = kernel_source(id, &constants);
            let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(id.name()),
                source: wgpu::ShaderSource::Wgsl(source.into()),
            });
            let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(id.name()),
                layout: None,
                module: &module,
                entry_point: Some("main"),
                compilation_options: Default::default(),
                cache: None,
            });
            if let Some(e) = pollster::block_on(scope.pop()) {
                return Err(GpuError::Device {
                    device: name,
                    what: format!("kernel {} does not compile: {e}", id.name()),
                });
            }
            let entries: Vec<wgpu::BindGroupEntry> = id
                .bindings()
                .iter()
                .enumerate()
                .map(|(b, (buffer, _))| wgpu::BindGroupEntry {
                    binding: b as u32,
                    resource: buffers[buffer].as_entire_binding(),
                })
                .collect();
            let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
            let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(id.name()),
                layout: &pipeline.get_bind_group_layout(0),
                entries: &entries,
            });
            if let Some(e) = pollster::block_on(scope.pop()) {
                return Err(GpuError::Device {
                    device: name,
                    what: format!("kernel {} cannot bind its buffers: {e}", id.name()),
                });
            }
            let groups = id.invocations(&constants).div_ceil(id.workgroup()).max(1);
            kernels.push(Kernel {
                id,
                pipeline,
                bind_group,
                groups,
            });
        }
        let real = real_bytes(&constants);
        let step_bytes = (STATE_WORDS as u64 * real + FLAG_WORDS as u64 * 4).div_ceil(8) * 8;
        let staging_step = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("staging step"),
            size: step_bytes,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let staging_walls = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("staging walls"),
            size: (2 * real * constants.n_wall.max(1) as u64).div_ceil(8) * 8,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let times = kernels
            .iter()
            .map(|k| (k.id.name().to_string(), 0.0))
            .collect();
        Ok(GpuStep {
            device,
            queue,
            name: if single {
                format!("{name}, f32 (positions relative to their cell)")
            } else {
                format!("{name}, f64")
            },
            constants,
            buffers,
            kernels,
            staging_step,
            staging_walls,
            wall_host_index: Vec::new(),
            times,
            step_time: 0.0,
            profile: false,
        })
    }

    /// Writes reals into buffer `name` in the device's precision.
    fn write_reals(&self, name: &str, data: &[f64]) {
        if self.constants.single {
            let v: Vec<f32> = data.iter().map(|&x| x as f32).collect();
            self.write(name, &v);
        } else {
            self.write(name, data);
        }
    }

    /// Reads `count` reals of buffer `name` back as f64.
    fn read_reals(&self, name: &str, count: usize) -> Result<Vec<f64>, SimError> {
        let bytes = count as u64 * real_bytes(&self.constants);
        let raw = self.read(name, bytes)?;
        Ok((0..count)
            .map(|k| real_at(&raw, k, self.constants.single))
            .collect())
    }

    /// A point as the kernels store it: its cell's coordinates in the grid (clamped into it,
    /// as the kernels clamp) and its offset from the cell's corner (m).
    fn relative(&self, x: &Vector<D>) -> ([i32; D], [f64; D]) {
        let c = &self.constants;
        let mut cell = [0i32; D];
        let mut offset = [0.0; D];
        for k in 0..D {
            let q = ((x[k] - c.domain_min[k]) / c.support).floor();
            let q = q.clamp(0.0, (c.dims[k] - 1) as f64) as i32;
            cell[k] = q;
            offset[k] = x[k] - (c.domain_min[k] + q as f64 * c.support);
        }
        (cell, offset)
    }

    /// Writes points into the offset buffer `pos` and the cell buffer `cell`.
    fn write_points(&self, pos: &str, cell: &str, points: &[Vector<D>]) {
        let mut cells = Vec::with_capacity(D * points.len());
        let mut offsets = Vec::with_capacity(D * points.len());
        for x in points {
            let (c, o) = self.relative(x);
            cells.extend_from_slice(&c);
            offsets.extend_from_slice(&o);
        }
        self.write(cell, &cells);
        self.write_reals(pos, &offsets);
    }

    fn write<T: bytemuck::Pod>(&self, name: &str, data: &[T]) {
        if !data.is_empty() {
            self.queue
                .write_buffer(&self.buffers[name], 0, bytemuck::cast_slice(data));
        }
    }

    /// Copies `bytes` of buffer `name` to the host.
    fn read(&self, name: &str, bytes: u64) -> Result<Vec<u8>, SimError> {
        let staging = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("staging read"),
            size: bytes.max(8).div_ceil(8) * 8,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = self.device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(
            &self.buffers[name],
            0,
            &staging,
            0,
            bytes.max(8).div_ceil(8) * 8,
        );
        self.queue.submit([encoder.finish()]);
        self.map_read(&staging, bytes)
    }

    fn map_read(&self, staging: &wgpu::Buffer, bytes: u64) -> Result<Vec<u8>, SimError> {
        self.with_mapped(staging, bytes, |view| view.to_vec())
    }

    /// Maps the first `bytes` of `staging` for reading and hands them to `read` in place (no
    /// host copy), then unmaps the buffer.
    fn with_mapped<R>(
        &self,
        staging: &wgpu::Buffer,
        bytes: u64,
        read: impl FnOnce(&[u8]) -> R,
    ) -> Result<R, SimError> {
        let slice = staging.slice(..);
        slice.map_async(wgpu::MapMode::Read, |_| {});
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| self.fail(format!("waiting for the device: {e}")))?;
        let out = {
            let view = slice
                .get_mapped_range()
                .map_err(|e| self.fail(format!("reading back: {e}")))?;
            read(&view[..bytes as usize])
        };
        staging.unmap();
        Ok(out)
    }

    fn fail(&self, what: String) -> SimError {
        SimError::InvalidSetup(format!("the GPU device {} failed: {what}", self.name))
    }

    /// The index of the cell of a wall particle, as the kernels number cells.
    fn cell_of(&self, x: &Vector<D>) -> u32 {
        let c = &self.constants;
        let (cell, _) = self.relative(x);
        let mut index = 0u32;
        let mut stride = 1u32;
        for (&ck, &dim) in cell.iter().zip(&c.dims) {
            index += ck as u32 * stride;
            stride *= dim;
        }
        index
    }

    fn encode(&self, encoder: &mut wgpu::CommandEncoder, kernel: &Kernel) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(kernel.id.name()),
            timestamp_writes: None,
        });
        pass.set_pipeline(&kernel.pipeline);
        pass.set_bind_group(0, &kernel.bind_group, &[]);
        pass.dispatch_workgroups(kernel.groups, 1, 1);
    }

    /// The copies of the gathered arrays back into the step's arrays (after the sort).
    fn encode_gather_copies(&self, encoder: &mut wgpu::CommandEncoder) {
        for (from, to) in [
            ("pos2", "pos"),
            ("pcell2", "pcell"),
            ("vel2", "vel"),
            ("vel_n2", "vel_n"),
            ("rho2", "rho"),
            ("rho_n2", "rho_n"),
            ("id2", "id"),
        ] {
            let size = self.buffers[to].size();
            encoder.copy_buffer_to_buffer(&self.buffers[from], 0, &self.buffers[to], 0, size);
        }
    }
}

impl<const D: usize> StepDevice<D> for GpuStep<D> {
    fn description(&self) -> String {
        self.name.clone()
    }

    fn upload(&mut self, setup: &DeviceSetup<'_, D>) -> Result<(), SimError> {
        let f = setup.fluid;
        if f.position.len() as u32 != self.constants.n_fluid
            || setup.walls.position.len() as u32 != self.constants.n_wall
        {
            return Err(self.fail("the particle counts changed since the device was built".into()));
        }
        self.write_points("pos", "pcell", &f.position);
        self.write_reals("vel", &flat(&f.velocity));
        self.write_reals("acc", &flat(&f.acceleration));
        self.write_reals("rho", &f.density);
        self.write_reals("drho", &f.density_rate);
        self.write_reals("p", &f.pressure);
        self.write("id", &f.id);
        // Walls sorted by cell once (they never move), with where each cell's start.
        let walls = setup.walls;
        let mut keyed: Vec<(u32, u32)> = walls
            .position
            .iter()
            .enumerate()
            .map(|(w, x)| (self.cell_of(x), w as u32))
            .collect();
        keyed.sort_unstable();
        let n_cells = self.constants.n_cells as usize;
        let mut wall_start = vec![0u32; n_cells + 1];
        for &(c, _) in &keyed {
            wall_start[c as usize + 1] += 1;
        }
        for c in 0..n_cells {
            wall_start[c + 1] += wall_start[c];
        }
        let wall_pos: Vec<Vector<D>> = keyed
            .iter()
            .map(|&(_, w)| walls.position[w as usize])
            .collect();
        self.wall_host_index = keyed.iter().map(|&(_, w)| w).collect();
        self.write_points("wall_pos", "wall_cell", &wall_pos);
        self.write("wall_start", &wall_start);
        let state: Vec<f64> = walls
            .pressure
            .iter()
            .zip(&walls.density)
            .map(|(p, r)| [*p, *r])
            .collect::<Vec<_>>()
            .concat();
        let sorted_state: Vec<f64> = self
            .wall_host_index
            .iter()
            .flat_map(|&w| [state[2 * w as usize], state[2 * w as usize + 1]])
            .collect();
        self.write_reals("wall_state", &sorted_state);
        self.queue.submit([]);
        Ok(())
    }

    fn step(
        &mut self,
        body_force: Vector<D>,
        walls: &mut Walls<D>,
    ) -> Result<DeviceStepReport<D>, SimError> {
        // The body force in the device's precision, from arrays on the stack.
        if self.constants.single {
            let body: [f32; D] = std::array::from_fn(|k| body_force[k] as f32);
            self.write("body", &body);
        } else {
            let body: [f64; D] = std::array::from_fn(|k| body_force[k]);
            self.write("body", &body);
        }
        let step_start = Instant::now();
        if self.profile {
            for k in 0..self.kernels.len() {
                let t0 = Instant::now();
                let mut encoder = self.device.create_command_encoder(&Default::default());
                self.encode(&mut encoder, &self.kernels[k]);
                if self.kernels[k].id == KernelId::Gather {
                    self.encode_gather_copies(&mut encoder);
                }
                self.queue.submit([encoder.finish()]);
                self.device
                    .poll(wgpu::PollType::wait_indefinitely())
                    .map_err(|e| self.fail(format!("waiting for the device: {e}")))?;
                self.times[k].1 += t0.elapsed().as_secs_f64();
            }
        }
        let mut encoder = self.device.create_command_encoder(&Default::default());
        if !self.profile {
            for kernel in &self.kernels {
                self.encode(&mut encoder, kernel);
                if kernel.id == KernelId::Gather {
                    self.encode_gather_copies(&mut encoder);
                }
            }
        }
        let real = real_bytes(&self.constants);
        let state_bytes = STATE_WORDS as u64 * real;
        encoder.copy_buffer_to_buffer(
            &self.buffers["state"],
            0,
            &self.staging_step,
            0,
            state_bytes,
        );
        encoder.copy_buffer_to_buffer(
            &self.buffers["flags"],
            0,
            &self.staging_step,
            state_bytes,
            (FLAG_WORDS * 4) as u64,
        );
        let wall_bytes = 2 * real * self.constants.n_wall as u64;
        if wall_bytes > 0 {
            encoder.copy_buffer_to_buffer(
                &self.buffers["wall_state"],
                0,
                &self.staging_walls,
                0,
                wall_bytes,
            );
        }
        self.queue.submit([encoder.finish()]);
        let step_bytes = self.staging_step.size();
        let single = self.constants.single;
        let state_end = state_bytes as usize;
        // The step report and the wall state are read where the device mapped them.
        let report = self.with_mapped(&self.staging_step, step_bytes, |raw| {
            let word = |k: usize| real_at(&raw[..state_end], k, single);
            let flags: &[u32] = bytemuck::cast_slice(&raw[state_end..state_end + FLAG_WORDS * 4]);
            DeviceStepReport {
                dt: word(0),
                max_speed: word(1),
                max_acceleration: word(2),
                non_finite: flags[0],
                outside: flags[1],
                first_outside: (flags[1] > 0).then(|| Vector::<D>::from_fn(|k, _| word(3 + k))),
            }
        })?;
        if wall_bytes > 0 {
            let index = &self.wall_host_index;
            self.with_mapped(&self.staging_walls, wall_bytes, |raw| {
                for (k, &w) in index.iter().enumerate() {
                    let (p, rho) = (real_at(raw, 2 * k, single), real_at(raw, 2 * k + 1, single));
                    let w = w as usize;
                    walls.pressure[w] = p;
                    walls.density[w] = rho;
                    walls.inverse_density[w] = 1.0 / rho;
                }
            })?;
        }
        if !self.profile {
            self.step_time += step_start.elapsed().as_secs_f64();
        }
        Ok(report)
    }

    fn download(&mut self, fluid: &mut Fluid<D>) -> Result<(), SimError> {
        let n = self.constants.n_fluid as usize;
        let vector = |v: Vec<f64>| -> Vec<Vector<D>> {
            (0..n)
                .map(|i| Vector::<D>::from_fn(|k, _| v[D * i + k]))
                .collect()
        };
        // Positions: the cell's corner plus the offset, in f64.
        let offsets = self.read_reals("pos", D * n)?;
        let raw_cells = self.read("pcell", (4 * D * n) as u64)?;
        let cells: &[i32] = bytemuck::cast_slice(&raw_cells);
        let c = &self.constants;
        fluid.position = (0..n)
            .map(|i| {
                Vector::<D>::from_fn(|k, _| {
                    c.domain_min[k] + cells[D * i + k] as f64 * c.support + offsets[D * i + k]
                })
            })
            .collect();
        fluid.velocity = vector(self.read_reals("vel", D * n)?);
        fluid.velocity_half.clone_from(&fluid.velocity);
        fluid.acceleration = vector(self.read_reals("acc", D * n)?);
        fluid.density = self.read_reals("rho", n)?;
        fluid.inverse_density = fluid.density.iter().map(|r| 1.0 / r).collect();
        fluid.pressure = self.read_reals("p", n)?;
        fluid.density_rate = self.read_reals("drho", n)?;
        let ids = self.read("id", (4 * n) as u64)?;
        fluid.id = bytemuck::cast_slice(&ids).to_vec();
        Ok(())
    }

    fn set_profiling(&mut self, on: bool) {
        self.profile = on;
    }

    fn kernel_times(&self) -> Vec<(String, f64)> {
        if self.profile {
            self.times.clone()
        } else {
            vec![("step".into(), self.step_time)]
        }
    }
}
