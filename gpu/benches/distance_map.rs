//! CPU throughput of the Rust twins: `distance_map::hit` per method and iteration count on a
//! fixed set of rays in a [`BoxRoom`] (the exact box map), and a few `prelude` functions on
//! the same rays. Rays per second; `cargo bench -p rtapprox-gpu`.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use glam::Vec3;
use gpu::distance_map::{BoxRoom, Method, hit};
use gpu::prelude::{
    box_project, cube_dir_to_face_uv, fresnel_dielectric, hash_to_unit, oct_decode, oct_encode,
    ray_box, ray_sphere, refract_dir,
};
use std::hint::black_box;

/// Rays per batch.
const RAYS: usize = 4096;

fn room() -> BoxRoom {
    BoxRoom {
        min: Vec3::new(-2.0, 0.0, -3.0),
        max: Vec3::new(2.0, 2.5, 3.0),
        reference: Vec3::new(0.2, 1.1, -0.4),
    }
}

/// Deterministic rays `(x, R)`: origins within 0.5 m of the reference point (the surface of a
/// reflector around it, relative to it), unit directions spread over the sphere.
fn rays() -> Vec<(Vec3, Vec3)> {
    let u = |i: usize, k: u32| hash_to_unit(i as u32 * 8 + k);
    (0..RAYS)
        .map(|i| {
            let x = Vec3::new(u(i, 0), u(i, 1), u(i, 2)) - 0.5;
            let z = 2.0 * u(i, 3) - 1.0;
            let phi = std::f32::consts::TAU * u(i, 4);
            let s = (1.0 - z * z).max(0.0).sqrt();
            (x, Vec3::new(s * phi.cos(), s * phi.sin(), z))
        })
        .collect()
}

fn bench_hit(c: &mut Criterion) {
    let room = room();
    let rays = rays();
    let mut group = c.benchmark_group("hit");
    group.throughput(Throughput::Elements(RAYS as u64));
    for (name, method) in [
        ("secant", Method::Secant),
        ("false-position", Method::FalsePosition),
    ] {
        for iterations in [0u32, 1, 2, 4, 8] {
            group.bench_function(BenchmarkId::new(name, iterations), |b| {
                b.iter(|| {
                    let mut sum = 0.0;
                    for &(x, r) in &rays {
                        sum += hit(&room, black_box(x), r, method, iterations).d;
                    }
                    sum
                })
            });
        }
    }
    group.finish();
}

fn bench_prelude(c: &mut Criterion) {
    let rays = rays();
    let mut group = c.benchmark_group("prelude");
    group.throughput(Throughput::Elements(RAYS as u64));
    let each = |f: fn(Vec3, Vec3) -> f32| {
        let rays = &rays;
        move || rays.iter().map(|&(x, r)| f(black_box(x), r)).sum::<f32>()
    };
    group.bench_function("ray_sphere", |b| {
        b.iter(each(|x, r| ray_sphere(x, r, Vec3::Y, 0.8).x))
    });
    group.bench_function("ray_box", |b| {
        b.iter(each(|x, r| ray_box(x, r, Vec3::splat(-1.0), Vec3::ONE).y))
    });
    // The engine's parallax-corrected lookup: the same rays against the room box, probe at
    // its centre (compare with `hit/*`: what Hit() replaces it with).
    group.bench_function("box_project", |b| {
        b.iter(each(|x, r| {
            box_project(
                x,
                r,
                Vec3::new(0.0, 1.0, 0.0),
                Vec3::new(-1.0, 0.0, -1.0),
                Vec3::new(1.0, 2.0, 1.0),
            )
            .x
        }))
    });
    group.bench_function("cube_dir_to_face_uv", |b| {
        b.iter(each(|_, r| cube_dir_to_face_uv(r).y))
    });
    group.bench_function("oct_round_trip", |b| {
        b.iter(each(|_, r| oct_decode(oct_encode(r)).x))
    });
    group.bench_function("refract_fresnel", |b| {
        b.iter(each(|x, r| {
            let n = x.normalize_or(Vec3::Y);
            refract_dir(r, n, 1.0 / 1.5).x + fresnel_dielectric(-n.dot(r), 1.5)
        }))
    });
    group.finish();
}

criterion_group!(benches, bench_hit, bench_prelude);
criterion_main!(benches);
