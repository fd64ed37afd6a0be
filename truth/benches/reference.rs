//! Throughput of the CPU reference renderer on `cornell-sphere` (default camera, time 0):
//! the eye pass alone at 64 x 64 (`reference::render` without photons; camera rays per
//! second, `ReferenceStats::camera_rays` of the image) and the light pass alone
//! (`reference::light_trace` with the caustic setup and a small photon count; photons per
//! second). Both include building the scene's BVH, as every call of them does.
//! `cargo bench -p rtapprox-truth --bench reference`.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use truth::reference::{self, PHOTON_CHUNK, PhotonSetup, ReferenceOptions};

const SPEC: &str = "cornell-sphere";
const SIZE: u32 = 64;
/// Photons of the light-pass bench: four deterministic work units.
const PHOTONS: u64 = 4 * PHOTON_CHUNK;

fn bench_reference(c: &mut Criterion) {
    let scene = scene::load(SPEC).unwrap_or_else(|e| panic!("scene {SPEC}: {e}"));
    let camera = scene.camera;
    let mut group = c.benchmark_group("reference");

    let eye = ReferenceOptions {
        photons: 0,
        ..Default::default()
    };
    // The eye pass is deterministic: every render casts the same camera rays.
    let stats = reference::render(&scene, &camera, 0.0, SIZE, SIZE, &eye).stats;
    group.throughput(Throughput::Elements(stats.camera_rays));
    group.bench_function(
        BenchmarkId::new("eye-pass", format!("{SPEC}-{SIZE}x{SIZE}")),
        |b| b.iter(|| reference::render(&scene, &camera, 0.0, SIZE, SIZE, &eye).stats),
    );

    let light = ReferenceOptions {
        photons: PHOTONS,
        ..Default::default()
    };
    let setup = PhotonSetup::caustics(&scene);
    group.throughput(Throughput::Elements(PHOTONS));
    group.bench_function(
        BenchmarkId::new("light-pass", format!("{SPEC}-{PHOTONS}-photons")),
        |b| {
            b.iter(|| {
                reference::light_trace(&scene, &camera, 0.0, SIZE, SIZE, &light, &setup)
                    .photons_stored
            })
        },
    );
    group.finish();
}

criterion_group!(benches, bench_reference);
criterion_main!(benches);
