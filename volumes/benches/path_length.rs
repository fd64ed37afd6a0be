//! CPU throughput of the Rust twin of the ray-traced soft volume's path-length search
//! (`path_length::primitive_path_length`), per volume primitive, on a fixed set of eye rays
//! through one volume (rays per second; `cargo bench -p rtapprox-volumes --bench path_length`).

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use glam::{Vec2, Vec3};
use gpu::prelude::hash_to_unit;
use std::hint::black_box;
use volumes::path_length::{
    Primitive, billboard_coords, primitive_path_length, sample_thickness, thickness_texels,
};

/// Rays per batch.
const RAYS: usize = 4096;

const CENTER: Vec3 = Vec3::new(0.0, 1.0, 0.0);
const RADIUS: f32 = 1.0;
const EYE: Vec3 = Vec3::new(0.3, 1.4, 4.0);

/// Billboard axes facing the eye: right, up, normal (toward the eye).
fn basis() -> [Vec3; 3] {
    let normal = (EYE - CENTER).normalize();
    let right = Vec3::Y.cross(normal).normalize();
    [right, normal.cross(right), normal]
}

/// Deterministic eye rays aimed at a square 1.2 radii wide around the volume (about a fifth
/// miss the disc), with the scene depth in front of, inside or behind the volume, or absent.
fn rays() -> Vec<(Vec3, f32)> {
    let [right, up, _] = basis();
    let u = |i: usize, k: u32| hash_to_unit(i as u32 * 4 + k);
    (0..RAYS)
        .map(|i| {
            let (a, b) = (2.4 * u(i, 0) - 1.2, 2.4 * u(i, 1) - 1.2);
            let target = CENTER + RADIUS * (a * right + b * up);
            let t_scene = if i % 4 == 0 {
                f32::INFINITY
            } else {
                EYE.distance(CENTER) + 3.0 * (u(i, 2) - 0.5)
            };
            ((target - EYE).normalize(), t_scene)
        })
        .collect()
}

fn bench_primitives(c: &mut Criterion) {
    let rays = rays();
    let basis = basis();
    let texels = thickness_texels();
    let mut group = c.benchmark_group("path_length");
    group.throughput(Throughput::Elements(RAYS as u64));
    for (name, primitive) in [
        ("constant", Primitive::Constant),
        ("linear", Primitive::Linear),
        ("sphere", Primitive::Sphere),
        ("texture", Primitive::Texture),
    ] {
        group.bench_function(BenchmarkId::from_parameter(name), |b| {
            b.iter(|| {
                let mut sum = 0.0;
                for &(d, t_scene) in &rays {
                    let d = black_box(d);
                    // The texture primitive reads the thickness texture at the ray's billboard
                    // coordinates first (bilinear, as the GPU's sampler), as the shader does.
                    let texture_value = if primitive == Primitive::Texture {
                        let [right, up, normal] = basis;
                        let uv = billboard_coords(EYE, d, CENTER, right, up, normal, RADIUS);
                        sample_thickness(&texels, Vec2::new(uv.x, uv.y))
                    } else {
                        0.0
                    };
                    sum += primitive_path_length(
                        primitive,
                        EYE,
                        d,
                        CENTER,
                        RADIUS,
                        basis,
                        texture_value,
                        t_scene,
                    );
                }
                sum
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench_primitives);
criterion_main!(benches);
