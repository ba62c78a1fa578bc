//! Host <-> device transfers of the engine: bytes written after the pending
//! commands and read back through one staging buffer, and the f64 host
//! vectors of a mixed-precision product converted to and from the device's
//! f32 in parallel, with one copy between the host and the staging memory
//! (at 2048^2 a contact set of 4 million cells crosses the bus twice per
//! product, and each pass over it on one core costs milliseconds).

use std::num::NonZeroU64;
use std::sync::mpsc;

use rayon::prelude::*;

use super::{Buf, Engine};
use crate::backend::gpu::context::GpuError;

/// Values converted per parallel task (256 KiB of f32: a cache's worth).
const CHUNK: usize = 1 << 16;

impl Engine {
    /// Write host bytes into a buffer, after the pending commands.
    pub fn write(&mut self, dst: &Buf, offset: u64, data: &[u8]) {
        if data.is_empty() {
            return;
        }
        self.flush();
        self.ctx.queue.write_buffer(&dst.buffer, offset, data);
    }

    /// Write `values` rounded to f32 at the start of `dst`, after the
    /// pending commands: converted in parallel into the engine's upload
    /// scratch (kept between writes), then copied once into the queue's
    /// staging memory.
    pub fn write_f64_as_f32(&mut self, dst: &Buf, values: &[f64]) {
        let Some(size) = NonZeroU64::new(4 * values.len() as u64) else {
            return;
        };
        let mut scratch = std::mem::take(&mut self.upload_scratch);
        scratch.resize(4 * values.len(), 0);
        scratch
            .par_chunks_mut(4 * CHUNK)
            .zip(values.par_chunks(CHUNK))
            .for_each(|(bytes, chunk)| {
                for (b, &v) in bytes.chunks_exact_mut(4).zip(chunk) {
                    b.copy_from_slice(&(v as f32).to_le_bytes());
                }
            });
        self.flush();
        let mut view = self
            .ctx
            .queue
            .write_buffer_with(&dst.buffer, 0, size)
            .unwrap_or_else(|| {
                panic!(
                    "a write of {size} bytes to a {}-byte buffer",
                    dst.buffer.size()
                )
            });
        view.copy_from_slice(&scratch);
        drop(view);
        self.upload_scratch = scratch;
    }

    /// Read `count` f32 values from `src`.
    pub fn read_f32(&mut self, src: &Buf, offset_elems: u64, count: usize) -> Vec<f32> {
        self.read_with(src, offset_elems * 4, count as u64 * 4, |bytes| {
            bytes
                .chunks_exact(4)
                .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
                .collect()
        })
    }

    /// Read the first `out.len()` f32 values of `src` into `out` as f64,
    /// converted straight from the mapped staging memory, in parallel.
    pub fn read_f32_as_f64(&mut self, src: &Buf, out: &mut [f64]) {
        self.read_with(src, 0, 4 * out.len() as u64, |bytes| {
            out.par_chunks_mut(CHUNK)
                .zip(bytes.par_chunks(4 * CHUNK))
                .for_each(|(o, b)| {
                    for (v, b) in o.iter_mut().zip(b.chunks_exact(4)) {
                        *v = f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64;
                    }
                });
        });
    }

    /// Read one u32 at element `offset_elems`.
    pub fn read_u32(&mut self, src: &Buf, offset_elems: u64) -> u32 {
        self.read_with(src, offset_elems * 4, 4, |b| {
            u32::from_le_bytes([b[0], b[1], b[2], b[3]])
        })
    }

    /// `f` of the `size` bytes of `src` from `offset`, mapped after the
    /// pending commands (copied into the readback staging buffer, which
    /// grows to the largest read). Panics if the device is lost (the
    /// backend trait returns no error).
    fn read_with<R>(&mut self, src: &Buf, offset: u64, size: u64, f: impl FnOnce(&[u8]) -> R) -> R {
        if size == 0 {
            return f(&[]);
        }
        let need = size.next_multiple_of(4);
        if self.staging.as_ref().is_none_or(|s| s.buffer.size() < need) {
            let cap = need.next_power_of_two().max(1 << 16);
            let b = self.create_buffer(
                "viscoslide readback staging",
                cap,
                wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            );
            self.staging = Some(b);
        }
        let staging = self.staging.clone().expect("staging buffer exists");
        self.copy(src, offset, &staging, 0, need);
        self.flush();
        let slice = staging.buffer.slice(0..need);
        let (tx, rx) = mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        self.ctx
            .device
            .poll(wgpu::PollType::wait_indefinitely())
            .unwrap_or_else(|e| panic!("{}", GpuError::Readback(e.to_string())));
        match rx.recv() {
            Ok(Ok(())) => {}
            Ok(Err(e)) => panic!("{}", GpuError::Readback(e.to_string())),
            Err(e) => panic!("{}", GpuError::Readback(e.to_string())),
        }
        let out = {
            let view = slice
                .get_mapped_range()
                .unwrap_or_else(|e| panic!("{}", GpuError::Readback(e.to_string())));
            f(&view[..size as usize])
        };
        staging.buffer.unmap();
        out
    }
}
