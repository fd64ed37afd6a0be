//! GPU conformance of `Hit()`: the WGSL function (`gpu/src/shaders/hit.wgsl`) run in a compute
//! shader against its Rust twin (`gpu::distance_map`) on the same rays over the same distance
//! cube map.
//!
//! The map is real: cornell-sphere's environment rendered from the sphere's centre by
//! `scene::foundation::render_environment` into an `Rgba32Float` cube (64 texels a face),
//! read back face by face with `gpu::read_texture_f32x4`.
//!
//! *Nearest* (`wgsl_hit_matches_the_rust_twin`): the GPU samples through a `Nearest`
//! sampler, the twin through `CubeDistanceMap` (the prelude's `cube_dir_to_face_uv`,
//! `floor(u * size)`). A ray agrees when `|d_gpu - d_cpu| <= 1e-4 (1 + d_cpu)`. A ray is
//! *ambiguous* when one of the twin's lookups falls within 2e-3 texel of a texel edge, or
//! within 1e-5 (relative) of a cube-face edge: the hardware may round that lookup to the
//! neighbouring texel, after which the iterations legitimately part. Every unambiguous ray
//! must agree, and ambiguous rays must stay below 2% of the rays.
//! `comparison_detects_a_wrong_count` shows the comparison can fail: the GPU run with one more
//! iteration disagrees on many rays.
//!
//! *Linear* (`wgsl_hit_matches_the_rust_twin_filtered`): the technique's sampler (`Linear`,
//! seamless cube) against `CubeDistanceMap::filtered` (bilinear on the prelude's face and
//! texel addressing, clamped to the face). Single lookups are compared first, to pin the
//! sampler's precision ([`LOOKUP_ULPS`]), then `Hit()` to [`LINEAR_TOLERANCE`]. A ray with a
//! lookup whose 2 x 2 footprint reaches past its face is excused when it disagrees (the GPU
//! blends the neighbouring face there, the twin does not), at most 1 in
//! [`MAX_EXCUSED_SHARE`]. `filtered_comparison_detects_mutants` shows both stages can fail:
//! a nearest twin, texel centres off by half a texel, 8-bit weights, one iteration too few.

mod common;

use std::cell::Cell;

use glam::Vec3;
use gpu::compute::{kernel_entry, kernel_header};
use gpu::cube::CubeTarget;
use gpu::distance_map::{CubeDistanceMap, DistanceMap, Method, hit};
use gpu::wgpu::{self, util::DeviceExt};
use scene::GpuScene;

const SIZE: u32 = 64;
const RAYS: usize = 4096;
const TEXEL_BAND: f32 = 2e-3;
const FACE_BAND: f32 = 1e-5;
/// Directions tried by the lookup stage of the filtered test (about half survive the
/// rejection sampling in [`directions`]).
const LOOKUPS: u32 = 40_000;
/// Bound on a single `Linear` lookup's disagreement with [`Twin::Bilinear`], in ulp of the
/// value. lavapipe filters `Rgba32Float` with f32 weights: measured 2.44 ulp over 20584
/// lookups (the rest is the order of the lerps). A sampler with 8-bit weights is off by
/// ~960 ulp on this map, so this bound tells the two apart.
const LOOKUP_ULPS: f32 = 8.0;
/// Tolerance of the filtered `Hit()` comparison, relative to `1 + d`. With lookups agreeing to
/// a few ulp, `d` agrees to a few ulp too: measured at most 4.6e-7 (~4 ulp, secant with 1
/// iteration). 1e-5 leaves a factor 20 for the secant steps to amplify lookup rounding
/// elsewhere, yet is tight enough to flag 8-bit filter weights ([`Twin::Bilinear8BitWeights`]
/// differs by more on 27-31% of the rays; at 1e-4 on 0-18 rays of 4096).
const LINEAR_TOLERANCE: f32 = 1e-5;
/// At most 1 in this many rays may be excused (a footprint past a face edge, which the twin
/// clamps and the GPU blends seamlessly). Measured: 3.0-4.0% of the rays have such a lookup;
/// 2.8% (116) are excused with 0 iterations, 1.2% (50) with 8.
const MAX_EXCUSED_SHARE: usize = 25;

/// The bindings past the two of `gpu::compute`'s kernel convention: the distance map, its
/// sampler and the run's method and iteration count.
const MAP_BINDINGS: &str = r#"
@group(0) @binding(2) var dist_map: texture_cube<f32>;
@group(0) @binding(3) var dist_sampler: sampler;

struct Run { method: u32, iterations: u32, _a: u32, _b: u32 };
@group(0) @binding(4) var<uniform> run: Run;
"#;

/// `Hit()` per ray (two `vec4f` in: the point `x` and the direction `R`; one `vec4f` out).
fn kernel() -> String {
    format!(
        "{}{MAP_BINDINGS}{}",
        kernel_header("array<vec4f, 2>", "vec4f"),
        kernel_entry(
            "main",
            "    outputs[i] = distance_map::hit(inputs[i][0].xyz, inputs[i][1].xyz, dist_map, dist_sampler, 3u, \
             run.method, run.iterations);"
        )
    )
}

/// One lookup per direction, with [`kernel`]'s bindings (`inputs` holds directions).
fn lookup_kernel() -> String {
    format!(
        "{}{MAP_BINDINGS}{}",
        kernel_header("vec4f", "vec4f"),
        kernel_entry(
            "main",
            "    outputs[i] = textureSampleLevel(dist_map, dist_sampler, inputs[i].xyz, 0.0);"
        )
    )
}

/// The GPU sampler's filter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Filter {
    Nearest,
    /// The technique's sampler.
    Linear,
}

/// How the twin looks the map up.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Twin {
    /// `CubeDistanceMap` (nearest texel): the match of a `Nearest` sampler.
    Nearest,
    /// `CubeDistanceMap::filtered`: the match of a `Linear` sampler.
    Bilinear,
    /// Mutants of `Bilinear`, to show the comparison notices them: weights rounded to 8
    /// fractional bits (what many GPUs do), and texel centres misplaced by half a texel
    /// (`x = u size` instead of `u size - 0.5`).
    Bilinear8BitWeights,
    BilinearNoHalfTexel,
}

impl Twin {
    fn lookup(self, map: &CubeDistanceMap, dir: Vec3) -> f32 {
        let variant = |bits: Option<i32>, offset: f32| {
            let fuv = gpu::prelude::cube_dir_to_face_uv(dir);
            let s = map.size as f32;
            let (x, y) = (fuv.y * s - offset, fuv.z * s - offset);
            let (x0, y0) = (x.floor(), y.floor());
            let q = |w: f32| bits.map_or(w, |b| (w * 2f32.powi(b)).round() / 2f32.powi(b));
            let (wu, wv) = (q(x - x0), q(y - y0));
            let t = |di: i32, dj: i32| {
                map.texel_clamped(fuv.x as usize, x0 as i32 + di, y0 as i32 + dj)
            };
            let top = t(0, 0) * (1.0 - wu) + t(1, 0) * wu;
            let bottom = t(0, 1) * (1.0 - wu) + t(1, 1) * wu;
            top * (1.0 - wv) + bottom * wv
        };
        match self {
            Twin::Nearest => map.distance(dir),
            Twin::Bilinear => map.filtered().distance(dir),
            Twin::Bilinear8BitWeights => variant(Some(8), 0.5),
            Twin::BilinearNoHalfTexel => variant(None, 0.0),
        }
    }
}

/// The twin's map, recording for each ray how close its lookups come to the places where the
/// GPU may legitimately read other texels: a texel edge or a face edge (nearest), a footprint
/// that reaches past its face, where the GPU blends the neighbouring face (bilinear).
struct Watched<'a> {
    map: &'a CubeDistanceMap,
    twin: Twin,
    closest: Cell<f32>,
    face_tie: Cell<bool>,
    border: Cell<bool>,
}

impl<'a> Watched<'a> {
    fn new(map: &'a CubeDistanceMap, twin: Twin) -> Self {
        Self {
            map,
            twin,
            closest: Cell::new(1.0),
            face_tie: Cell::new(false),
            border: Cell::new(false),
        }
    }

    /// Whether the GPU may have read other texels than the twin on this ray.
    fn excused(&self) -> bool {
        match self.twin {
            Twin::Nearest => self.closest.get() < TEXEL_BAND || self.face_tie.get(),
            _ => self.border.get(),
        }
    }
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
        if self.map.footprint(dir).crosses_face_edge(self.map.size) {
            self.border.set(true);
        }
        self.twin.lookup(self.map, dir)
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
        scene::foundation::render_environment(frame, s, &cube, sphere);
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

/// `Hit()` on every ray of the fixture, the map looked up through a `filter` sampler.
fn run_gpu(f: &Fixture, filter: Filter, method: Method, iterations: u32) -> Vec<[f32; 4]> {
    let ray_data: Vec<[f32; 4]> = f
        .rays
        .iter()
        .flat_map(|(x, r)| [x.extend(0.0).to_array(), r.extend(0.0).to_array()])
        .collect();
    let source = format!("#import gpu::distance_map\n{}", kernel());
    dispatch(
        f,
        &source,
        filter,
        &ray_data,
        f.rays.len(),
        [method.wgsl_id(), iterations, 0, 0],
    )
}

/// One `textureSampleLevel` of the map per direction, through a `filter` sampler.
fn sample_gpu(f: &Fixture, filter: Filter, dirs: &[Vec3]) -> Vec<[f32; 4]> {
    let data: Vec<[f32; 4]> = dirs.iter().map(|d| d.extend(0.0).to_array()).collect();
    dispatch(f, &lookup_kernel(), filter, &data, dirs.len(), [0; 4])
}

/// Runs `main` of `source` (the bindings of [`kernel`]) over `count` results.
fn dispatch(
    f: &Fixture,
    source: &str,
    filter: Filter,
    inputs: &[[f32; 4]],
    count: usize,
    params: [u32; 4],
) -> Vec<[f32; 4]> {
    let ctx = common::ctx();
    let device = &ctx.device;
    let module = gpu::shader(ctx, gpu::wgsl::Shader::new("hit conformance", source));
    let rays = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("rays"),
        contents: bytemuck::cast_slice(inputs),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let results = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("results"),
        size: (count * 16) as u64,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let run = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("run"),
        contents: bytemuck::cast_slice(&params),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    // The technique's sampler is `Linear` with every other field default (clamp to edge,
    // which a cube view ignores: cube sampling is seamless).
    let (mode, filterable, binding) = match filter {
        Filter::Nearest => (
            wgpu::FilterMode::Nearest,
            false,
            wgpu::SamplerBindingType::NonFiltering,
        ),
        Filter::Linear => (
            wgpu::FilterMode::Linear,
            true,
            wgpu::SamplerBindingType::Filtering,
        ),
    };
    let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("hit conformance"),
        mag_filter: mode,
        min_filter: mode,
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
                    sample_type: wgpu::TextureSampleType::Float { filterable },
                    view_dimension: wgpu::TextureViewDimension::Cube,
                    multisampled: false,
                },
            ),
            entry(3, wgpu::BindingType::Sampler(binding)),
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
        pass.dispatch_workgroups((count as u32).div_ceil(64), 1, 1);
    }
    ctx.queue.submit([encoder.finish()]);
    let bytes = gpu::read_buffer(ctx, &results).unwrap();
    bytemuck::pod_collect_to_vec(&bytes)
}

struct Outcome {
    agree: usize,
    /// Disagreeing rays with an excuse (see [`Watched::excused`]).
    excused: usize,
    unexplained: Vec<String>,
    /// Largest `|d_gpu - d_cpu| / (1 + d_cpu)` over the rays without an excuse, and over the
    /// rays with one (agreeing or not).
    max_rel: f32,
    max_rel_excusable: f32,
}

/// Compares the GPU's `d` with the twin's ray by ray: a ray agrees when
/// `|d_gpu - d_cpu| <= tolerance (1 + d_cpu)`.
fn compare(
    f: &Fixture,
    gpu: &[[f32; 4]],
    twin: Twin,
    method: Method,
    iterations: u32,
    tolerance: f32,
) -> Outcome {
    let mut out = Outcome {
        agree: 0,
        excused: 0,
        unexplained: Vec::new(),
        max_rel: 0.0,
        max_rel_excusable: 0.0,
    };
    for (i, &(x, r)) in f.rays.iter().enumerate() {
        let watched = Watched::new(&f.map, twin);
        let cpu = hit(&watched, x, r, method, iterations);
        let g = gpu[i];
        assert!(
            g.iter().all(|c| c.is_finite()),
            "non-finite GPU result {g:?} for ray {i}"
        );
        let rel = (g[3] - cpu.d).abs() / (1.0 + cpu.d);
        if watched.excused() {
            out.max_rel_excusable = out.max_rel_excusable.max(rel);
        } else {
            out.max_rel = out.max_rel.max(rel);
        }
        if rel <= tolerance {
            out.agree += 1;
        } else if watched.excused() {
            out.excused += 1;
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
            let gpu = run_gpu(&f, Filter::Nearest, method, iterations);
            let o = compare(&f, &gpu, Twin::Nearest, method, iterations, 1e-4);
            println!(
                "{method:?} {iterations}: {} agree, {} ambiguous (texel-edge lookups), {} unexplained",
                o.agree,
                o.excused,
                o.unexplained.len()
            );
            assert!(
                o.unexplained.is_empty(),
                "{method:?} {iterations}: {:#?}",
                o.unexplained
            );
            assert!(
                o.excused * 50 <= f.rays.len(),
                "{method:?} {iterations}: {} ambiguous rays",
                o.excused
            );
        }
    }
}

#[test]
fn comparison_detects_a_wrong_count() {
    let _g = common::gpu_lock();
    let f = fixture();
    let gpu = run_gpu(&f, Filter::Nearest, Method::FalsePosition, 2);
    let o = compare(&f, &gpu, Twin::Nearest, Method::FalsePosition, 1, 1e-4);
    let wrong = o.unexplained.len() + o.excused;
    assert!(
        wrong * 10 > f.rays.len(),
        "only {wrong} rays differ between 1 and 2 iterations"
    );
}

/// Directions spread over the sphere (deterministic; not the rays' hash sequence).
fn directions(n: u32) -> Vec<Vec3> {
    let h = |k: u32| gpu::prelude::hash_to_unit(k + 7_000_000) * 2.0 - 1.0;
    (0..n)
        .map(|k| Vec3::new(h(3 * k), h(3 * k + 1), h(3 * k + 2)))
        .filter(|d| (0.1..=1.0).contains(&d.length()))
        .collect()
}

/// Largest disagreement of single `Linear` lookups with `twin`, in units of the float spacing
/// at the twin's value (`f32::EPSILON |v|`), over `dirs` whose footprint stays on its face.
fn lookup_ulps(f: &Fixture, gpu: &[[f32; 4]], dirs: &[Vec3], twin: Twin) -> (usize, f32) {
    let mut n = 0;
    let mut worst = 0.0f32;
    for (g, &d) in gpu.iter().zip(dirs) {
        if f.map.footprint(d).crosses_face_edge(SIZE) {
            continue;
        }
        n += 1;
        let v = twin.lookup(&f.map, d);
        worst = worst.max((g[3] - v).abs() / (f32::EPSILON * v.abs().max(1e-3)));
    }
    (n, worst)
}

/// `Hit()` with the technique's `Linear` sampler against [`Twin::Bilinear`]: first single
/// lookups (which pin down the sampler's precision), then `Hit()` itself.
#[test]
fn wgsl_hit_matches_the_rust_twin_filtered() {
    let _g = common::gpu_lock();
    let f = fixture();
    let dirs = directions(LOOKUPS);
    let samples = sample_gpu(&f, Filter::Linear, &dirs);
    let (n, ulps) = lookup_ulps(&f, &samples, &dirs, Twin::Bilinear);
    println!("lookups: {n} away from face edges, max {ulps:.2} ulp from the bilinear twin");
    assert!(
        ulps <= LOOKUP_ULPS,
        "Linear lookups differ from the bilinear twin by up to {ulps} ulp (bound {LOOKUP_ULPS}): \
         this sampler does not filter at float precision (8-bit weights would differ by ~1e3 \
         ulp); the Hit tolerance below assumes it does"
    );
    for method in [Method::Secant, Method::FalsePosition] {
        for iterations in [0u32, 1, 2, 4, 8] {
            let gpu = run_gpu(&f, Filter::Linear, method, iterations);
            let o = compare(
                &f,
                &gpu,
                Twin::Bilinear,
                method,
                iterations,
                LINEAR_TOLERANCE,
            );
            println!(
                "{method:?} {iterations}: {} agree, {} excused, {} unexplained; max rel {:.2e} \
                 (rays whose footprints stay on their faces), {:.2e} (the other rays)",
                o.agree,
                o.excused,
                o.unexplained.len(),
                o.max_rel,
                o.max_rel_excusable,
            );
            assert!(
                o.unexplained.is_empty(),
                "{method:?} {iterations}: {:#?}",
                o.unexplained
            );
            assert!(
                o.excused * MAX_EXCUSED_SHARE <= f.rays.len(),
                "{method:?} {iterations}: {} excused rays",
                o.excused
            );
        }
    }
}

/// The filtered comparison can fail: mutants of the twin, or a wrong iteration count, are
/// caught at the lookup stage and at the `Hit()` stage.
#[test]
fn filtered_comparison_detects_mutants() {
    let _g = common::gpu_lock();
    let f = fixture();
    let dirs = directions(LOOKUPS);
    let samples = sample_gpu(&f, Filter::Linear, &dirs);
    for twin in [
        Twin::Nearest,
        Twin::Bilinear8BitWeights,
        Twin::BilinearNoHalfTexel,
    ] {
        let (_, ulps) = lookup_ulps(&f, &samples, &dirs, twin);
        println!("lookups vs {twin:?}: max {ulps:.0} ulp");
        assert!(ulps > 10.0 * LOOKUP_ULPS, "{twin:?}: only {ulps} ulp");
    }
    let (method, iterations) = (Method::FalsePosition, 2);
    let gpu = run_gpu(&f, Filter::Linear, method, iterations);
    let rays = f.rays.len();
    for (twin, twin_iterations, share) in [
        (Twin::Nearest, iterations, 2),
        (Twin::BilinearNoHalfTexel, iterations, 2),
        (Twin::Bilinear8BitWeights, iterations, 10),
        (Twin::Bilinear, iterations - 1, 20),
    ] {
        let o = compare(&f, &gpu, twin, method, twin_iterations, LINEAR_TOLERANCE);
        let wrong = o.unexplained.len();
        println!("Linear GPU {iterations} vs {twin:?} {twin_iterations}: {wrong} unexplained");
        assert!(
            wrong * share > rays,
            "{twin:?} with {twin_iterations} iterations: only {wrong} unexplained rays"
        );
    }
}
