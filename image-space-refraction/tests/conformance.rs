//! GPU conformance: `shaders/search.wgsl` runs in compute kernels against its Rust twin
//! (`image_space_refraction::search`) on the same front/back buffers (an analytic sphere's,
//! uploaded as the `Rgba32Float` textures the technique draws), entry points and indices.

use glam::{Vec2, Vec3, Vec4};
use gpu::compute::{kernel_entry, kernel_header, run_kernel_with};
use gpu::wgpu::{self, util::DeviceExt};
use image_space_refraction::search::{
    self, Buffers, Eye, FrontBack, Iteration, Side, Strategy, exit_direction, hu_qin_exit,
    wyman_exit,
};
use image_space_refraction::technique::{EyeGpu, SEARCH_WGSL};

const W: u32 = 96;
const H: u32 = 80;
const IT: Iteration = Iteration {
    tolerance: 1e-4,
    max_iterations: 16,
    initial_step: 0.1,
};

fn eye() -> Eye {
    let camera = scene::Camera {
        eye: Vec3::new(0.4, 0.3, 4.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_y_deg: 40.0,
    };
    Eye::of_camera(&camera, W, H)
}

const BINDINGS: &str = r#"
@group(0) @binding(2) var<uniform> eye_params: EyeParams;
@group(0) @binding(3) var front_buffer: texture_2d<f32>;
@group(0) @binding(4) var back_buffer: texture_2d<f32>;
"#;

/// One case: p1 (xyz) + ior (w), v (xyz) + strategy (w), n1 (xyz) + d_n (w), t1.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Case {
    p1: [f32; 4],
    v: [f32; 4],
    n1: [f32; 4],
    t1: [f32; 4],
}

/// Out: the exit point (xyz) + side (w), T2 (xyz) + iterations (w), silhouette inside (xy) +
/// outside (zw), Wyman's exit point (xyz) + distance (w).
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct Out {
    exit: [f32; 4],
    t2: [f32; 4],
    silhouette: [f32; 4],
    wyman: [f32; 4],
}

fn kernel() -> String {
    format!(
        "{}{BINDINGS}{SEARCH_WGSL}{}",
        kernel_header("Case", "Out"),
        kernel_entry(
            "main",
            r#"
    let c = inputs[i];
    let it = Iteration(1e-4, 16u, 0.1);
    let exit = hu_qin_exit(eye_params, c.p1.xyz, c.v.xyz, c.t1.xyz, u32(c.v.w), it);
    let t2 = exit_direction(exit, c.t1.xyz, c.p1.w);
    let start = eye_project(eye_params, c.p1.xyz).xy;
    let dir = projected_direction(eye_params, c.p1.xyz, c.t1.xyz);
    let s = silhouette_search(eye_params, start, dir, 1.0);
    let w = wyman_exit(eye_params, c.p1.xyz, c.v.xyz, c.n1.xyz, c.t1.xyz, c.n1.w);
    outputs[i] = Out(vec4f(exit.point, f32(exit.side)), vec4f(t2.xyz, f32(exit.iterations)),
                     vec4f(s.inside, s.outside), vec4f(w.point, w.distance));
"#
        )
    )
    .replacen(
        "@group(0) @binding(0)",
        "struct Case { p1: vec4f, v: vec4f, n1: vec4f, t1: vec4f };\n\
         struct Out { exit: vec4f, t2: vec4f, silhouette: vec4f, wyman: vec4f };\n\
         @group(0) @binding(0)",
        1,
    )
}

fn upload(ctx: &gpu::Context, data: &[[f32; 4]], label: &str) -> wgpu::TextureView {
    ctx.device
        .create_texture_with_data(
            &ctx.queue,
            &wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width: W,
                    height: H,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu::TextureFormat::Rgba32Float,
                usage: wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            },
            wgpu::util::TextureDataOrder::LayerMajor,
            bytemuck::cast_slice(data),
        )
        .create_view(&Default::default())
}

#[test]
fn wgsl_searches_match_their_twins() {
    let ctx = testkit::context();
    let _lock = testkit::gpu_lock();
    let e = eye();
    let buffers = FrontBack::sphere(&e, Vec3::ZERO, 1.0);
    // Entry points: every covered pixel of a coarse grid, several indices, both strategies.
    let mut cases = Vec::new();
    let mut twins = Vec::new();
    for y in (0..H).step_by(3) {
        for x in (0..W).step_by(3) {
            let pixel = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
            let Some(front) = buffers.texel(Side::Front, pixel) else {
                continue;
            };
            let p1 = e.unproject(pixel, front.depth);
            let v = (p1 - e.position).normalize();
            let n1 = front.normal;
            for (k, ior) in [0.6f32, 1.15, 1.5, 2.4].into_iter().enumerate() {
                let t1 = gpu::prelude::refract_dir(v, n1, 1.0 / ior);
                if t1.w < 0.5 {
                    continue;
                }
                let t1 = t1.truncate();
                let strategy = if (x + y + k as u32) % 2 == 0 {
                    Strategy::AngleTest
                } else {
                    Strategy::BackFirst
                };
                let d_n = 2.0 * p1.length() * n1.dot(-p1.normalize()).abs();
                cases.push(Case {
                    p1: p1.extend(ior).to_array(),
                    v: v.extend(if strategy == Strategy::BackFirst {
                        1.0
                    } else {
                        0.0
                    })
                    .to_array(),
                    n1: n1.extend(d_n).to_array(),
                    t1: t1.extend(0.0).to_array(),
                });
                let exit = hu_qin_exit(&buffers, &e, p1, v, t1, strategy, &IT);
                let t2 = exit_direction(&exit, t1, ior);
                let start = e.project(p1).truncate();
                let dir = search::projected_direction(&e, p1, t1);
                let s = search::silhouette_search(&buffers, &e, start, dir, 1.0);
                let w = wyman_exit(&buffers, &e, p1, v, n1, t1, d_n);
                twins.push((exit, t2, s, w));
            }
        }
    }
    assert!(cases.len() > 300, "only {} cases", cases.len());
    let eye_uniform = ctx
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("eye"),
            contents: bytemuck::bytes_of(&EyeGpu::from(&e)),
            usage: wgpu::BufferUsages::UNIFORM,
        });
    let front = upload(ctx, &buffers.front, "front");
    let back = upload(ctx, &buffers.back, "back");
    let source = format!("{}\n{}", gpu::prelude::PRELUDE_WGSL, kernel());
    let out: Vec<Out> = run_kernel_with(
        ctx,
        &source,
        "main",
        &cases,
        1,
        &[
            (gpu::bind::uniform(), eye_uniform.as_entire_binding()),
            (
                gpu::bind::texture_2d_unfilterable(),
                gpu::bind::view(&front),
            ),
            (gpu::bind::texture_2d_unfilterable(), gpu::bind::view(&back)),
        ],
    )
    .expect("the kernel runs");
    // Float differences may move a test point across a texel boundary: the exit may then
    // land a texel away. Count those; everything else must agree closely.
    let texel = 2.0 * 4.0 * 20f32.to_radians().tan() / H as f32;
    let mut far = 0;
    for (g, (exit, t2, s, w)) in out.iter().zip(&twins) {
        let gpu_exit = Vec4::from(g.exit);
        assert!(Vec4::from(g.t2).is_finite() && gpu_exit.is_finite());
        let side = if gpu_exit.w == 0.0 {
            Side::Front
        } else {
            Side::Back
        };
        let close = gpu_exit.truncate().distance(exit.point) < 1e-3
            && side == exit.side
            && Vec4::from(g.t2).truncate().distance(t2.truncate()) < 1e-3;
        let silhouette = Vec2::new(g.silhouette[0], g.silhouette[1]).distance(s.inside) < 1e-2
            && Vec2::new(g.silhouette[2], g.silhouette[3]).distance(s.outside) < 1e-2;
        let wyman = Vec4::from(g.wyman).truncate().distance(w.point) < 1e-3;
        if !(close && silhouette && wyman) {
            far += 1;
            assert!(
                gpu_exit.truncate().distance(exit.point) < 2.0 * texel,
                "GPU exit {gpu_exit} vs twin {exit:?}"
            );
        }
    }
    println!(
        "{} cases, {far} differ by float rounding (within 2 texels)",
        cases.len()
    );
    assert!(
        far * 50 <= cases.len(),
        "{far} of {} cases differ",
        cases.len()
    );
}
