//! GPU conformance of `Hit()`: the WGSL function (`src/shaders/hit.wgsl`) run in a compute
//! shader against its Rust twin (`impostors::hit`) on the same rays over the same distance
//! cube map.
//!
//! The map is real: cornell-sphere's environment rendered from the sphere's centre by
//! `scene::techniques::render_environment` into an `Rgba32Float` cube (64 texels a face),
//! read back face by face with `gpu::read_texture_f32x4`. Both sides look it up *nearest
//! texel*: the GPU through a `Nearest` sampler, the twin through `CubeDistanceMap`
//! (the prelude's `cube_dir_to_face_uv`, `floor(u * size)`).
//!
//! Tolerance: a ray agrees when `|d_gpu - d_cpu| <= 1e-4 (1 + d_cpu)`. A ray is *ambiguous*
//! when one of the twin's lookups falls within 2e-3 texel of a texel edge, or within 1e-5
//! (relative) of a cube-face edge: the hardware may round that lookup to the neighbouring
//! texel, after which the iterations legitimately part. Every unambiguous ray must agree,
//! and ambiguous rays must stay below 2% of the rays. `comparison_detects_a_wrong_count`
//! shows the comparison can fail: the GPU run with one more iteration disagrees on many rays.

mod common;

use std::cell::Cell;

use glam::Vec3;
use gpu::cube::CubeTarget;
use gpu::wgpu::{self, util::DeviceExt};
use impostors::hit::{CubeDistanceMap, DistanceMap, Method, hit};
use scene::GpuScene;

const SIZE: u32 = 64;
const RAYS: usize = 4096;
const TEXEL_BAND: f32 = 2e-3;
const FACE_BAND: f32 = 1e-5;

const KERNEL: &str = r#"
@group(0) @binding(0) var<storage, read> rays: array<vec4f>;
@group(0) @binding(1) var<storage, read_write> results: array<vec4f>;
@group(0) @binding(2) var dist_map: texture_cube<f32>;
@group(0) @binding(3) var dist_sampler: sampler;

struct Run { method: u32, iterations: u32, _a: u32, _b: u32 };
@group(0) @binding(4) var<uniform> run: Run;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) g: vec3u) {
    let i = g.x;
    if (i >= arrayLength(&results)) { return; }
    let x = rays[2u * i].xyz;
    let r = rays[2u * i + 1u].xyz;
    results[i] = hit(x, r, dist_map, dist_sampler, 3u, run.method, run.iterations);
}
"#;

/// Records how close each lookup comes to a texel or face edge.
struct Watched<'a> {
    map: &'a CubeDistanceMap,
    closest: Cell<f32>,
    face_tie: Cell<bool>,
}

impl DistanceMap for Watched<'_> {
    fn distance(&self, dir: Vec3) -> f32 {
        let fuv = gpu::prelude::cube_dir_to_face_uv(dir);
        let s = self.map.size as f32;
        for c in [fuv.y * s, fuv.z * s] {
            let edge = (c - c.round()).abs();
            self.closest.set(self.closest.get().min(edge));
        }
        let mut a = dir.abs().to_array();
        a.sort_by(f32::total_cmp);
        if a[2] - a[1] <= FACE_BAND * a[2] {
            self.face_tie.set(true);
        }
        self.map.distance(dir)
    }
}

struct Fixture {
    map: CubeDistanceMap,
    cube: CubeTarget,
    rays: Vec<(Vec3, Vec3)>,
}

fn fixture() -> Fixture {
    let ctx = common::ctx();
    let scene = scene::load("cornell-sphere:material=mirror").unwrap();
    let sphere = scene
        .objects
        .iter()
        .position(|o| o.name == "sphere")
        .unwrap();
    let radius = scene.objects[sphere].bounding_radius_at(0.0);
    let mut gpu_scene = GpuScene::new(ctx, &scene).unwrap();
    let cube = CubeTarget::new(ctx, SIZE, gpu::HDR_FORMAT, "conformance impostor").unwrap();
    common::submit(ctx, &mut gpu_scene, 0.0, |frame, s| {
        scene::techniques::render_environment(frame, s, &cube, sphere);
    });
    let faces: Vec<Vec<[f32; 4]>> = (0..6)
        .map(|f| gpu::read_texture_f32x4(ctx, &cube.color, f).unwrap())
        .collect();
    let map = CubeDistanceMap::from_rgba_faces(SIZE, &faces, 3);

    // Rays leaving the sphere's surface (reflection-like) plus some entering it (refraction-
    // like, reaching the far side of the room through the centre region), deterministic.
    let h = |k: u32| gpu::prelude::hash_to_unit(k) * 2.0 - 1.0;
    let mut rays = Vec::new();
    let mut k = 0u32;
    while rays.len() < RAYS {
        let base = k;
        k += 1;
        let n = Vec3::new(h(6 * base), h(6 * base + 1), h(6 * base + 2));
        let r = Vec3::new(h(6 * base + 3), h(6 * base + 4), h(6 * base + 5));
        if !(0.1..=1.0).contains(&n.length()) || !(0.1..=1.0).contains(&r.length()) {
            continue;
        }
        let (n, mut r) = (n.normalize(), r.normalize());
        if r.dot(n) < 0.0 && rays.len() % 4 != 0 {
            r = -r;
        }
        rays.push((n * radius, r));
    }
    Fixture { map, cube, rays }
}

fn run_gpu(f: &Fixture, method: Method, iterations: u32) -> Vec<[f32; 4]> {
    let ctx = common::ctx();
    let device = &ctx.device;
    let source = format!("{}\n{}", impostors::HIT_WGSL, KERNEL);
    let module = gpu::shader_with_prelude(ctx, "hit conformance", &source);
    let ray_data: Vec<[f32; 4]> = f
        .rays
        .iter()
        .flat_map(|(x, r)| [x.extend(0.0).to_array(), r.extend(0.0).to_array()])
        .collect();
    let rays = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("rays"),
        contents: bytemuck::cast_slice(&ray_data),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let results = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("results"),
        size: (f.rays.len() * 16) as u64,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let run = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("run"),
        contents: bytemuck::cast_slice(&[method.wgsl_id(), iterations, 0, 0]),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("nearest"),
        mag_filter: wgpu::FilterMode::Nearest,
        min_filter: wgpu::FilterMode::Nearest,
        ..Default::default()
    });
    let entry = |binding, ty| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty,
        count: None,
    };
    let storage = |read_only| wgpu::BindingType::Buffer {
        ty: wgpu::BufferBindingType::Storage { read_only },
        has_dynamic_offset: false,
        min_binding_size: None,
    };
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("hit conformance"),
        entries: &[
            entry(0, storage(true)),
            entry(1, storage(false)),
            entry(
                2,
                wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: false },
                    view_dimension: wgpu::TextureViewDimension::Cube,
                    multisampled: false,
                },
            ),
            entry(
                3,
                wgpu::BindingType::Sampler(wgpu::SamplerBindingType::NonFiltering),
            ),
            entry(
                4,
                wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
            ),
        ],
    });
    let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("hit conformance"),
        layout: &layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: rays.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: results.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: wgpu::BindingResource::TextureView(&f.cube.cube_view),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: wgpu::BindingResource::Sampler(&sampler),
            },
            wgpu::BindGroupEntry {
                binding: 4,
                resource: run.as_entire_binding(),
            },
        ],
    });
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("hit conformance"),
        bind_group_layouts: &[Some(&layout)],
        immediate_size: 0,
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("hit conformance"),
        layout: Some(&pipeline_layout),
        module: &module,
        entry_point: Some("main"),
        compilation_options: Default::default(),
        cache: None,
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.dispatch_workgroups((f.rays.len() as u32).div_ceil(64), 1, 1);
    }
    ctx.queue.submit([encoder.finish()]);
    let bytes = gpu::read_buffer(ctx, &results).unwrap();
    bytemuck::pod_collect_to_vec(&bytes)
}

struct Outcome {
    agree: usize,
    ambiguous: usize,
    unexplained: Vec<String>,
}

fn compare(f: &Fixture, gpu: &[[f32; 4]], method: Method, iterations: u32) -> Outcome {
    let mut out = Outcome {
        agree: 0,
        ambiguous: 0,
        unexplained: Vec::new(),
    };
    for (i, &(x, r)) in f.rays.iter().enumerate() {
        let watched = Watched {
            map: &f.map,
            closest: Cell::new(1.0),
            face_tie: Cell::new(false),
        };
        let cpu = hit(&watched, x, r, method, iterations);
        let g = gpu[i];
        assert!(
            g.iter().all(|c| c.is_finite()),
            "non-finite GPU result {g:?} for ray {i}"
        );
        if (g[3] - cpu.d).abs() <= 1e-4 * (1.0 + cpu.d) {
            out.agree += 1;
        } else if watched.closest.get() < TEXEL_BAND || watched.face_tie.get() {
            out.ambiguous += 1;
        } else if out.unexplained.len() < 5 {
            out.unexplained.push(format!(
                "ray {i}: x {x} R {r}: gpu d {} cpu d {} (closest texel edge {})",
                g[3],
                cpu.d,
                watched.closest.get()
            ));
        } else {
            out.unexplained.push(String::new());
        }
    }
    out
}

#[test]
fn wgsl_hit_matches_the_rust_twin() {
    let _g = common::gpu_lock();
    let f = fixture();
    for method in [Method::Secant, Method::FalsePosition] {
        for iterations in [0u32, 1, 2, 4, 8] {
            let gpu = run_gpu(&f, method, iterations);
            let o = compare(&f, &gpu, method, iterations);
            println!(
                "{method:?} {iterations}: {} agree, {} ambiguous (texel-edge lookups), {} unexplained",
                o.agree,
                o.ambiguous,
                o.unexplained.len()
            );
            assert!(
                o.unexplained.is_empty(),
                "{method:?} {iterations}: {:#?}",
                o.unexplained
            );
            assert!(
                o.ambiguous * 50 <= f.rays.len(),
                "{method:?} {iterations}: {} ambiguous rays",
                o.ambiguous
            );
        }
    }
}

#[test]
fn comparison_detects_a_wrong_count() {
    let _g = common::gpu_lock();
    let f = fixture();
    let gpu = run_gpu(&f, Method::FalsePosition, 2);
    let o = compare(&f, &gpu, Method::FalsePosition, 1);
    let wrong = o.unexplained.len() + o.ambiguous;
    assert!(
        wrong * 10 > f.rays.len(),
        "only {wrong} rays differ between 1 and 2 iterations"
    );
}
