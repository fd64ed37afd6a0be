//! GPU conformance: `shaders/search.wgsl` runs in compute kernels against its Rust twin
//! (`image_space_refraction::search`) on the same front/back buffers (an analytic sphere's,
//! uploaded as the `Rgba32Float` textures the technique draws), entry points and indices;
//! `shaders/caustic_compute.wgsl` (through `caustics::Accumulator`) and `shaders/nearby.wgsl`'s
//! `nearby_hit` against their twins (`caustics`, `nearby`).

use glam::{Vec2, Vec3, Vec4};
use gpu::compute::{kernel_entry, kernel_header, run_kernel_with};
use gpu::wgpu::{self, util::DeviceExt};
use image_space_refraction::caustics::{self, Accumulator, CausticSettings, scatter};
use image_space_refraction::nearby::{DepthLayers, Lookup, Rect, nearby_hit};
use image_space_refraction::rectangles::{NearbyParamsGpu, RectGpu};
use image_space_refraction::search::EyeGpu;
use image_space_refraction::search::{
    self, Buffers, Eye, FrontBack, Iteration, Side, Strategy, exit_direction, hu_qin_exit,
    wyman_exit,
};

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
        orthographic: None,
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
        "#import image_space_refraction::search::{{EyeParams, Iteration, eye_project, \
         exit_direction, hu_qin_exit, projected_direction, silhouette_search, wyman_exit}}\n\
         {}{BINDINGS}{}",
        kernel_header("Case", "Out"),
        kernel_entry(
            "main",
            r#"
    let c = inputs[i];
    let it = Iteration(1e-4, 16u, 0.1);
    let exit = hu_qin_exit(front_buffer, back_buffer, eye_params, c.p1.xyz, c.v.xyz, c.t1.xyz,
                           u32(c.v.w), it);
    let t2 = exit_direction(exit, c.t1.xyz, c.p1.w);
    let start = eye_project(eye_params, c.p1.xyz).xy;
    let dir = projected_direction(eye_params, c.p1.xyz, c.t1.xyz);
    let s = silhouette_search(front_buffer, back_buffer, eye_params, start, dir, 1.0);
    let w = wyman_exit(front_buffer, back_buffer, eye_params, c.p1.xyz, c.v.xyz, c.n1.xyz,
                       c.t1.xyz, c.n1.w);
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
    let source = kernel();
    let imports = [&image_space_refraction::search::SEARCH];
    let kernel = gpu::wgsl::Shader::new("searches", &source).importing(&imports);
    let out: Vec<Out> = run_kernel_with(
        ctx,
        kernel,
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

// ---- GPU conformance -------------------------------------------------------------------------

/// A small deterministic generator (xorshift) for the GPU cases.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
    fn unit(&mut self) -> Vec3 {
        loop {
            let v = Vec3::new(self.next(), self.next(), self.next()) * 2.0 - 1.0;
            if (0.01..1.0).contains(&v.length_squared()) {
                return v.normalize();
            }
        }
    }
}

fn texture_2d(
    ctx: &gpu::Context,
    label: &str,
    (width, height, layers): (u32, u32, u32),
    format: wgpu::TextureFormat,
    data: &[u8],
) -> wgpu::Texture {
    ctx.device.create_texture_with_data(
        &ctx.queue,
        &wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: layers,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        data,
    )
}

/// A photon buffer of `size`^2 photons over `layers` layers: about a quarter empty, some on
/// texel edges and at u or v = 1.
fn photon_buffer(rng: &mut Rng, size: u32, layers: u32, res: u32) -> [Vec<[f32; 4]>; 2] {
    let mut hits = Vec::new();
    let mut power = Vec::new();
    for _ in 0..size * size {
        let coordinate = |rng: &mut Rng| match (rng.next() * 8.0) as u32 {
            0 => 1.0,
            1 => (rng.next() * res as f32).floor() / res as f32,
            _ => rng.next(),
        };
        let (u, v) = (coordinate(rng), coordinate(rng));
        let layer = ((rng.next() * layers as f32) as u32).min(layers - 1);
        if rng.next() < 0.25 {
            hits.push([0.0; 4]);
        } else {
            hits.push([u, v, (layer + 1) as f32, 0.0]);
        }
        power.push([rng.next() * 10.0, rng.next() * 10.0, rng.next() * 3.0, 0.0]);
    }
    [hits, power]
}

/// `Accumulator` (scatter of two photon buffers, then the filter) against `scatter` +
/// `filter` + the texel areas: the same irradiance per texel.
#[test]
fn caustic_compute_matches_its_twins() {
    let _lock = testkit::gpu_lock();
    let ctx = testkit::context();
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    for (layers, k, resolution, scale) in [(2u32, 1u32, 24u32, 1.0f32), (3, 2, 20, 0.37)] {
        let settings = CausticSettings {
            photon_size: 32,
            resolution,
            k,
            scale,
            ..CausticSettings::default()
        };
        let accumulator = Accumulator::new(ctx, settings, layers);
        let unit = 1e-5f32;
        let areas: Vec<f32> = (0..layers).map(|l| 0.01 + 0.02 * l as f32).collect();
        let buffers: Vec<[Vec<[f32; 4]>; 2]> = (0..2)
            .map(|_| photon_buffer(&mut rng, settings.photon_size, layers, resolution))
            .collect();
        let size = (settings.photon_size, settings.photon_size, 1);
        let views: Vec<[wgpu::TextureView; 2]> = buffers
            .iter()
            .map(|[hit, power]| {
                [hit, power].map(|data| {
                    texture_2d(
                        ctx,
                        "photons",
                        size,
                        wgpu::TextureFormat::Rgba32Float,
                        bytemuck::cast_slice(data),
                    )
                    .create_view(&Default::default())
                })
            })
            .collect();
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        accumulator.begin(ctx, &mut encoder, unit, &areas);
        for [hit, power] in &views {
            accumulator.scatter(ctx, &mut encoder, hit, power);
        }
        accumulator.filter(ctx, &mut encoder, &views[0][0], &views[0][1]);
        ctx.queue.submit([encoder.finish()]);
        let bytes = gpu::read_buffer(ctx, &accumulator.caustic).expect("read back");
        let gpu_out: Vec<[f32; 4]> = bytemuck::pod_collect_to_vec(&bytes);
        // The twins.
        let photons: Vec<(Vec2, u32, Vec3)> = buffers
            .iter()
            .flat_map(|[hit, power]| hit.iter().zip(power))
            .filter(|(h, _)| h[2] >= 0.5)
            .map(|(h, p)| {
                (
                    Vec2::new(h[0], h[1]),
                    (h[2] - 0.5) as u32,
                    Vec3::new(p[0], p[1], p[2]),
                )
            })
            .collect();
        let counts = scatter(&photons, resolution, layers, unit);
        let texels = (resolution * resolution) as usize;
        let mut largest = 0.0f32;
        let mut twin = Vec::new();
        for layer in 0..layers as usize {
            let layer_counts: Vec<[f32; 3]> = counts[layer * texels..(layer + 1) * texels]
                .iter()
                .map(|c| c.map(|c| c as f32))
                .collect();
            for t in caustics::filter(&layer_counts, resolution, k, scale) {
                let e = t.map(|p| p * unit / areas[layer]);
                largest = largest.max(e[0].max(e[1]).max(e[2]));
                twin.push(e);
            }
        }
        assert_eq!(gpu_out.len(), twin.len());
        let mut worst = 0.0f32;
        for (i, (g, t)) in gpu_out.iter().zip(&twin).enumerate() {
            for ch in 0..3 {
                let diff = (g[ch] - t[ch]).abs();
                worst = worst.max(diff / t[ch].abs().max(1e-6 * largest));
                assert!(
                    diff <= 1e-4 * t[ch].abs() + 1e-6 * largest,
                    "layers {layers}, k {k}: texel {i} channel {ch}: GPU {} vs twin {}",
                    g[ch],
                    t[ch]
                );
            }
            assert_eq!(g[3], 0.0);
        }
        println!(
            "{layers} layers of {resolution}^2, k {k}: {} photons, largest irradiance {largest}, \
             worst relative difference {worst:e}",
            photons.len()
        );
        assert!(largest > 0.0);
    }
}

// ---- nearby.wgsl ---------------------------------------------------------------------------

const RES: u32 = 256;

/// The depth texture of a sphere's square impostor (texel centres, first hit along the
/// projection, normalized; 1 where missed).
fn sphere_layer(rect: &Rect, centre: Vec3, radius: f32) -> Vec<f32> {
    let mut texels = vec![1.0f32; (RES * RES) as usize];
    for y in 0..RES {
        for x in 0..RES {
            let u = (x as f32 + 0.5) / RES as f32;
            let v = (y as f32 + 0.5) / RES as f32;
            let q = rect.centre
                + rect.axis_u * (2.0 * u - 1.0) * rect.half_u
                + rect.axis_v * (1.0 - 2.0 * v) * rect.half_v;
            let rho2 = (q - centre).length_squared();
            if rho2 < radius * radius {
                let p = q - rect.direction * (radius * radius - rho2).sqrt();
                let depth = (p - rect.origin).dot(rect.direction);
                texels[(y * RES + x) as usize] = (depth - rect.near) / (rect.far - rect.near);
            }
        }
    }
    texels
}

/// A wall's texture: the rectangle itself (normalized depth 0.5), with a few empty squares.
fn wall_layer() -> Vec<f32> {
    (0..RES * RES)
        .map(|i| {
            let (x, y) = (i % RES / 32, i / RES / 32);
            if (x + 2 * y) % 5 == 0 { 1.0 } else { 0.5 }
        })
        .collect()
}

/// Writes normalized depths into every layer of a `Depth32Float` array (which takes no
/// buffer copies): a full-screen draw per layer whose fragment depth is the texel's value.
fn depth_array(ctx: &gpu::Context, layers: &[(u32, &[f32])]) -> wgpu::Texture {
    let texture = gpu::render_texture(
        ctx,
        "impostor depths",
        (RES, RES, layers.len() as u32),
        gpu::DEPTH_FORMAT,
        wgpu::TextureUsages::COPY_SRC,
    );
    let source = r#"
@group(0) @binding(0) var<storage, read> values: array<f32>;
@vertex
fn vs(@builtin(vertex_index) index: u32) -> @builtin(position) vec4f {
    let xy = vec2f(f32((index << 1u) & 2u), f32(index & 2u));
    return vec4f(xy * 2.0 - 1.0, 0.0, 1.0);
}
@fragment
fn fs(@builtin(position) p: vec4f) -> @builtin(frag_depth) f32 {
    let size = u32(sqrt(f32(arrayLength(&values))) + 0.5);
    return values[u32(p.y) * size + u32(p.x)];
}
"#;
    let module = ctx
        .device
        .create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("depth upload"),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
    let layout = gpu::bind::layout(
        ctx,
        "depth upload",
        wgpu::ShaderStages::FRAGMENT,
        &[gpu::bind::storage(true)], // values
    );
    let pipeline_layout = ctx
        .device
        .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("depth upload"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
    let pipeline = ctx
        .device
        .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("depth upload"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs"),
                compilation_options: Default::default(),
                targets: &[],
            }),
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(gpu::pass::depth_state(true, wgpu::CompareFunction::Always)),
            multisample: wgpu::MultisampleState::default(),
            multiview_mask: None,
            cache: None,
        });
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    for &(layer, values) in layers {
        let buffer = ctx
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("depth values"),
                contents: bytemuck::cast_slice(values),
                usage: wgpu::BufferUsages::STORAGE,
            });
        let group = gpu::bind::group(ctx, "depth upload", &layout, &[buffer.as_entire_binding()]);
        let view = gpu::layer_view(&texture, layer);
        let mut pass = gpu::pass::begin(
            &mut encoder,
            "depth upload",
            &[],
            Some(gpu::pass::depth(&view, gpu::pass::CLEAR_FAR)),
            None,
        );
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.draw(0..3, 0..1);
    }
    ctx.queue.submit([encoder.finish()]);
    texture
}

/// A kernel importing `image_space_refraction::nearby` (the module the technique imports) with
/// its resources placed after the kernel's two buffers, [`NEARBY_IN_KERNEL`].
fn nearby_kernel() -> String {
    format!(
        "#import image_space_refraction::nearby::nearby_hit\n\
         struct Ray {{ origin: vec4f, dir: vec4f }};\n{}\n{}",
        kernel_header("Ray", "vec4f"),
        kernel_entry(
            "main",
            "    let h = nearby_hit(inputs[i].origin.xyz, inputs[i].dir.xyz);\n    \
             outputs[i] = vec4f(select(-1.0, f32(h.rect), h.hit), h.t, h.uv);"
        )
    )
}

/// nearby.wgsl's resources at `@group(0)` from binding 2, after the kernel's buffers.
const NEARBY_IN_KERNEL: [(&str, gpu::wgsl::Def); 2] = [
    ("NEARBY_GROUP", gpu::wgsl::Def::UInt(0)),
    ("NEARBY_FIRST_BINDING", gpu::wgsl::Def::UInt(2)),
];

/// `nearby_hit` of nearby.wgsl against the twin, uncorrected and corrected, on two spheres'
/// impostors and a wall with holes (layers permuted, as the WGSL reads `origin.w`).
#[test]
fn nearby_wgsl_matches_its_twin() {
    let _lock = testkit::gpu_lock();
    let ctx = testkit::context();
    let from = Vec3::new(0.0, 0.2, 0.5);
    let spheres = [
        (Vec3::new(0.2, 0.1, -3.0), 0.8f32),
        (Vec3::new(1.2, -0.4, -1.8), 0.5),
    ];
    let mut rects: Vec<Rect> = spheres
        .iter()
        .map(|&(c, r)| Rect::square(from, c, r))
        .collect();
    rects.push(Rect::planar(
        Vec3::new(-3.0, -1.5, -5.0),
        Vec3::new(6.0, 0.0, 0.0),
        Vec3::new(0.0, 4.0, 0.0),
        from,
    ));
    let mut layers: Vec<Vec<f32>> = rects
        .iter()
        .zip(&spheres)
        .map(|(r, &(c, radius))| sphere_layer(r, c, radius))
        .collect();
    layers.push(wall_layer());
    let twin_depths = DepthLayers {
        resolution: RES,
        layers: layers.clone(),
    };
    // Rectangle i at texture layer perm[i].
    let perm = [2u32, 0, 1];
    let depth_texture = depth_array(
        ctx,
        &perm
            .iter()
            .zip(&layers)
            .map(|(&p, l)| (p, l.as_slice()))
            .collect::<Vec<_>>(),
    );
    for (&p, l) in perm.iter().zip(&layers) {
        let back = gpu::read_texture_f32(ctx, &depth_texture, p).expect("read depth");
        assert!(
            back.iter().zip(l).all(|(a, b)| a.to_bits() == b.to_bits()),
            "the depth upload changed values"
        );
    }
    let depth_view = depth_texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    });
    let color_data = vec![[0.5f32; 4]; (RES * RES) as usize * rects.len()];
    let color_view = texture_2d(
        ctx,
        "impostor colours",
        (RES, RES, rects.len() as u32),
        wgpu::TextureFormat::Rgba32Float,
        bytemuck::cast_slice(&color_data),
    )
    .create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    });
    let table: Vec<RectGpu> = rects
        .iter()
        .zip(perm)
        .map(|(r, p)| RectGpu::new(r, p))
        .collect();
    let rect_buffer = ctx
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("rects"),
            contents: bytemuck::cast_slice(&table),
            usage: wgpu::BufferUsages::STORAGE,
        });
    // Rays from around the refractor: half aimed at the objects, half anywhere ahead.
    let mut rng = Rng(0x2545_f491_4f6c_dd1d);
    let mut rays = Vec::new();
    while rays.len() < 1200 {
        let origin = from + rng.unit() * rng.next().cbrt() * 0.3;
        let dir = match rays.len() % 4 {
            0 | 1 => {
                let (c, r) = spheres[rays.len() % 4];
                (c + rng.unit() * r * 1.1 - origin).normalize()
            }
            2 => (Vec3::new(rng.next() * 6.0 - 3.0, rng.next() * 4.0 - 1.5, -5.0) - origin)
                .normalize(),
            _ => rng.unit(),
        };
        rays.push([origin.extend(0.0).to_array(), dir.extend(0.0).to_array()]);
    }
    let source = nearby_kernel();
    let texel = rects
        .iter()
        .map(|r| 2.0 * r.half_u.max(r.half_v) / RES as f32)
        .fold(0.0f32, f32::max);
    let tolerance = 1e-4;
    for lookup in [
        Lookup::Uncorrected,
        Lookup::Corrected {
            seeds: 8,
            iterations: 16,
        },
    ] {
        let params = match lookup {
            Lookup::Uncorrected => NearbyParamsGpu::new(3, false, 8, 16, tolerance),
            Lookup::Corrected { seeds, iterations } => {
                NearbyParamsGpu::new(3, true, seeds, iterations, tolerance)
            }
        };
        let params = ctx
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("nearby params"),
                contents: bytemuck::bytes_of(&params),
                usage: wgpu::BufferUsages::UNIFORM,
            });
        let imports = [&image_space_refraction::nearby::NEARBY];
        let kernel = gpu::wgsl::Shader::new("nearby", &source)
            .importing(&imports)
            .with_defs(&NEARBY_IN_KERNEL);
        let out: Vec<[f32; 4]> = run_kernel_with(
            ctx,
            kernel,
            "main",
            &rays,
            1,
            &[
                (gpu::bind::storage(true), rect_buffer.as_entire_binding()),
                (gpu::bind::uniform(), params.as_entire_binding()),
                (
                    gpu::bind::texture(wgpu::TextureViewDimension::D2Array, false),
                    gpu::bind::view(&color_view),
                ),
                (
                    gpu::bind::depth_texture(wgpu::TextureViewDimension::D2Array),
                    gpu::bind::view(&depth_view),
                ),
            ],
        )
        .expect("the kernel runs");
        let (mut hits, mut differ, mut hit_or_miss) = (0, 0, 0);
        let mut per_rect = [0usize; 3];
        for (g, ray) in out.iter().zip(&rays) {
            let (origin, dir) = (Vec3::from_slice(&ray[0]), Vec3::from_slice(&ray[1]));
            let twin = nearby_hit(&rects, &twin_depths, origin, dir, lookup, tolerance);
            let gpu_hit = (g[0] >= 0.0).then(|| (g[0] as usize, g[1], Vec2::new(g[2], g[3])));
            if let Some((i, _, _)) = twin {
                hits += 1;
                per_rect[i] += 1;
            }
            match (twin, gpu_hit) {
                (None, None) => {}
                (Some((i, t, uv)), Some((gi, gt, guv))) => {
                    let same = i == gi
                        && (t - gt).abs() <= 1e-4 * t.max(1.0)
                        && (uv - guv).abs().max_element() <= 1e-4;
                    if !same {
                        differ += 1;
                        let apart = (origin + dir * t).distance(origin + dir * gt);
                        assert!(
                            apart <= 2.0 * texel,
                            "{lookup:?}: ray {origin} {dir}: GPU {gpu_hit:?} vs twin {twin:?}"
                        );
                    }
                }
                _ => {
                    differ += 1;
                    hit_or_miss += 1;
                }
            }
        }
        println!(
            "{lookup:?}: {} rays, {hits} hits (per rectangle {per_rect:?}), {differ} differ by \
             float rounding ({hit_or_miss} hit against miss)",
            rays.len()
        );
        assert!(
            hits > rays.len() / 3 && per_rect.iter().all(|&n| n > 50),
            "too few hits"
        );
        assert!(
            differ * 50 < rays.len(),
            "{differ} of {} rays differ",
            rays.len()
        );
    }
}
