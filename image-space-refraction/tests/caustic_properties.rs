//! Properties of the caustic twins (`image_space_refraction::caustics`, section 3.2) and GPU
//! conformance of `shaders/caustic_compute.wgsl` (through `caustics::Accumulator`) and of
//! `shaders/nearby.wgsl`'s `nearby_hit` against their Rust twins.

use glam::{Vec2, Vec3};
use gpu::compute::{kernel_entry, kernel_header, run_kernel_with};
use gpu::wgpu::{self, util::DeviceExt};
use image_space_refraction::caustics::{
    self, Accumulator, CausticSettings, filter, filter_weight, scatter,
};
use image_space_refraction::nearby::{DepthLayers, Lookup, Rect, nearby_hit};
use image_space_refraction::rectangles::{NearbyParamsGpu, RectGpu};
use proptest::prelude::*;

/// Sparse counts: `(x, y, rgb)` at texels of a `res`^2 layer, at least `border` from its edges.
fn sparse_counts(res: u32, border: u32, photons: &[(f32, f32, [f32; 3])]) -> Vec<[f32; 3]> {
    let mut counts = vec![[0.0f32; 3]; (res * res) as usize];
    let span = (res - 2 * border) as f32;
    for &(a, b, c) in photons {
        let x = border + ((a * span) as u32).min(res - 2 * border - 1);
        let y = border + ((b * span) as u32).min(res - 2 * border - 1);
        let t = &mut counts[(y * res + x) as usize];
        for ch in 0..3 {
            t[ch] += c[ch];
        }
    }
    counts
}

fn sums(counts: &[[f32; 3]]) -> [f64; 3] {
    let mut s = [0.0f64; 3];
    for c in counts {
        for ch in 0..3 {
            s[ch] += f64::from(c[ch]);
        }
    }
    s
}

fn photon_list() -> impl Strategy<Value = Vec<(f32, f32, [f32; 3])>> {
    proptest::collection::vec(
        (
            0.0f32..1.0,
            0.0f32..1.0,
            [0u32..5000, 0u32..5000, 0u32..5000].prop_map(|c| c.map(|c| c as f32)),
        ),
        0..40,
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// The normalized filter keeps a layer's power times `s` when no photon lies within `k`
    /// texels of the border, and never adds power otherwise.
    #[test]
    fn filter_keeps_power_times_scale(
        res in 16u32..=64,
        k in 0u32..=3,
        scale in 0.1f32..10.0,
        photons in photon_list(),
    ) {
        let inside = sparse_counts(res, k, &photons);
        let (sin, sout) = (sums(&inside), sums(&filter(&inside, res, k, scale)));
        for ch in 0..3 {
            let want = f64::from(scale) * sin[ch];
            prop_assert!(
                (sout[ch] - want).abs() <= 1e-4 * want,
                "channel {ch}: filtered {} vs s x photons {want}", sout[ch]
            );
        }
        let anywhere = sparse_counts(res, 0, &photons);
        let (sin, sout) = (sums(&anywhere), sums(&filter(&anywhere, res, k, scale)));
        for ch in 0..3 {
            let bound = f64::from(scale) * sin[ch];
            prop_assert!(sout[ch] <= bound * (1.0 + 1e-4), "channel {ch}: {} > {bound}", sout[ch]);
        }
    }

    /// The paper's weights are positive over the whole window and symmetric in i, j and
    /// their signs.
    #[test]
    fn filter_weights_are_positive_and_symmetric(k in 0i32..=64, a in 0.0f64..=1.0, b in 0.0f64..=1.0) {
        let i = (a * f64::from(2 * k)).round() as i32 - k;
        let j = (b * f64::from(2 * k)).round() as i32 - k;
        let w = filter_weight(i, j, k);
        prop_assert!(w > 0.0 && w.is_finite(), "w({i}, {j}, {k}) = {w}");
        for other in [filter_weight(j, i, k), filter_weight(-i, j, k), filter_weight(i, -j, k)] {
            prop_assert_eq!(w, other);
        }
    }

    /// Each photon's power lands in texel floor(uv res) (clamped to the last texel) of its
    /// layer, as round(power / unit) counts; the total counts times `unit` equal the total
    /// power within unit / 2 per photon.
    #[test]
    fn scatter_puts_power_in_the_photon_texel(
        res in 1u32..=48,
        layers in 1u32..=3,
        unit in 1e-3f32..1.0,
        photons in proptest::collection::vec(
            (
                prop_oneof![3 => 0.0f32..=1.0, 1 => Just(1.0f32), 1 => (0u32..=48).prop_map(|i| i as f32 / 48.0)],
                prop_oneof![3 => 0.0f32..=1.0, 1 => Just(1.0f32), 1 => Just(0.0f32)],
                0u32..3,
                [0.0f32..100.0, 0.0f32..100.0, 0.0f32..100.0],
            ),
            0..30,
        ),
    ) {
        let photons: Vec<(Vec2, u32, Vec3)> = photons
            .into_iter()
            .map(|(u, v, l, p)| (Vec2::new(u, v), l % layers, Vec3::from(p)))
            .collect();
        let r = res as usize;
        for &(uv, layer, power) in &photons {
            let counts = scatter(&[(uv, layer, power)], res, layers, unit);
            let x = ((uv.x * res as f32).floor() as usize).min(r - 1);
            let y = ((uv.y * res as f32).floor() as usize).min(r - 1);
            let at = (layer as usize * r + y) * r + x;
            let want = power.to_array().map(|p| (p / unit).round() as u32);
            prop_assert_eq!(counts[at], want);
            prop_assert!(counts.iter().enumerate().all(|(i, c)| i == at || *c == [0; 3]));
        }
        let counts = scatter(&photons, res, layers, unit);
        for ch in 0..3 {
            let total: f64 = counts.iter().map(|c| f64::from(c[ch])).sum::<f64>() * f64::from(unit);
            let power: f64 = photons.iter().map(|p| f64::from(p.2[ch])).sum();
            let slack = photons.len() as f64 * f64::from(unit) * (0.5 + 1e-5) + 1e-9;
            prop_assert!((total - power).abs() <= slack, "channel {ch}: {total} vs {power}");
        }
    }
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

/// nearby.wgsl moved to `@group(0)` after the kernel's two buffers, with a stub for the
/// environment lookup that `outgoing_radiance` calls.
fn nearby_kernel() -> String {
    let mut nearby = include_str!("../src/shaders/nearby.wgsl").to_string();
    for b in 0..4 {
        let from = format!("@group(3) @binding({b})");
        assert!(nearby.contains(&from), "nearby.wgsl has no {from}");
        nearby = nearby.replace(&from, &format!("@group(0) @binding({})", b + 2));
    }
    format!(
        "{}\nstruct Ray {{ origin: vec4f, dir: vec4f }};\n{}{}\n{nearby}\n\
         fn env_lookup(d: vec3f) -> vec3f {{ return vec3f(0.0); }}\n{}",
        gpu::prelude::PRELUDE_WGSL,
        kernel_header("Ray", "vec4f"),
        include_str!("../src/shaders/rect.wgsl"),
        kernel_entry(
            "main",
            "    let h = nearby_hit(inputs[i].origin.xyz, inputs[i].dir.xyz);\n    \
             outputs[i] = vec4f(select(-1.0, f32(h.rect), h.hit), h.t, h.uv);"
        )
    )
}

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
        let out: Vec<[f32; 4]> = run_kernel_with(
            ctx,
            &source,
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
