//! Grid-sized storage buffers, recycled. Every vector and index of the
//! iteration occupies one buffer of `4 nx ny` bytes (f32 values or u32
//! positions); short vectors over a contact set use a logical length inside
//! the same storage, so resizing never allocates. A buffer dropped by its
//! owner goes back to the pool; the engine's bind-group cache keys on the
//! buffer id, which stays valid because the buffer itself is kept.

use std::sync::{Arc, Mutex};

use super::engine::{Buf, Engine};

/// The free list of grid buffers.
#[derive(Clone)]
pub struct Pool {
    free: Arc<Mutex<Vec<Buf>>>,
    bytes: u64,
}

/// A buffer borrowed from the pool; returned on drop.
pub struct Slot {
    buf: Buf,
    free: Arc<Mutex<Vec<Buf>>>,
}

impl Slot {
    pub fn buf(&self) -> &Buf {
        &self.buf
    }
}

impl Drop for Slot {
    fn drop(&mut self) {
        if let Ok(mut f) = self.free.lock() {
            f.push(self.buf.clone());
        }
    }
}

impl Pool {
    /// A pool of buffers of `bytes` bytes each.
    pub fn new(bytes: u64) -> Self {
        Self {
            free: Arc::new(Mutex::new(Vec::new())),
            bytes: bytes.max(4),
        }
    }

    /// A buffer from the free list, or a new one. Contents unspecified.
    pub fn take(&self, engine: &mut Engine) -> Slot {
        let recycled = self.free.lock().ok().and_then(|mut f| f.pop());
        let buf = recycled.unwrap_or_else(|| {
            engine.create_buffer(
                "viscoslide grid vector",
                self.bytes,
                wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_SRC
                    | wgpu::BufferUsages::COPY_DST,
            )
        });
        Slot {
            buf,
            free: Arc::clone(&self.free),
        }
    }

    /// Buffers currently free.
    pub fn free_count(&self) -> usize {
        self.free.lock().map(|f| f.len()).unwrap_or(0)
    }
}
