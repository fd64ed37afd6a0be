//! The limits a run is held to before it starts, so that no argument can make the harness
//! allocate until the machine runs out of memory, or run for days.
//!
//! Every option of the command line has a declared range (clap checks the integer ones with
//! the constants here; see docs/reliability.md). What a range cannot say, the memory a
//! run of a given image size needs, [`check_memory`] estimates before any image is allocated
//! and compares with what the machine can give and with the adapter's largest buffer (wgpu
//! does not report a hardware adapter's free memory; on a software adapter the machine's
//! memory is the adapter's).

use crate::{Frames, Size};
use anyhow::{Result, bail};

/// Largest `--ref-depth` (specular interactions per reference path).
pub const MAX_REF_DEPTH: u32 = 64;
/// Largest `--ref-photons`: 25 times the default; about 2 min of light tracing per
/// reference image on the 2-core development machine.
pub const MAX_REF_PHOTONS: u64 = 100_000_000;
/// Largest `--ref-spp` (eye samples per pixel of the reference).
pub const MAX_REF_SPP: u32 = 256;
/// Largest `bench --time` (seconds along the camera path; past a path's end its last key
/// holds).
pub const MAX_TIME: f32 = 1.0e6;

/// GPU bytes per pixel a technique's frame may hold: the target (16 colour + 4 depth), its
/// read-back buffer (16), and up to six more screen-sized float targets of a technique's own
/// (front/back buffers, float accumulation, depth pre-passes).
pub const GPU_BYTES_PER_PIXEL: u64 = 16 + 4 + 16 + 6 * 16;
/// CPU bytes per pixel and error frame held by a compare: the technique's and the reference's
/// HDR images (16 each), the reference's ids and mask (5), the FLIP map (4) and the sRGB and
/// encoder copies of one frame being written (about 16).
pub const CPU_BYTES_PER_PIXEL_AND_FRAME: u64 = 16 + 16 + 5 + 4 + 16;
/// CPU bytes per pixel of one reference render at work (rows, splat lists of the light pass).
pub const CPU_BYTES_PER_PIXEL_REFERENCE: u64 = 64;

/// What a run of `size` with `frames` needs, in bytes: (GPU, CPU).
pub fn estimate(size: Size, frames: Frames) -> (u64, u64) {
    let pixels = size.width as u64 * size.height as u64;
    let errors = frames.errors.clamp(1, Frames::MAX_ERRORS) as u64;
    let gpu = pixels * GPU_BYTES_PER_PIXEL;
    let cpu = pixels * (errors * CPU_BYTES_PER_PIXEL_AND_FRAME + CPU_BYTES_PER_PIXEL_REFERENCE);
    (gpu, cpu)
}

/// The memory this machine can still give (Linux: `MemAvailable` of /proc/meminfo), `None`
/// where it cannot be read.
pub fn available_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

fn gb(bytes: u64) -> String {
    format!("{:.1} GB", bytes as f64 / 1e9)
}

/// Fails, with one sentence, when a run of `size` with `frames` cannot fit: its largest GPU
/// buffer (the read-back of the colour target) over the adapter's `max_buffer_size`, or its
/// memory over what the machine has available. On a software adapter (lavapipe) the GPU's
/// memory is the machine's, so both estimates count against it.
pub fn check_memory(ctx: &gpu::Context, size: Size, frames: Frames) -> Result<()> {
    ctx.check_size(size.width, size.height)?;
    let readback = size.width as u64 * size.height as u64 * 16;
    let max_buffer = ctx.device.limits().max_buffer_size;
    if readback > max_buffer {
        bail!(
            "a {size} image needs a {} read-back buffer, more than this adapter's largest buffer \
             ({}); choose a smaller --size",
            gb(readback),
            gb(max_buffer)
        );
    }
    let (gpu_bytes, cpu_bytes) = estimate(size, frames);
    let need = if ctx.summary.is_software {
        gpu_bytes + cpu_bytes
    } else {
        cpu_bytes
    };
    if let Some(available) = available_memory()
        && need > available
    {
        let gpu_part = if ctx.summary.is_software {
            format!(
                " (of it {} for the software adapter's images)",
                gb(gpu_bytes)
            )
        } else {
            String::new()
        };
        bail!(
            "a {size} run with {} error frame(s) needs about {}{gpu_part}, but this machine has {} \
             available; choose a smaller --size or fewer --error-frames",
            frames.errors,
            gb(need),
            gb(available)
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn estimates_grow_with_pixels_and_error_frames() {
        let frames = Frames::default();
        let (g1, c1) = estimate(Size::new(256, 256), frames);
        let (g2, c2) = estimate(Size::new(512, 512), frames);
        assert_eq!((g2, c2), (4 * g1, 4 * c1));
        let more = Frames {
            errors: 30,
            ..frames
        };
        let c30 = estimate(Size::new(256, 256), more).1;
        assert_eq!(c30 - c1, 27 * CPU_BYTES_PER_PIXEL_AND_FRAME * 256 * 256);
        // The case: 11600 x 11600 needs far more than this 24 GB machine.
        let (g, c) = estimate(Size::new(11600, 11600), frames);
        assert!(g + c > 24_000_000_000, "{}", g + c);
    }
}
