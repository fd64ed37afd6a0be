//! GPU conformance: the BVH traversal (`raytracer::queries`' `trace_closest` and `trace_any` over
//! `raytracer::bvh`, `raytracer::triangles`' `surface_hit`, the modules the tracer imports) runs
//! in a compute kernel over the same flattened BVH as its Rust twin
//! (`raytracer::bvh::FlatBvh`) and must find the same triangle at the same distance, on camera
//! rays of built-in scenes, axis-parallel rays and rays aimed at triangle edges.

use glam::Vec3;
use gpu::compute::{kernel_entry, kernel_header, run_kernel_with};
use gpu::wgpu::{self, util::DeviceExt};
use raytracer::bvh::{FlatBvh, RayGpu, TraceResultGpu};

/// The kernel's imports; the nodes, triangles, attributes and cut-outs bound from binding 2
/// (after its inputs and outputs).
const IMPORTS: &str = r#"
#import raytracer::triangles::{NO_HIT, bvh_triangles, hit_barycentrics, surface_hit}
#import raytracer::queries::{trace_any, trace_closest}
"#;

const BODY: &str = r#"
    let r = inputs[i];
    let t_max = select(3.4028235e38, r.t_max, r.t_max >= 0.0);
    let h = trace_closest(r.origin, r.dir, t_max);
    var out: TraceResult;
    out.t = -1.0;
    out.object = -1;
    out.triangle = -1;
    out.any = select(0u, 1u, trace_any(r.origin, r.dir, t_max));
    if (h.triangle != NO_HIT) {
        let s = surface_hit(h, r.origin, r.dir);
        out.t = h.t;
        out.object = i32(s.object);
        out.triangle = i32(h.triangle);
        out.bary = hit_barycentrics(bvh_triangles[h.triangle], r.origin, r.dir);
    }
    outputs[i] = out;
"#;

const TYPES: &str = r#"
struct Ray { origin: vec3f, t_max: f32, dir: vec3f, };
struct TraceResult { t: f32, object: i32, triangle: i32, any: u32, bary: vec2f, _pad: vec2f, };
"#;

/// Runs the kernel on `rays` (t_max < 0: unbounded).
fn gpu_trace(bvh: &FlatBvh, rays: &[RayGpu]) -> Vec<TraceResultGpu> {
    let ctx = testkit::context();
    let _lock = testkit::gpu_lock();
    let source = format!(
        "{IMPORTS}\n{TYPES}\n{}\n{}",
        kernel_header("Ray", "TraceResult"),
        kernel_entry("trace_rays", BODY)
    );
    let imports = [&raytracer::tracer::QUERIES];
    let defs = [("TRACE_FIRST_BINDING", gpu::wgsl::Def::UInt(2))];
    let kernel = gpu::wgsl::Shader::new("trace_rays", &source)
        .importing(&imports)
        .with_defs(&defs);
    let (nodes, triangles, attributes) =
        (bvh.nodes.clone(), bvh.triangle_gpu(), bvh.attributes_gpu());
    let cutouts = if bvh.cutouts.is_empty() {
        vec![0u32]
    } else {
        bvh.cutouts.clone()
    };
    let buffer = |contents: &[u8]| {
        ctx.device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("bvh"),
                contents,
                usage: wgpu::BufferUsages::STORAGE,
            })
    };
    let nodes = buffer(bytemuck::cast_slice(&nodes));
    let triangles = buffer(bytemuck::cast_slice(&triangles));
    let attributes = buffer(bytemuck::cast_slice(&attributes));
    let cutouts = buffer(bytemuck::cast_slice(&cutouts));
    run_kernel_with(
        ctx,
        kernel,
        "trace_rays",
        rays,
        1,
        &[
            (gpu::bind::storage(true), nodes.as_entire_binding()),
            (gpu::bind::storage(true), triangles.as_entire_binding()),
            (gpu::bind::storage(true), attributes.as_entire_binding()),
            (gpu::bind::storage(true), cutouts.as_entire_binding()),
        ],
    )
    .expect("the traversal kernel runs")
}

fn ray(o: Vec3, d: Vec3, t_max: f32) -> RayGpu {
    RayGpu {
        origin: o.into(),
        t_max,
        dir: d.into(),
        _pad: 0.0,
    }
}

/// Checks every GPU result against the twin; returns how many rays hit.
fn conform(bvh: &FlatBvh, rays: &[RayGpu]) -> usize {
    let out = gpu_trace(bvh, rays);
    let mut hits = 0;
    for (r, g) in rays.iter().zip(&out) {
        let (o, d) = (Vec3::from(r.origin), Vec3::from(r.dir));
        let t_max = if r.t_max >= 0.0 {
            r.t_max
        } else {
            f32::INFINITY
        };
        let twin = bvh.closest_hit(o, d, t_max);
        assert_eq!(g.any == 1, bvh.any_hit(o, d, t_max), "any-hit of {r:?}");
        match twin {
            None => assert!(
                g.t < 0.0,
                "{r:?}: the GPU hit at {} where the twin missed",
                g.t
            ),
            Some(h) => {
                hits += 1;
                assert!(
                    g.t >= 0.0,
                    "{r:?}: the GPU missed where the twin hit at {}",
                    h.t
                );
                // Same triangle, or (on a shared edge) the same distance.
                let tol = 1e-5 * h.t.max(1.0);
                assert!((g.t - h.t).abs() <= tol, "{r:?}: t {} vs twin {}", g.t, h.t);
                if g.object == h.object as i32 && (g.t - h.t).abs() == 0.0 {
                    continue;
                }
                assert_eq!(g.object, h.object as i32, "{r:?}: object");
            }
        }
    }
    hits
}

#[test]
fn camera_rays_of_built_in_scenes_hit_what_the_twin_hits() {
    for spec in [
        "cornell-sphere",
        "refraction-bunny",
        "chess",
        "hu-qin:refractor=teapot",
        scene::builtin::CUTOUT_VARIANTS[0],
    ] {
        let scene = scene::load(spec).unwrap();
        let bvh = FlatBvh::build(&scene, 0.0).unwrap();
        let camera = scene.camera_at(0.0);
        let n = 48;
        let mut rays = Vec::new();
        for y in 0..n {
            for x in 0..n {
                let d = camera.ray_dir(x as f32 + 0.5, y as f32 + 0.5, n, n);
                rays.push(ray(camera.eye, d, -1.0));
            }
        }
        let hits = conform(&bvh, &rays);
        assert!(hits > rays.len() / 2, "{spec}: only {hits} hits");
    }
}

#[test]
fn axis_parallel_grazing_and_bounded_rays_conform() {
    let scene = scene::load("cornell-box").unwrap();
    let bvh = FlatBvh::build(&scene, 0.0).unwrap();
    let world = scene::bvh::WorldTriangles::of(&scene, 0.0);
    let mut rays = Vec::new();
    let axes = [
        Vec3::X,
        Vec3::NEG_X,
        Vec3::Y,
        Vec3::NEG_Y,
        Vec3::Z,
        Vec3::NEG_Z,
    ];
    for k in 0..200 {
        let h = |j: u32| gpu::prelude::hash_to_unit(k * 7 + j);
        let o = Vec3::new(h(0) * 2.0 - 1.0, h(1) * 2.0, h(2) * 2.0 - 1.0);
        rays.push(ray(o, axes[k as usize % 6], -1.0));
        rays.push(ray(o, axes[k as usize % 6], 0.3)); // bounded: may stop short
        // At a point on an edge of a triangle (vertices included).
        let t = &world.triangles
            [(h(3) * world.triangles.len() as f32) as usize % world.triangles.len()];
        let (a, b) = (Vec3::from(t.v0), Vec3::from(t.v1));
        let target = a.lerp(b, (k % 5) as f32 / 4.0);
        let d = (target - o).normalize_or_zero();
        if d != Vec3::ZERO {
            rays.push(ray(o, d, -1.0));
        }
    }
    conform(&bvh, &rays);
}
