//! GPU conformance of `shaders/medium.wgsl` (box clipping, transmittance, Henyey-Greenstein)
//! against its Rust twin `scene::medium`, on random media, segments and angles; and a mutated
//! shader fails the comparison.

use glam::{Vec3, Vec4};
use scene::Medium;
use scene::medium::{MEDIUM, MEDIUM_WGSL, MediumGpu, henyey_greenstein};

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Case {
    medium: MediumGpu,
    /// xyz origin, w t_max.
    origin: [f32; 4],
    /// xyz unit direction, w cos theta.
    dir: [f32; 4],
}

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 % 1_000_000) as f32 / 1_000_000.0
    }
    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.next()
    }
    fn vec(&mut self, lo: f32, hi: f32) -> Vec3 {
        Vec3::new(self.range(lo, hi), self.range(lo, hi), self.range(lo, hi))
    }
}

fn cases() -> Vec<(Medium, Vec3, Vec3, f32, f32)> {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    (0..2048)
        .map(|i| {
            let min = rng.vec(-3.0, 0.0);
            let max = min + rng.vec(0.2, 3.0);
            let m = Medium {
                name: "m".into(),
                min,
                max,
                scattering: rng.vec(0.0, 2.0),
                absorption: rng.vec(0.0, 1.0),
                anisotropy: rng.range(-0.9, 0.9),
            };
            // Origins inside and outside, rays through the box and past it; some stopped
            // short by a surface, some unbounded.
            let origin = rng.vec(-4.0, 2.0);
            // Most rays aim into the box.
            let target = if i % 4 == 0 {
                rng.vec(-3.5, 1.5)
            } else {
                min + (max - min) * rng.vec(0.0, 1.0)
            };
            let dir = (target - origin).normalize_or(Vec3::Y);
            let t_max = if i % 3 == 0 {
                1e30
            } else {
                rng.range(0.0, 6.0)
            };
            (m, origin, dir, t_max, rng.range(-1.0, 1.0))
        })
        .collect()
}

/// The module `scene::medium` as the techniques import it, or (`mutate`) a copy whose clip
/// ignores the ray's end.
fn medium_module(mutate: bool) -> gpu::wgsl::Module {
    if mutate {
        MEDIUM.with_source(MEDIUM_WGSL.replace("min(t.y, t_max)", "t.y"))
    } else {
        MEDIUM.clone()
    }
}

fn kernel() -> String {
    format!(
        "#import scene::medium::{{Medium, henyey_greenstein, medium_clip, medium_transmittance}}\n\
         struct Case {{ medium: Medium, origin: vec4f, dir: vec4f }};\n\
         {header}\n{entry}",
        header = gpu::compute::kernel_header("Case", "vec4f"),
        entry = gpu::compute::kernel_entry(
            "main",
            "    let c = inputs[i];\n    \
             let t = medium_transmittance(c.medium, c.origin.xyz, c.dir.xyz, c.origin.w);\n    \
             let span = medium_clip(c.medium, c.origin.xyz, c.dir.xyz, c.origin.w);\n    \
             outputs[2u * i] = vec4f(t, max(span.y - span.x, 0.0));\n    \
             outputs[2u * i + 1u] = vec4f(henyey_greenstein(c.dir.w, c.medium.max.w), 0.0, 0.0, 0.0);",
        ),
    )
}

/// Cases whose GPU result differs from the twin's beyond the tolerance.
fn mismatches(mutate: bool) -> usize {
    let cases = cases();
    let inputs: Vec<Case> = cases
        .iter()
        .map(|(m, o, d, t_max, cos)| Case {
            medium: Medium::gpu(Some(m)),
            origin: o.extend(*t_max).to_array(),
            dir: d.extend(*cos).to_array(),
        })
        .collect();
    let (source, medium) = (kernel(), medium_module(mutate));
    let imports = [&medium];
    let kernel = gpu::wgsl::Shader::new("medium", &source).importing(&imports);
    let out: Vec<Vec4> =
        gpu::compute::run_kernel(testkit::context(), kernel, "main", &inputs, 2).unwrap();
    let mut bad = 0;
    for (k, (m, o, d, t_max, cos)) in cases.iter().enumerate() {
        let (gpu_t, gpu_hg) = (out[2 * k], out[2 * k + 1].x);
        let len = m.length_inside(*o, *d, *t_max);
        let t = m.transmittance(*o, *d, *t_max);
        let hg = henyey_greenstein(*cos, m.anisotropy);
        let close = |a: f32, b: f32| (a - b).abs() <= 1e-4 + 1e-4 * b.abs();
        if !(close(gpu_t.w, len)
            && close(gpu_t.x, t.x)
            && close(gpu_t.y, t.y)
            && close(gpu_t.z, t.z)
            && close(gpu_hg, hg))
        {
            bad += 1;
        }
    }
    bad
}

#[test]
fn the_wgsl_medium_matches_its_twin() {
    let _lock = testkit::gpu_lock();
    assert_eq!(mismatches(false), 0);
}

#[test]
fn a_mutated_clip_is_detected() {
    let _lock = testkit::gpu_lock();
    let bad = mismatches(true);
    assert!(
        bad > 400,
        "a clip that ignores surfaces differs in only {bad} cases"
    );
}
