//! Command recording and submission. Kernels are recorded into a pending
//! list and submitted together when the host needs a result (a readback) or
//! writes a buffer; the parameters of each dispatch occupy one slot of a
//! uniform ring bound with a dynamic offset, written just before the
//! submission. Pipelines and bind groups are created once and cached
//! (DESIGN.md "plan once, apply many"); every resource carries a label.
//! A buffer larger than the device's largest storage binding is bound as
//! several windows where the kernel allows it ([`Kernel::splittable`],
//! [`super::split`]); the pipeline of each split is compiled once.
//!
//! The one place that talks to wgpu for every kernel (pipeline and
//! bind-group caches, the parameter ring, buffers, submission and
//! read-back); the table of the kernels and their bindings is
//! [`Kernel`] (`kernel.rs`).

use std::collections::HashMap;

use bytemuck::{Pod, Zeroable};

use super::context::{check_binding_count, GpuContext, GpuError};
use super::shaders;
use super::split;

mod kernel;
mod transfer;

pub use kernel::Kernel;

/// Invocations per workgroup of every kernel (`WG` in `shared/common.wgsl`).
pub const WORKGROUP: u32 = 256;
/// Workgroups of one dispatch along x (the WebGPU minimum limit).
const MAX_GROUPS_X: u32 = 65_535;
/// Slots of the parameter ring.
const RING_SLOTS: u64 = 512;

/// Windows of each storage binding of a dispatch (1: the whole buffer).
type Split = [u64; 7];

/// Parameters of one dispatch (`Params` in `shared/common.wgsl`).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, Pod, Zeroable)]
pub struct Params {
    pub i: [u32; 4],
    pub j: [u32; 4],
    pub f: [f32; 4],
}

/// A buffer with a stable id (the key of the bind-group cache).
#[derive(Debug, Clone)]
pub struct Buf {
    pub id: u64,
    pub buffer: wgpu::Buffer,
}

struct Pipeline {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
}

enum Command {
    Dispatch {
        pipeline: wgpu::ComputePipeline,
        bind: wgpu::BindGroup,
        offset: u32,
        groups: (u32, u32),
    },
    Clear(wgpu::Buffer),
    Copy {
        src: wgpu::Buffer,
        src_offset: u64,
        dst: wgpu::Buffer,
        dst_offset: u64,
        size: u64,
    },
}

/// The device, its caches and the pending commands.
pub struct Engine {
    pub ctx: GpuContext,
    pipelines: HashMap<(Kernel, Split), Pipeline>,
    binds: HashMap<(Kernel, [u64; 7]), wgpu::BindGroup>,
    ring: Buf,
    stride: u64,
    staged: Vec<u8>,
    commands: Vec<Command>,
    staging: Option<Buf>,
    /// Host bytes of the last f32 upload converted from f64, reused.
    upload_scratch: Vec<u8>,
    next_id: u64,
    /// Buffers created, by label: count and bytes (the device memory of
    /// the engine's arrays; [`Engine::allocations`]).
    allocated: std::collections::BTreeMap<String, (usize, u64)>,
    /// Complex elements of the workgroup block of the shared-memory FFT
    /// kernels (`FFT_SHARED` in `shared/fft_block.wgsl`), from the
    /// device's workgroup storage limit.
    pub fft_shared: usize,
    /// Bytes of one window of a split binding ([`split::window_bytes`]).
    window: u64,
}

/// Workgroup grid `(x, y)` covering `threads` invocations.
pub fn groups_for(threads: u64) -> (u32, u32) {
    let g = threads.div_ceil(WORKGROUP as u64).max(1);
    let x = g.min(MAX_GROUPS_X as u64);
    (x as u32, g.div_ceil(x) as u32)
}

impl Engine {
    pub fn new(ctx: GpuContext) -> Self {
        let align: u64 = ctx
            .device
            .limits()
            .min_uniform_buffer_offset_alignment
            .into();
        let stride = (std::mem::size_of::<Params>() as u64).next_multiple_of(align.max(1));
        let ring = wgpu::BufferDescriptor {
            label: Some("viscoslide parameter ring"),
            size: stride * RING_SLOTS,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        };
        let ring = Buf {
            id: 0,
            buffer: ctx.device.create_buffer(&ring),
        };
        let fft_shared =
            shaders::shared_elements(ctx.device.limits().max_compute_workgroup_storage_size as u64);
        let limits = ctx.device.limits();
        let window = split::window_bytes(
            limits
                .max_storage_buffer_binding_size
                .min(limits.max_buffer_size),
            limits.min_storage_buffer_offset_alignment.into(),
        );
        Self {
            fft_shared,
            window,
            ctx,
            pipelines: HashMap::new(),
            binds: HashMap::new(),
            ring,
            stride,
            allocated: std::collections::BTreeMap::new(),
            staged: Vec::new(),
            commands: Vec::new(),
            staging: None,
            upload_scratch: Vec::new(),
            next_id: 1,
        }
    }

    /// Largest storage binding of the device \[bytes\].
    pub fn max_binding(&self) -> u64 {
        let l = self.ctx.device.limits();
        l.max_storage_buffer_binding_size.min(l.max_buffer_size)
    }

    /// Fail with [`GpuError::TooLarge`] when `bytes` exceed one binding.
    pub fn check_binding(&self, what: &str, bytes: u64) -> Result<(), GpuError> {
        let limit = self.max_binding();
        if bytes > limit {
            return Err(GpuError::TooLarge {
                what: what.to_string(),
                need: bytes,
                limit,
                per: "per storage binding",
                adapter: self.ctx.adapter.name.clone(),
            });
        }
        Ok(())
    }

    /// Bytes of one window of a split binding.
    pub fn window_bytes(&self) -> u64 {
        self.window
    }

    /// Windows a buffer of `bytes` occupies when bound by a kernel that
    /// splits it (1 when it fits one binding).
    pub fn windows(&self, bytes: u64) -> u64 {
        if bytes <= self.max_binding() {
            1
        } else {
            split::windows(bytes, self.window)
        }
    }

    /// Fail with [`GpuError::TooLarge`] when `bytes` exceed one buffer
    /// (`max_buffer_size`): the limit of an array that kernels bind in
    /// windows.
    pub fn check_buffer(&self, what: &str, bytes: u64) -> Result<(), GpuError> {
        let limit = self.ctx.device.limits().max_buffer_size;
        if bytes > limit {
            return Err(GpuError::TooLarge {
                what: what.to_string(),
                need: bytes,
                limit,
                per: "per buffer",
                adapter: self.ctx.adapter.name.clone(),
            });
        }
        Ok(())
    }

    /// Fail with [`GpuError::TooManyBindings`] when a kernel would need
    /// more than the device's storage bindings per shader stage
    /// (`bindings`, windows of split arrays included).
    pub fn check_bindings(&self, what: &str, bindings: u64) -> Result<(), GpuError> {
        check_binding_count(
            what,
            bindings,
            &self.ctx.device.limits(),
            &self.ctx.adapter.name,
        )
    }

    /// Fail when `kernel` cannot bind `arrays` (`(name, bytes)` in binding
    /// order): an array it splits beyond one buffer, another beyond one
    /// binding, or all their windows beyond the storage bindings per shader
    /// stage (`what`: the dispatch, for that message).
    pub fn check_kernel(
        &self,
        what: &str,
        kernel: Kernel,
        arrays: &[(&str, u64)],
    ) -> Result<(), GpuError> {
        let mut bindings = 0;
        for (k, &(name, bytes)) in arrays.iter().enumerate() {
            if kernel.splittable().get(k) == Some(&true) {
                self.check_buffer(name, bytes)?;
                bindings += self.windows(bytes);
            } else {
                self.check_binding(name, bytes)?;
                bindings += 1;
            }
        }
        self.check_bindings(what, bindings)
    }

    /// A new labelled buffer (zero-initialised by wgpu).
    pub fn create_buffer(&mut self, label: &str, size: u64, usage: wgpu::BufferUsages) -> Buf {
        let size = size.max(4).next_multiple_of(4);
        let entry = self.allocated.entry(label.to_string()).or_default();
        entry.0 += 1;
        entry.1 += size;
        let buffer = self.ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage,
            mapped_at_creation: false,
        });
        self.next_id += 1;
        Buf {
            id: self.next_id,
            buffer,
        }
    }

    /// Every buffer this engine created (the parameter ring aside; the
    /// readback staging buffer at each size it grew to), by label:
    /// `(label, buffers, bytes)`. Grid vectors are recycled by their pool, not freed, so
    /// their count is the most held at once; a buffer dropped early (the
    /// device coefficient table, read back before the operator is built)
    /// is counted too.
    pub fn allocations(&self) -> Vec<(String, usize, u64)> {
        self.allocated
            .iter()
            .map(|(label, &(count, bytes))| (label.clone(), count, bytes))
            .collect()
    }

    /// A storage buffer holding `data`.
    pub fn storage_with(&mut self, label: &str, data: &[u8]) -> Buf {
        let b = self.create_buffer(
            label,
            data.len() as u64,
            wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_DST
                | wgpu::BufferUsages::COPY_SRC,
        );
        self.write(&b, 0, data);
        b
    }

    fn pipeline(&mut self, kernel: Kernel, windows: Split) -> &Pipeline {
        if !self.pipelines.contains_key(&(kernel, windows)) {
            let device = &self.ctx.device;
            let source = shaders::compose(kernel.file()).expect("every kernel has a shader file");
            let source = shaders::with_fft_shared(&source, self.fft_shared);
            let count = kernel.storage().len();
            let source = split::split_source(&source, &windows[..count], self.window)
                .unwrap_or_else(|e| panic!("{kernel:?}: {e}"));
            let label = format!("viscoslide {}", kernel.file());
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(&label),
                source: wgpu::ShaderSource::Wgsl(source.into()),
            });
            let mut entries = vec![wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: true,
                    min_binding_size: wgpu::BufferSize::new(std::mem::size_of::<Params>() as u64),
                },
                count: None,
            }];
            let extra = kernel
                .storage()
                .iter()
                .enumerate()
                .flat_map(|(k, &r)| std::iter::repeat_n(r, windows[k] as usize - 1));
            let access: Vec<bool> = kernel.storage().iter().copied().chain(extra).collect();
            for (k, &read_only) in access.iter().enumerate() {
                entries.push(wgpu::BindGroupLayoutEntry {
                    binding: k as u32 + 1,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Storage { read_only },
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                });
            }
            let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(&label),
                entries: &entries,
            });
            let pl = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(&label),
                bind_group_layouts: &[Some(&layout)],
                immediate_size: 0,
            });
            let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(&label),
                layout: Some(&pl),
                module: &module,
                entry_point: Some("main"),
                compilation_options: Default::default(),
                cache: None,
            });
            self.pipelines
                .insert((kernel, windows), Pipeline { layout, pipeline });
        }
        &self.pipelines[&(kernel, windows)]
    }

    /// Windows of each binding of `kernel` over `bufs`; panics when a
    /// buffer that the kernel cannot split exceeds one binding (callers
    /// refuse such sizes first, [`Engine::check_binding`]).
    fn split_of(&self, kernel: Kernel, bufs: &[&Buf]) -> Split {
        let mut windows = [1u64; 7];
        for (k, b) in bufs.iter().enumerate() {
            let size = b.buffer.size();
            windows[k] = self.windows(size);
            assert!(
                windows[k] == 1 || kernel.splittable().get(k) == Some(&true),
                "{kernel:?}: binding {} of {size} bytes exceeds one storage binding ({} bytes)",
                k + 1,
                self.max_binding()
            );
        }
        windows
    }

    /// Window `w` of a buffer bound in `windows` windows.
    fn window_of<'a>(&self, b: &'a Buf, windows: u64, w: u64) -> wgpu::BindingResource<'a> {
        if windows == 1 {
            return b.buffer.as_entire_binding();
        }
        let offset = w * self.window;
        wgpu::BindingResource::Buffer(wgpu::BufferBinding {
            buffer: &b.buffer,
            offset,
            size: wgpu::BufferSize::new(self.window.min(b.buffer.size() - offset)),
        })
    }

    /// Record `kernel` over a `groups` workgroup grid with storage bindings
    /// `bufs` (in binding order) and parameters `params`.
    pub fn dispatch(&mut self, kernel: Kernel, bufs: &[&Buf], params: Params, groups: (u32, u32)) {
        assert_eq!(bufs.len(), kernel.storage().len(), "{kernel:?} bindings");
        if self.staged.len() as u64 >= self.stride * RING_SLOTS {
            self.flush();
        }
        let mut key = [0u64; 7];
        for (k, b) in bufs.iter().enumerate() {
            key[k] = b.id;
        }
        let windows = self.split_of(kernel, bufs);
        let pipeline = self.pipeline(kernel, windows).pipeline.clone();
        if !self.binds.contains_key(&(kernel, key)) {
            let layout = &self.pipelines[&(kernel, windows)].layout;
            let mut entries = vec![wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                    buffer: &self.ring.buffer,
                    offset: 0,
                    size: wgpu::BufferSize::new(std::mem::size_of::<Params>() as u64),
                }),
            }];
            for (k, b) in bufs.iter().enumerate() {
                entries.push(wgpu::BindGroupEntry {
                    binding: k as u32 + 1,
                    resource: self.window_of(b, windows[k], 0),
                });
            }
            // The further windows of split buffers, numbered after the
            // kernel's own bindings (the order of split::split_source).
            let mut next = bufs.len() as u32 + 1;
            for (k, b) in bufs.iter().enumerate() {
                for w in 1..windows[k] {
                    entries.push(wgpu::BindGroupEntry {
                        binding: next,
                        resource: self.window_of(b, windows[k], w),
                    });
                    next += 1;
                }
            }
            let bind = self
                .ctx
                .device
                .create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some(&format!("viscoslide {} bindings", kernel.file())),
                    layout,
                    entries: &entries,
                });
            self.binds.insert((kernel, key), bind);
        }
        let bind = self.binds[&(kernel, key)].clone();
        let offset = self.staged.len() as u32;
        self.staged.extend_from_slice(bytemuck::bytes_of(&params));
        self.staged
            .resize(offset as usize + self.stride as usize, 0);
        self.commands.push(Command::Dispatch {
            pipeline,
            bind,
            offset,
            groups,
        });
    }

    /// Record zeroing a whole buffer.
    pub fn clear(&mut self, buf: &Buf) {
        self.commands.push(Command::Clear(buf.buffer.clone()));
    }

    /// Record a buffer-to-buffer copy of `size` bytes.
    pub fn copy(&mut self, src: &Buf, src_offset: u64, dst: &Buf, dst_offset: u64, size: u64) {
        if size == 0 {
            return;
        }
        self.commands.push(Command::Copy {
            src: src.buffer.clone(),
            src_offset,
            dst: dst.buffer.clone(),
            dst_offset,
            size,
        });
    }

    /// Submit the pending commands.
    pub fn flush(&mut self) {
        if self.commands.is_empty() {
            return;
        }
        if !self.staged.is_empty() {
            self.ctx
                .queue
                .write_buffer(&self.ring.buffer, 0, &self.staged);
        }
        let mut enc = self
            .ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("viscoslide commands"),
            });
        let mut k = 0;
        let commands = std::mem::take(&mut self.commands);
        while k < commands.len() {
            match &commands[k] {
                Command::Dispatch { .. } => {
                    let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                        label: Some("viscoslide kernels"),
                        timestamp_writes: None,
                    });
                    while let Some(Command::Dispatch {
                        pipeline,
                        bind,
                        offset,
                        groups,
                    }) = commands.get(k)
                    {
                        pass.set_pipeline(pipeline);
                        pass.set_bind_group(0, bind, &[*offset]);
                        pass.dispatch_workgroups(groups.0, groups.1, 1);
                        k += 1;
                    }
                }
                Command::Clear(b) => {
                    enc.clear_buffer(b, 0, None);
                    k += 1;
                }
                Command::Copy {
                    src,
                    src_offset,
                    dst,
                    dst_offset,
                    size,
                } => {
                    enc.copy_buffer_to_buffer(src, *src_offset, dst, *dst_offset, *size);
                    k += 1;
                }
            }
        }
        self.ctx.queue.submit([enc.finish()]);
        self.staged.clear();
    }
}
