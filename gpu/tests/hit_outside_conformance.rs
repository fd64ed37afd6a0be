//! GPU conformance of the search from outside (`hit_from_outside` in `shaders/hit.wgsl`)
//! against its Rust twin (`gpu::distance_map::hit_from_outside`), on the refractor distance map
//! of an ellipsoid (64 x 64 faces, distances at texel centres, `Rgba32Float`) read through a
//! nearest sampler on the GPU and the nearest-texel `CubeDistanceMap` on the CPU, so both see
//! the same numbers.
//!
//! 4096 rays from outside: aimed inside the ellipsoid, beside it, and at its bounding box's
//! corners, both methods, 0/4/8/16 iterations. Tolerances: hit or no hit must agree, and `d`
//! and the point within `1e-4 (1 + d)`, except where the twin itself is within rounding of a
//! decision: a lookup within 2e-3 texels of a texel edge (the GPU may pick the neighbour) or a
//! surface gap within 1e-4 of the epsilon. At most 2% of the rays may be excused.
//! `a_loosened_epsilon_test_is_caught` runs a copy of the WGSL whose epsilon test is twice as
//! loose and checks that the comparison reports it.

use glam::Vec3;
use gpu::compute::{kernel_entry, kernel_header, run_kernel_with};
use gpu::distance_map::{CubeDistanceMap, DistanceMap, HIT, HIT_WGSL, Method, hit_from_outside};
use gpu::wgpu;
use std::sync::OnceLock;
use wgpu::util::DeviceExt;

const SIZE: u32 = 64;
const RAYS: u32 = 4096;
const EPSILON: f32 = 2e-2;
const AXES: Vec3 = Vec3::new(0.6, 1.1, 0.35);

fn ctx() -> &'static gpu::Context {
    static CTX: OnceLock<gpu::Context> = OnceLock::new();
    CTX.get_or_init(|| gpu::Context::new().expect("a GPU adapter (lavapipe is enough)"))
}

/// The ellipsoid's distance from its centre at each texel centre, face after face (alpha).
fn faces() -> Vec<Vec<[f32; 4]>> {
    (0..6)
        .map(|face| {
            let mut texels = Vec::new();
            for j in 0..SIZE {
                for i in 0..SIZE {
                    let (u, v) = (
                        (i as f32 + 0.5) / SIZE as f32,
                        (j as f32 + 0.5) / SIZE as f32,
                    );
                    let d = gpu::prelude::cube_face_uv_to_dir(face, u, v).normalize();
                    texels.push([0.0, 0.0, 0.0, 1.0 / (d / AXES).length()]);
                }
            }
            texels
        })
        .collect()
}

/// Rays (origin, direction) from outside the box: a third aimed inside, a third beside, a
/// third at the box's corners.
fn rays() -> Vec<(Vec3, Vec3)> {
    let h = |k: u32| gpu::prelude::hash_to_unit(k) * 2.0 - 1.0;
    (0..RAYS)
        .map(|i| {
            let k = 8 * i;
            let from = Vec3::new(h(k), h(k + 1), h(k + 2)).normalize_or(Vec3::X);
            let aim = Vec3::new(h(k + 3), h(k + 4), h(k + 5));
            let target = match i % 3 {
                0 => aim * 0.8 * AXES,
                1 => aim.normalize_or(Vec3::Y) * 1.1 * AXES,
                _ => aim.signum() * AXES,
            };
            let y = target + from * 4.0;
            (y, (target - y).normalize())
        })
        .collect()
}

/// The kernel: one ray per input (origin, direction), the map and the run's settings bound
/// after the buffers; one `vec4f` out (point, d), (0, 0, 0, -1) for no hit.
fn kernel(layered: bool) -> String {
    let (map_type, module, call, layer) = if layered {
        (
            "texture_cube_array<f32>",
            "gpu::layered_distance_map",
            "hit_from_outside_layered",
            " 1,",
        )
    } else {
        (
            "texture_cube<f32>",
            "gpu::distance_map",
            "hit_from_outside",
            "",
        )
    };
    format!(
        "#import {module}::{call}\n{}{}\n{}",
        kernel_header("array<vec4f, 2>", "vec4f"),
        format!(
            r#"
@group(0) @binding(2) var dist_map: {map_type};
@group(0) @binding(3) var dist_sampler: sampler;
struct Run {{ method: u32, iterations: u32, epsilon: f32, _a: u32, half_axes: vec4f }};
@group(0) @binding(4) var<uniform> run: Run;
"#
        ),
        kernel_entry(
            "main",
            &format!(
                "    outputs[i] = {call}(inputs[i][0].xyz, inputs[i][1].xyz, dist_map,{layer} \
                 dist_sampler, 3u, -run.half_axes.xyz, run.half_axes.xyz, run.method, \
                 run.iterations, run.epsilon);"
            )
        )
    )
}

/// Runs the search on the GPU, with `hit` as the module `gpu::distance_map`. `layered`: the map is the
/// second cube of a two-cube array (the first a decoy sphere of radius 0.2) searched with the
/// `_layered` functions of `gpu::layered_distance_map` instead.
fn run_gpu(
    hit: &gpu::wgsl::Module,
    faces: &[Vec<[f32; 4]>],
    rays: &[(Vec3, Vec3)],
    method: Method,
    iterations: u32,
    layered: bool,
) -> Vec<[f32; 4]> {
    let ctx = ctx();
    let decoy = (SIZE * SIZE * 6) as usize;
    let data: Vec<[f32; 4]> =
        std::iter::repeat_n([0.0, 0.0, 0.0, 0.2], if layered { decoy } else { 0 })
            .chain(faces.iter().flatten().copied())
            .collect();
    let texture = ctx.device.create_texture_with_data(
        &ctx.queue,
        &wgpu::TextureDescriptor {
            label: Some("ellipsoid refractor map"),
            size: wgpu::Extent3d {
                width: SIZE,
                height: SIZE,
                depth_or_array_layers: if layered { 12 } else { 6 },
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba32Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        bytemuck::cast_slice(&data),
    );
    let dimension = if layered {
        wgpu::TextureViewDimension::CubeArray
    } else {
        wgpu::TextureViewDimension::Cube
    };
    let view = texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(dimension),
        ..Default::default()
    });
    let sampler = ctx.device.create_sampler(&Default::default());
    let settings: [u32; 8] = [
        method.wgsl_id(),
        iterations,
        EPSILON.to_bits(),
        0,
        AXES.x.to_bits(),
        AXES.y.to_bits(),
        AXES.z.to_bits(),
        0,
    ];
    let uniform = ctx
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("run"),
            contents: bytemuck::cast_slice(&settings),
            usage: wgpu::BufferUsages::UNIFORM,
        });
    let inputs: Vec<[[f32; 4]; 2]> = rays
        .iter()
        .map(|(y, r)| [y.extend(0.0).to_array(), r.extend(0.0).to_array()])
        .collect();
    let source = kernel(layered);
    run_kernel_with(
        ctx,
        gpu::wgsl::Shader::new("search from outside", &source).importing(&[hit]),
        "main",
        &inputs,
        1,
        &[
            (gpu::bind::texture(dimension, false), gpu::bind::view(&view)),
            (
                gpu::bind::sampler_non_filtering(),
                gpu::bind::sampler_resource(&sampler),
            ),
            (gpu::bind::uniform(), uniform.as_entire_binding()),
        ],
    )
    .unwrap_or_else(|e| panic!("search-from-outside kernel: {e}"))
}

/// Whether the twin's run on this ray touches a decision within rounding: a lookup near a
/// texel edge, or the surface gap (what the epsilon test compares) within 1e-4 of the epsilon.
fn ill_conditioned(
    map: &CubeDistanceMap,
    y: Vec3,
    r: Vec3,
    method: Method,
    iterations: u32,
) -> bool {
    let near_edge = std::cell::Cell::new(false);
    let probe = |dir: Vec3| {
        let fuv = gpu::prelude::cube_dir_to_face_uv(dir);
        let (u, v) = (fuv.y * SIZE as f32, fuv.z * SIZE as f32);
        let edge = |x: f32| (x - x.round()).abs() < 2e-3;
        if edge(u) || edge(v) {
            near_edge.set(true);
        }
        map.distance(dir)
    };
    // The twin's steps, to read the gap it compares with the epsilon.
    let t = gpu::prelude::ray_box(y, r, -AXES, AXES);
    let gap_near_epsilon = t.x <= t.y && t.y > 0.0 && {
        let h = gpu::distance_map::hit(&probe, y + r * t.y, -r, method, iterations);
        let surface = h.l.normalize_or_zero() * probe(h.l);
        ((surface - h.l).length() - EPSILON).abs() < 1e-4
    };
    near_edge.get() || gap_near_epsilon
}

/// Rays on which the GPU run disagrees with the twin: (all, excused as ill-conditioned).
fn disagreements(
    gpu: &[[f32; 4]],
    map: &CubeDistanceMap,
    rays: &[(Vec3, Vec3)],
    method: Method,
    iterations: u32,
) -> (Vec<usize>, usize) {
    let mut all = Vec::new();
    let mut excused = 0;
    for (k, ((y, r), g)) in rays.iter().zip(gpu).enumerate() {
        let cpu = hit_from_outside(map, *y, *r, -AXES, AXES, method, iterations, EPSILON);
        let agree = match cpu {
            None => g[3] == -1.0,
            Some(h) => {
                let tol = 1e-4 * (1.0 + h.d);
                (g[3] - h.d).abs() <= tol && (Vec3::new(g[0], g[1], g[2]) - h.point).length() <= tol
            }
        };
        if !agree {
            all.push(k);
            if ill_conditioned(map, *y, *r, method, iterations) {
                excused += 1;
            }
        }
    }
    (all, excused)
}

#[test]
fn wgsl_search_from_outside_matches_the_twin() {
    let faces = faces();
    let map = CubeDistanceMap::from_rgba_faces(SIZE, &faces, 3);
    let rays = rays();
    for method in [Method::FalsePosition, Method::Secant] {
        for iterations in [0, 4, 8, 16] {
            let gpu = run_gpu(&HIT, &faces, &rays, method, iterations, false);
            let hits = gpu.iter().filter(|g| g[3] >= 0.0).count();
            let (differ, excused) = disagreements(&gpu, &map, &rays, method, iterations);
            println!(
                "{method:?} {iterations}: {hits} hits of {RAYS}, {} differ, {excused} excused",
                differ.len()
            );
            assert_eq!(
                differ.len(),
                excused,
                "{method:?} {iterations}: rays {:?} differ beyond rounding",
                &differ[..differ.len().min(8)]
            );
            assert!(excused * 50 <= rays.len(), "{excused} excused");
            if iterations >= 4 {
                assert!(hits > RAYS as usize / 4, "the rays must hit: {hits}");
            }
        }
    }
}

/// The comparison can fail: a copy of the WGSL accepting gaps up to twice the epsilon differs
/// from the twin on more rays than may be excused.
#[test]
fn a_loosened_epsilon_test_is_caught() {
    let original = "if (length(surface - h.xyz) > epsilon) { return HIT_NONE; }";
    assert_eq!(
        HIT_WGSL.matches(original).count(),
        1,
        "the mutated line must exist once"
    );
    let loosened = HIT_WGSL.replace(
        original,
        "if (length(surface - h.xyz) > 2.0 * epsilon) { return HIT_NONE; }",
    );
    let faces = faces();
    let map = CubeDistanceMap::from_rgba_faces(SIZE, &faces, 3);
    let rays = rays();
    let gpu = run_gpu(
        &HIT.with_source(loosened),
        &faces,
        &rays,
        Method::FalsePosition,
        8,
        false,
    );
    let (differ, excused) = disagreements(&gpu, &map, &rays, Method::FalsePosition, 8);
    println!(
        "loosened epsilon: {} differ, {excused} excused",
        differ.len()
    );
    assert!(
        differ.len() > excused && differ.len() * 50 > rays.len(),
        "the loosened WGSL went unnoticed: {} differ, {excused} excused",
        differ.len()
    );
}

/// The cube-array functions of `gpu::layered_distance_map` (a map on the second cube of an array, a
/// decoy on the first) return exactly the bits of the cube functions on the same map.
#[test]
fn the_layered_search_returns_the_same_bits() {
    let faces = faces();
    let rays = rays();
    for iterations in [0, 4] {
        let cube = run_gpu(
            &HIT,
            &faces,
            &rays,
            Method::FalsePosition,
            iterations,
            false,
        );
        let layered = run_gpu(&HIT, &faces, &rays, Method::FalsePosition, iterations, true);
        let hits = cube.iter().filter(|g| g[3] >= 0.0).count();
        assert!(hits > 0);
        for (i, (a, b)) in cube.iter().zip(&layered).enumerate() {
            assert_eq!(
                a.map(f32::to_bits),
                b.map(f32::to_bits),
                "ray {i}: cube {a:?}, layered {b:?}"
            );
        }
    }
}
