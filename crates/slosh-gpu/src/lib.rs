//! The GPU backend of slosh: the modern step of `slosh-core` as wgpu compute shaders (WGSL),
//! in double precision where the device offers it (`wgpu::Features::SHADER_F64`) or in single
//! precision with positions relative to their cell ([`Precision`]).
//!
//! [`attach`] hands a built [`slosh_core::Simulation`] to the first Vulkan device: every later
//! step runs there (`shader.rs` has the kernels, `device.rs` the buffers and the dispatch);
//! the simulation keeps the time, the step statistics and the load evaluation, and copies the
//! particles back only when a caller reads them (`Simulation::sync_host`). Each step sorts the
//! particles by cell on the device (a counting sort of their cell keys), so no particle array
//! crosses to the host but what an output row, a frame or a checkpoint needs; what does cross
//! every step is the step length, the blow-up counts and the wall pressures the loads are read
//! from.

mod device;
mod shader;

pub use device::{GpuError, GpuStep, SOFTWARE_DEVICE};

use slosh_core::{SimError, Simulation};

/// Floating-point precision of the device's arithmetic.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Precision {
    /// f64 throughout (needs `SHADER_F64`).
    F64,
    /// f32 throughout, positions kept as an offset from the particle's cell (so their
    /// round-off is ≈ 1e-7 of the cell, 2h, whatever the tank's size); runs on any device.
    F32,
}

impl Precision {
    /// The precision a run's `backend` asks for, or `None` for the CPU.
    pub fn of(backend: slosh_core::Backend) -> Option<Precision> {
        match backend {
            slosh_core::Backend::Cpu => None,
            slosh_core::Backend::Gpu => Some(Precision::F64),
            slosh_core::Backend::GpuF32 => Some(Precision::F32),
        }
    }
}

/// Builds the device step for `sim` on the first Vulkan adapter and attaches it; returns the
/// device's description ("llvmpipe (LLVM 15.0.6, 256 bits), Vulkan, f64"). Fails with a
/// message that says why when no device can run it: no Vulkan device, no f64 support, or a
/// run whose parameters are not the modern step's.
pub fn attach<const D: usize>(
    sim: &mut Simulation<D>,
    precision: Precision,
) -> Result<String, SimError> {
    let setup = sim.device_setup()?;
    let step =
        GpuStep::<D>::new(&setup, precision).map_err(|e| SimError::InvalidSetup(e.to_string()))?;
    let description = slosh_core::StepDevice::description(&step);
    sim.attach_device(Box::new(step))?;
    Ok(description)
}
