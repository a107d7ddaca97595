//! The GPU context every simulation of the process shares: the adapter, its device and queue,
//! and every stage compiled once for that device. A simulation keeps only its own buffers and
//! bind groups (`buffers.rs`, `pipelines.rs`'s `BindGroups`): the split of pipelines per device
//! from data per simulation of wgsparkl. Creating the context (the adapter, the device, the
//! shaders compiled) is most of the time to a simulation's first GPU frame; with it shared,
//! the Live tool's rebuilds and a batch of simulations pay it once.
//!
//! The context lives for the process once made, and is made again only after its device was
//! lost. wgpu 26's error scopes belong to the device, not to a thread, so a simulation that
//! opens one (`GpuContext::validated`) holds the context's scope lock until it closes it: two
//! simulations stepping on two threads never catch each other's errors.

use std::sync::{Arc, Mutex, MutexGuard};

use super::pipelines::Pipelines;

pub(super) struct GpuContext {
    pub(super) device: wgpu::Device,
    pub(super) queue: wgpu::Queue,
    pub(super) info: wgpu::AdapterInfo,
    pub(super) pipelines: Pipelines,
    /// The device writes timestamps inside compute passes (`TIMESTAMP_QUERY_INSIDE_PASSES`),
    /// so frames can report per-stage GPU times; and nanoseconds per timestamp tick.
    pub(super) timestamps: bool,
    pub(super) timestamp_period: f32,
    /// The first error wgpu reported outside a scope (validation, out of memory), taken by the
    /// first simulation that looks.
    errors: Arc<Mutex<Option<String>>>,
    /// Why the device was lost, if it was: every simulation on it sees it, and no new one is
    /// given this context.
    lost: Arc<Mutex<Option<String>>>,
    scope: Mutex<()>,
}

/// The context in use; replaced only after its device was lost.
static SHARED: Mutex<Option<Arc<GpuContext>>> = Mutex::new(None);

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

impl GpuContext {
    /// The shared context, made on first use (or again after a lost device), and whether this
    /// call made it. `Err` names why there is none (no adapter, device refused, shaders failed).
    pub(super) fn shared() -> Result<(Arc<GpuContext>, bool), String> {
        let mut slot = lock(&SHARED);
        if let Some(ctx) = slot.as_ref() {
            if lock(&ctx.lost).is_none() {
                return Ok((ctx.clone(), false));
            }
        }
        let ctx = Arc::new(Self::create()?);
        *slot = Some(ctx.clone());
        Ok((ctx, true))
    }

    fn create() -> Result<GpuContext, String> {
        let instance = wgpu::Instance::new(&wgpu::InstanceDescriptor {
            backends: wgpu::Backends::from_env().unwrap_or(wgpu::Backends::all()),
            ..Default::default()
        });
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: None,
        }))
        .map_err(|e| format!("no GPU adapter: {e}"))?;
        let info = adapter.get_info();
        // The stages bind up to 8 storage buffers; ask for what the adapter has (at least the
        // WebGPU defaults) rather than the downlevel minimum.
        let wanted = wgpu::Features::TIMESTAMP_QUERY
            | wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS
            | wgpu::Features::TIMESTAMP_QUERY_INSIDE_PASSES;
        // Asking for the features costs nothing; a simulation writes timestamps only when its
        // stage timing is on (`GpuSolver::set_stage_timing`).
        let timestamps = adapter.features().contains(wanted);
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("tailor"),
            required_limits: adapter.limits(),
            required_features: if timestamps { wanted } else { wgpu::Features::empty() },
            ..Default::default()
        }))
        .map_err(|e| format!("GPU device request failed on {}: {e}", info.name))?;
        let errors = Arc::new(Mutex::new(None::<String>));
        let lost = Arc::new(Mutex::new(None::<String>));
        {
            let errors = errors.clone();
            device.on_uncaptured_error(Box::new(move |e| {
                lock(&errors).get_or_insert_with(|| e.to_string());
            }));
        }
        {
            let lost = lost.clone();
            device.set_device_lost_callback(move |_, msg| {
                lock(&lost).get_or_insert_with(|| format!("device lost: {msg}"));
            });
        }
        device.push_error_scope(wgpu::ErrorFilter::Validation);
        let pipelines = Pipelines::compile(&device);
        if let Some(e) = pollster::block_on(device.pop_error_scope()) {
            return Err(format!("compiling the shaders failed on {}: {e}", info.name));
        }
        let timestamp_period = queue.get_timestamp_period();
        Ok(GpuContext {
            device,
            queue,
            info,
            pipelines,
            timestamps,
            timestamp_period,
            errors,
            lost,
            scope: Mutex::new(()),
        })
    }

    /// Runs `f` inside a validation error scope of its own; returns its result and the
    /// validation error it caused, if any.
    pub(super) fn validated<R>(&self, f: impl FnOnce() -> R) -> (R, Option<String>) {
        let _only_scope = lock(&self.scope);
        self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let r = f();
        let e = pollster::block_on(self.device.pop_error_scope()).map(|e| e.to_string());
        (r, e)
    }

    /// The device's loss, or else an error reported outside any scope (taken).
    pub(super) fn take_error(&self) -> Option<String> {
        if let Some(l) = lock(&self.lost).clone() {
            return Some(l);
        }
        lock(&self.errors).take()
    }
}
