//! CPU throughput of the Rust twin of the room ray cast (`rooms::cast_rooms`) on a fixed set
//! of rays entering a facade, for the regular room grid and for displaced walls, and of the
//! engine baseline's room-box exit (`rooms::cubemap_room`) on the same rays (rays per second;
//! `cargo bench -p rtapprox-interior-mapping --bench rooms`).

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use glam::Vec3;
use gpu::prelude::hash_to_unit;
use interior_mapping::rooms::{cast_rooms, cubemap_room, plane_uv};
use std::hint::black_box;

/// Rays per batch.
const RAYS: usize = 4096;

const ROOM_SIZE: Vec3 = Vec3::new(4.0, 3.0, 5.0);

/// Deterministic rays from points of the facade `z = 0` (which coincides with a wall plane)
/// into the building (`-z`), over a facade of 10 x 10 rooms.
fn rays() -> Vec<(Vec3, Vec3)> {
    let u = |i: usize, k: u32| hash_to_unit(i as u32 * 4 + k);
    (0..RAYS)
        .map(|i| {
            let origin = Vec3::new(40.0 * u(i, 0), 30.0 * u(i, 1), 0.0);
            let dir = Vec3::new(2.0 * u(i, 2) - 1.0, 2.0 * u(i, 3) - 1.0, -1.0).normalize();
            (origin, dir)
        })
        .collect()
}

fn bench_cast(c: &mut Criterion) {
    let rays = rays();
    let mut group = c.benchmark_group("cast_rooms");
    group.throughput(Throughput::Elements(RAYS as u64));
    for (name, displacement) in [("regular", Vec3::ZERO), ("displaced", Vec3::splat(0.3))] {
        group.bench_function(BenchmarkId::from_parameter(name), |b| {
            b.iter(|| {
                let mut sum = 0.0;
                for &(o, d) in &rays {
                    let hit = cast_rooms(black_box(o), d, ROOM_SIZE, displacement, 7);
                    // What the shader does next: the hit plane's texture coordinates.
                    sum += plane_uv(hit.family, hit.point / ROOM_SIZE).x + hit.room.x as f32;
                }
                sum
            })
        });
    }
    group.finish();
    let mut group = c.benchmark_group("cubemap_room");
    group.throughput(Throughput::Elements(RAYS as u64));
    for (name, variants) in [("one", 1), ("varied", 4)] {
        group.bench_function(BenchmarkId::from_parameter(name), |b| {
            b.iter(|| {
                let mut sum = 0.0;
                for &(o, d) in &rays {
                    let hit = cubemap_room(black_box(o), d, ROOM_SIZE, variants, 7);
                    // What the shader does next: the cube lookup direction.
                    sum += hit.lookup.x + hit.atlas as f32;
                }
                sum
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench_cast);
criterion_main!(benches);
