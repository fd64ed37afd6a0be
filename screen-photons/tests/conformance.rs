//! GPU conformance: the WGSL march (`shaders/ldi.wgsl`) and splat weight (`shaders/splat.wgsl`)
//! run in compute kernels against their Rust twins (`march`, `splat`) on the same inputs.

use glam::{Vec3, Vec4};
use gpu::compute::{kernel_entry, kernel_header, run_kernel, run_kernel_with};
use gpu::wgpu::{self, util::DeviceExt};
use scene::Camera;
use screen_photons::march::{self, Eye, Ldi, RayState, Side, Sphere};
use screen_photons::technique::LdiParamsGpu;

const TOLERANCE: f32 = 0.03;
const THICKNESS: f32 = 0.1;
const W: u32 = 64;
const H: u32 = 48;

fn eye() -> Eye {
    let cam = Camera {
        eye: Vec3::new(0.3, 0.4, 5.0),
        target: Vec3::new(0.0, 0.0, -1.0),
        up: Vec3::Y,
        fov_y_deg: 50.0,
        orthographic: None,
    };
    Eye {
        view_proj: cam.view_proj(W, H),
        position: cam.eye,
        width: W,
        height: H,
    }
}

/// A glass sphere in front of a larger diffuse one.
fn spheres() -> Vec<Sphere> {
    vec![
        Sphere {
            centre: Vec3::ZERO,
            radius: 1.0,
            object: 0,
            specular: true,
        },
        Sphere {
            centre: Vec3::new(1.2, -0.4, -3.0),
            radius: 1.6,
            object: 1,
            specular: false,
        },
    ]
}

/// The kernel's side of `screen_photons::ldi`: the march's names, the LDI placed at @group(0)
/// from binding 2 (the definitions [`KERNEL_LDI_DEFS`]), and each object's material kind from
/// a buffer of the kernel's own (it overrides `ldi_kind`, which reads the scene's materials).
const KERNEL_BINDINGS: &str = r#"
#import screen_photons::ldi
#import screen_photons::ldi::{LDI_REFRACTORS, LDI_SCENE, LdiHit, clip_segment, march_dda, march_monotone, march_shadow, march_tolerance, scene_range}
@group(0) @binding(7) var<storage, read> kinds: array<u32>;
override fn screen_photons::ldi::ldi_kind(object: u32) -> u32 { return kinds[object]; }

struct RayCase {
    // xyz origin, w: mode (0 DDA, 1 tolerance in order, 2 monotone in layer 1 of the
    // refractors, 3 the shadow ray with the in-out test)
    origin: vec4f,
    // xyz direction, w: the side (0 outside glass, 1 inside, 2 any: a shadow ray)
    dir: vec4f,
};
"#;

/// The kernel's LDI: `@group(0)` from `@binding(2)` (0 and 1 are its inputs and outputs).
const KERNEL_LDI_DEFS: [(&str, gpu::wgsl::Def); 2] = [
    ("LDI_GROUP", gpu::wgsl::Def::UInt(0)),
    ("LDI_FIRST_BINDING", gpu::wgsl::Def::UInt(2)),
];

const MARCH_BODY: &str = r#"
    let c = inputs[i];
    let range = scene_range(c.origin.xyz, c.dir.xyz);
    let s = clip_segment(c.origin.xyz, c.dir.xyz, range.x, range.y);
    let side = u32(c.dir.w);
    var h: LdiHit;
    if (c.origin.w == 0.0) {
        h = march_dda(LDI_SCENE, s, side);
    } else if (c.origin.w == 1.0) {
        h = march_tolerance(LDI_SCENE, s, side);
    } else if (c.origin.w == 2.0) {
        h = march_monotone(LDI_REFRACTORS, s, 1u);
    } else {
        h = march_shadow(LDI_SCENE, s);
    }
    outputs[i] = select(vec4f(0.0), vec4f(h.t, f32(h.layer), vec2f(h.pixel)), h.found);
"#;

/// Uploads an LDI as the two array textures the peeler makes (normal + distance, surface).
fn upload(ctx: &gpu::Context, ldi: &Ldi) -> (wgpu::Texture, wgpu::Texture) {
    let make = |label: &str, texel: &dyn Fn(&march::Texel) -> [f32; 4]| {
        let data: Vec<[f32; 4]> = ldi.texels.iter().map(texel).collect();
        ctx.device.create_texture_with_data(
            &ctx.queue,
            &wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width: ldi.width,
                    height: ldi.height,
                    depth_or_array_layers: ldi.layers,
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
        )
    };
    (
        make("ldi layers", &|t| t.normal.extend(t.distance).to_array()),
        make("ldi surfaces", &|t| {
            [
                t.object as f32,
                0.0,
                0.0,
                if t.distance > 0.0 { 1.0 } else { 0.0 },
            ]
        }),
    )
}

fn params(eye: &Eye, layers: u32) -> LdiParamsGpu {
    LdiParamsGpu {
        view_proj: eye.view_proj.to_cols_array_2d(),
        inv_view_proj: eye.view_proj.inverse().to_cols_array_2d(),
        eye: eye.position.extend(1.0).to_array(),
        size: [eye.width, eye.height, layers, march::max_steps(eye)],
        tests: [TOLERANCE, THICKNESS, TOLERANCE, 0.0],
        bounds_min: [-20.0, -20.0, -20.0, 0.0],
        bounds_max: [20.0, 20.0, 20.0, 0.0],
    }
}

/// The rays: view rays refracted into the glass sphere (inside) and rays from around the
/// glass sphere into the scene (outside), in every mode that applies.
fn cases(eye: &Eye, scene_ldi: &Ldi) -> Vec<[[f32; 4]; 2]> {
    let mut cases = Vec::new();
    for y in (0..H).step_by(3) {
        for x in (0..W).step_by(3) {
            let front = scene_ldi.get(x, y, 0);
            let view = eye.pixel_ray(x, y);
            if front.distance > 0.0 && front.object == 0 {
                let p = eye.position + view * front.distance;
                let dir = gpu::prelude::refract_dir(view, front.normal, 1.0 / 1.5).truncate();
                for mode in [0.0, 1.0, 2.0] {
                    cases.push([p.extend(mode).to_array(), dir.extend(1.0).to_array()]);
                }
            }
            // A ray from a point near the glass sphere outward, away from the eye.
            let origin = Vec3::new(x as f32 / W as f32 - 0.5, y as f32 / H as f32 - 0.5, 1.2);
            let dir = (Vec3::new(0.8, -0.3, -3.0) - origin + Vec3::new(0.0, 0.0, x as f32 * 0.05))
                .normalize();
            for mode in [0.0, 1.0] {
                for side in [0.0, 2.0] {
                    cases.push([origin.extend(mode).to_array(), dir.extend(side).to_array()]);
                }
            }
            cases.push([origin.extend(3.0).to_array(), dir.extend(2.0).to_array()]);
        }
    }
    cases
}

fn twin(eye: &Eye, scene_ldi: &Ldi, refractor_ldi: &Ldi, case: &[[f32; 4]; 2]) -> [f32; 4] {
    let origin = Vec4::from(case[0]);
    let dir = Vec4::from(case[1]);
    let state = RayState {
        side: match dir.w as u32 {
            0 => Side::Outside,
            1 => Side::Inside,
            _ => Side::Any,
        },
        t_skip: TOLERANCE,
    };
    let range = gpu::prelude::ray_box(
        origin.truncate(),
        dir.truncate(),
        Vec3::splat(-20.0),
        Vec3::splat(20.0),
    );
    let Some(seg) = march::clip(
        eye,
        origin.truncate(),
        dir.truncate(),
        (range.x.max(0.0), range.y),
        2.0 * TOLERANCE,
    ) else {
        return [0.0; 4];
    };
    let hit = match origin.w {
        0.0 => march::march_dda(scene_ldi, eye, &seg, THICKNESS, state).0,
        1.0 => march::march_lines(scene_ldi, eye, &seg, TOLERANCE, state).0,
        2.0 => march::march_monotone(refractor_ldi, eye, &seg, 1, state.t_skip),
        _ => march::march_shadow(scene_ldi, eye, &seg, TOLERANCE, state.t_skip),
    };
    hit.map_or([0.0; 4], |h| [h.t, h.layer as f32, h.x as f32, h.y as f32])
}

#[test]
fn the_wgsl_march_finds_the_twins_hits() {
    let _lock = testkit::gpu_lock();
    let ctx = testkit::context();
    let eye = eye();
    let layers = 4;
    let scene_ldi = Ldi::of_spheres(&eye, layers, &spheres());
    let refractor_ldi = Ldi::of_spheres(&eye, layers, &spheres()[..1]);
    let (scene_layers, scene_surfaces) = upload(ctx, &scene_ldi);
    let (refr_layers, refr_surfaces) = upload(ctx, &refractor_ldi);
    let uniform = gpu::Uniform::new(ctx, "ldi", &params(&eye, layers));
    let kinds = ctx
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("material kinds"),
            // Object 0 glass, object 1 diffuse.
            contents: bytemuck::cast_slice(&[2u32, 0]),
            usage: wgpu::BufferUsages::STORAGE,
        });
    let views: Vec<_> = [&scene_layers, &scene_surfaces, &refr_layers, &refr_surfaces]
        .iter()
        .map(|t| {
            t.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2Array),
                ..Default::default()
            })
        })
        .collect();
    let layer_type = gpu::bind::texture(wgpu::TextureViewDimension::D2Array, false);
    let mut extra = vec![(gpu::bind::uniform(), uniform.binding())];
    extra.extend(views.iter().map(|v| (layer_type, gpu::bind::view(v))));
    extra.push((gpu::bind::storage(true), kinds.as_entire_binding()));

    let cases = cases(&eye, &scene_ldi);
    let source = format!(
        "{KERNEL_BINDINGS}\n{}{}",
        kernel_header("RayCase", "vec4f"),
        kernel_entry("march_kernel", MARCH_BODY)
    );
    let imports = [&march::LDI];
    let kernel = gpu::wgsl::Shader::new("march kernel", &source)
        .importing(&imports)
        .with_defs(&KERNEL_LDI_DEFS);
    let gpu_hits: Vec<[f32; 4]> =
        run_kernel_with(ctx, kernel, "march_kernel", &cases, 1, &extra).expect("kernel");
    let mut same = 0;
    let mut hits = 0;
    for (case, got) in cases.iter().zip(&gpu_hits) {
        let want = twin(&eye, &scene_ldi, &refractor_ldi, case);
        hits += (want[0] > 0.0) as usize;
        let agree = (got[0] > 0.0) == (want[0] > 0.0)
            && got[1..] == want[1..]
            && (got[0] - want[0]).abs() <= 1e-3 * want[0].abs().max(1.0);
        if agree {
            same += 1;
        } else {
            println!("case {case:?}: gpu {got:?} twin {want:?}");
        }
    }
    println!("{same} of {} cases agree ({hits} hits)", cases.len());
    assert!(hits > cases.len() / 3, "too few hits to test: {hits}");
    // Samples that sit on a test's threshold may fall either way in f32 on two devices.
    assert!(
        same as f64 >= 0.99 * cases.len() as f64,
        "{same} of {} agree",
        cases.len()
    );
}

/// A kernel importing `screen_photons::splat_weight`, the module the splat pass imports.
fn weight_kernel(source: &str) -> gpu::wgsl::Shader<'_> {
    static WEIGHT: [&gpu::wgsl::Module; 1] = [&screen_photons::splat::WEIGHT];
    gpu::wgsl::Shader::new("splat weight kernel", source).importing(&WEIGHT)
}

/// A kernel module over splat_weight.wgsl: `inputs` of `input`, `outputs` of `output`,
/// entry point `entry` running `body` for element `i`.
fn weight_kernel_source(input: &str, output: &str, entry: &str, body: &str) -> String {
    format!(
        "#import screen_photons::splat_weight::{{footprint_kernel, footprint_matrix, \
         footprint_reach, footprint_tangent, splat_weight}}\n{}{}",
        kernel_header(input, output),
        kernel_entry(entry, body)
    )
}

#[test]
fn the_wgsl_splat_weight_matches_the_twin() {
    let _lock = testkit::gpu_lock();
    let ctx = testkit::context();
    let source = weight_kernel_source(
        "array<vec4f, 3>",
        "vec2f",
        "weight_kernel",
        "let c = inputs[i]; outputs[i] = splat_weight(c[0].xyz, normalize(c[1].xyz), c[2].xyz, \
         normalize(vec3f(c[0].w, c[1].w, c[2].w)), 0.4);",
    );
    let eye = Vec3::new(0.0, 1.0, 3.0);
    let mut cases = Vec::new();
    for i in 0..200 {
        let f = i as f32 * 0.37;
        let c = Vec3::new(f.sin() * 0.5, -0.2 + (f * 1.3).cos() * 0.1, (f * 0.7).sin());
        let view = (c + Vec3::new((f * 2.1).sin(), (f * 1.7).cos(), (f * 0.3).sin()) * 0.3 - eye)
            .normalize();
        let n = Vec3::new((f * 0.9).sin() * 0.5, 1.0, (f * 1.1).cos() * 0.5).normalize();
        cases.push([
            eye.extend(n.x).to_array(),
            view.extend(n.y).to_array(),
            c.extend(n.z).to_array(),
        ]);
    }
    let got: Vec<[f32; 2]> =
        run_kernel(ctx, weight_kernel(&source), "weight_kernel", &cases, 1).expect("kernel");
    let mut nonzero = 0;
    for (case, got) in cases.iter().zip(&got) {
        let n = Vec3::new(case[0][3], case[1][3], case[2][3]).normalize();
        let (w, tau) = screen_photons::splat::weight(
            Vec4::from(case[0]).truncate(),
            Vec4::from(case[1]).truncate().normalize(),
            Vec4::from(case[2]).truncate(),
            n,
            0.4,
        );
        nonzero += (w > 0.0) as usize;
        assert!(
            (got[0] - w).abs() <= 1e-3 * w.max(1.0),
            "{case:?}: {got:?} vs {w}"
        );
        assert!(
            (got[1] - tau).abs() <= 1e-4 * tau.max(1.0),
            "{case:?}: {got:?} vs {tau}"
        );
    }
    assert!(nonzero > 50, "only {nonzero} cases inside a splat");
}

/// The footprint functions of splat_weight.wgsl (`footprint_matrix`, `footprint_reach`,
/// `footprint_kernel`, `footprint_tangent`) against their twins in `splat.rs`, on cells of
/// every size and tilt, capped ones included.
#[test]
fn the_wgsl_footprints_match_the_twins() {
    use glam::Vec2;
    use screen_photons::splat;
    let _lock = testkit::gpu_lock();
    let ctx = testkit::context();
    let source = weight_kernel_source(
        "array<vec4f, 2>",
        "vec4f",
        "footprint_kernel_test",
        "let c = inputs[i]; let m = footprint_matrix(c[0].x, c[0].yz, vec2f(c[0].w, c[1].x)); \
         let t = footprint_tangent(normalize(vec3f(c[1].w, 0.7, -0.4))); \
         outputs[2u * i] = vec4f(m, footprint_reach(m)); \
         outputs[2u * i + 1u] = vec4f(footprint_kernel(c[1].yz, m), t);",
    );
    let mut cases = Vec::new();
    for i in 0..256 {
        let f = i as f32 * 0.61;
        let s = 0.01 + 0.05 * (f * 0.3).sin().abs();
        // Cells from none to far past the cap, at every angle.
        let scale = [0.0, 0.01, 0.1, 1.0][i % 4];
        let ex = Vec2::new(f.cos(), f.sin()) * scale;
        let ey = Vec2::new(-(f * 1.7).sin(), (f * 1.3).cos()) * scale * 0.3;
        let u = Vec2::new((f * 2.3).sin(), (f * 0.9).cos()) * 0.1;
        cases.push([[s, ex.x, ex.y, ey.x], [ey.y, u.x, u.y, (f * 1.1).sin()]]);
    }
    let got: Vec<[f32; 4]> = run_kernel(
        ctx,
        weight_kernel(&source),
        "footprint_kernel_test",
        &cases,
        2,
    )
    .expect("kernel");
    let close = |a: f32, b: f32| (a - b).abs() <= 1e-4 * a.abs().max(b.abs()).max(1e-3);
    let mut inside = 0;
    for (case, got) in cases.iter().zip(got.chunks_exact(2)) {
        let [c0, c1] = case;
        let m = splat::footprint_matrix(c0[0], Vec2::new(c0[1], c0[2]), Vec2::new(c0[3], c1[0]));
        let reach = splat::footprint_reach(m);
        let k = splat::footprint_kernel(Vec2::new(c1[1], c1[2]), m);
        let t = splat::footprint_tangent(Vec3::new(c1[3], 0.7, -0.4).normalize());
        inside += (k > 0.0) as usize;
        let want = [m[0], m[1], m[2], reach, k, t.x, t.y, t.z];
        let got = [got[0], got[1]].concat();
        assert!(
            want.iter().zip(&got).all(|(w, g)| close(*w, *g)),
            "{case:?}: gpu {got:?}, twin {want:?}"
        );
    }
    assert!(inside > 50, "only {inside} offsets inside a footprint");
}

/// The technique's own marchers, in place: the paper's line marcher (lines drawn into rows,
/// the row reduction), its single-shader alternative and the compute DDA, run by
/// `screen-photons/lines`, `/shader` and `/dda` on a real frame (`bounces = 0`: the hit buffer holds the first hits of the transfer map's photons),
/// against the twin's `march_lines` and `march_dda` on the same photons over the same LDI
/// read back from the GPU.
#[test]
fn the_marchers_in_a_frame_find_the_twins_first_hits() {
    use scene::Technique;
    use screen_photons::{ScreenPhotons, technique::variants};
    let _lock = testkit::gpu_lock();
    let ctx = testkit::context();
    for spec in ["cornell-sphere", "pool"] {
        let scene = scene::load(spec).unwrap();
        for name in ["lines", "shader", "dda"] {
            let mut t =
                ScreenPhotons::new(variants().into_iter().find(|v| v.name == name).unwrap());
            t.set_param("bounces", 0.0).unwrap();
            t.set_param("photons", 96.0).unwrap();
            testkit::render(&mut t, &scene, testkit::Shot::along_path(&scene, 0.0, 64));
            let params = t.last_ldi_params().unwrap();
            let [width, height, layers, _] = params.size;
            let eye = Eye {
                view_proj: glam::Mat4::from_cols_array_2d(&params.view_proj),
                position: Vec4::from(params.eye).truncate(),
                width,
                height,
            };
            let mut ldi = Ldi::new(width, height, layers);
            for l in 0..layers {
                let normals = t.last_ldi_layer(ctx, l).unwrap();
                let surfaces = t.last_ldi_surface(ctx, l).unwrap();
                for (p, (n, s)) in normals.iter().zip(&surfaces).enumerate() {
                    let object = s[0] as u32;
                    let material = &scene.objects[object as usize].material;
                    ldi.set(
                        p as u32 % width,
                        p as u32 / width,
                        l,
                        march::Texel {
                            distance: n[3],
                            normal: Vec4::from(*n).truncate(),
                            object,
                            specular: n[3] > 0.0 && material.is_specular(),
                            glass: n[3] > 0.0 && matches!(material, scene::Material::Glass { .. }),
                        },
                    );
                }
            }
            let [tolerance, thickness, t_skip, _] = params.tests;
            let (lo, hi) = (
                Vec4::from(params.bounds_min).truncate(),
                Vec4::from(params.bounds_max).truncate(),
            );
            let photons = t.last_photons(ctx).unwrap();
            let hits = t.last_hits(ctx).unwrap();
            let (mut marched, mut same, mut found) = (0, 0, 0);
            for (photon, got) in photons.iter().zip(&hits) {
                if Vec4::from(photon[2]).truncate().max_element() <= 0.0 {
                    continue; // no photon in this transfer-map pixel
                }
                marched += 1;
                let (origin, dir) = (Vec4::from(photon[0]).truncate(), Vec4::from(photon[1]));
                let state = RayState {
                    side: if dir.w > 0.5 {
                        Side::Inside
                    } else {
                        Side::Outside
                    },
                    t_skip,
                };
                let range = gpu::prelude::ray_box(origin, dir.truncate(), lo, hi);
                let want = march::clip(
                    &eye,
                    origin,
                    dir.truncate(),
                    (range.x.max(0.0), range.y),
                    2.0 * tolerance,
                )
                .and_then(|seg| match name {
                    "lines" | "shader" => march::march_lines(&ldi, &eye, &seg, tolerance, state).0,
                    _ => march::march_dda(&ldi, &eye, &seg, thickness, state).0,
                })
                .map_or([0.0; 4], |h| [h.t, h.layer as f32, h.x as f32, h.y as f32]);
                found += (want[0] > 0.0) as usize;
                let agree = (got[0] > 0.0) == (want[0] > 0.0)
                    && got[1..] == want[1..]
                    && (got[0] - want[0]).abs() <= 1e-3 * want[0].abs().max(1.0);
                same += agree as usize;
            }
            println!("{spec} {name}: {same} of {marched} photons agree ({found} hits)");
            assert!(
                found > marched / 10,
                "{spec} {name}: {found} hits of {marched}"
            );
            // Samples on a test's threshold may fall either way in f32 on two devices.
            assert!(
                same as f64 >= 0.99 * marched as f64,
                "{spec} {name}: {same} of {marched} agree"
            );
        }
    }
}

/// One beam-fragment case: the medium, the view, the beam, the pixel and its surface.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct BeamCase {
    medium: scene::medium::MediumGpu,
    view_proj: [[f32; 4]; 4],
    eye: [f32; 4],
    forward: [f32; 4],
    size: [u32; 4],
    origin: [f32; 4],
    dir: [f32; 4],
    power: [f32; 4],
    /// xy pixel centre, z surface distance.
    pixel: [f32; 4],
}

/// The bands of photon beams (`beam.wgsl`'s `beam_band` and `beam_fragment`) against the twin
/// (`screen_photons::shafts`): random media, eyes inside and outside them, beams through them
/// and the pixels of each beam's band; and a mutated tent is detected.
#[test]
fn the_wgsl_beam_fragments_match_the_twin() {
    use screen_photons::shafts::{self, Beam, ShaftView, beam_band, beam_fragment};
    let _lock = testkit::gpu_lock();
    let ctx = testkit::context();
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut rnd = move |lo: f32, hi: f32| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        lo + (hi - lo) * ((state % 1_000_000) as f32 / 1_000_000.0)
    };
    let mut cases = Vec::new();
    let mut twins = Vec::new();
    while cases.len() < 4096 {
        let min = Vec3::new(rnd(-3.0, -1.0), rnd(-2.0, -1.0), rnd(-5.0, -3.0));
        let medium = scene::Medium {
            name: "m".into(),
            min,
            max: min + Vec3::new(rnd(1.0, 4.0), rnd(1.0, 3.0), rnd(1.0, 4.0)),
            scattering: Vec3::new(rnd(0.05, 0.5), rnd(0.05, 0.5), rnd(0.05, 0.5)),
            absorption: Vec3::new(rnd(0.0, 0.3), rnd(0.0, 0.3), rnd(0.0, 0.3)),
            anisotropy: rnd(-0.8, 0.8),
        };
        let camera = Camera {
            eye: Vec3::new(rnd(-1.0, 1.0), rnd(-1.5, 0.5), rnd(-2.0, 1.0)),
            target: Vec3::new(rnd(-1.0, 1.0), rnd(-2.0, 0.0), -6.0),
            up: Vec3::Y,
            fov_y_deg: rnd(40.0, 80.0),
            orthographic: None,
        };
        let view = ShaftView::new(&camera, 64, 48);
        let origin = Vec3::new(rnd(-2.0, 2.0), rnd(0.0, 1.0), rnd(-5.0, -2.0));
        let beam = Beam {
            origin,
            dir: (Vec3::new(rnd(-2.0, 2.0), -2.0, rnd(-5.0, -2.0)) - origin).normalize(),
            length: rnd(1.0, 4.0),
            power: Vec3::new(rnd(0.1, 1.0), rnd(0.1, 1.0), rnd(0.1, 1.0)),
        };
        let Some(band) = beam_band(&view, &medium, &beam) else {
            continue;
        };
        // Pixels along and beside the band.
        for _ in 0..16 {
            let f = rnd(0.0, 1.0);
            let p = band.p_start + (band.p_end - band.p_start) * f;
            let pixel = (p + Vec3::new(rnd(-2.0, 2.0), rnd(-2.0, 2.0), 0.0).truncate()).floor()
                + glam::Vec2::splat(0.5);
            let surface = if rnd(0.0, 1.0) < 0.2 {
                rnd(0.1, 4.0)
            } else {
                1e30
            };
            twins.push(beam_fragment(&view, &medium, &beam, &band, pixel, surface));
            cases.push(BeamCase {
                medium: scene::Medium::gpu(Some(&medium)),
                view_proj: view.view_proj.to_cols_array_2d(),
                eye: view.eye.extend(view.pixel_area).to_array(),
                forward: view.forward.extend(0.0).to_array(),
                size: [view.width, view.height, 0, 0],
                origin: beam.origin.extend(1.0).to_array(),
                dir: beam.dir.extend(beam.length).to_array(),
                power: beam.power.extend(0.0).to_array(),
                pixel: [pixel.x, pixel.y, surface, 0.0],
            });
        }
    }
    let source = format!(
        "#import scene::medium::Medium\n\
         #import screen_photons::beam::{{Beam, ShaftView, beam_band, beam_fragment}}\n\
         struct BeamCase {{ medium: Medium, view_proj: mat4x4f, eye: vec4f, forward: vec4f, \
         size: vec4u, origin: vec4f, dir: vec4f, power: vec4f, pixel: vec4f }};\n\
         {header}\n{entry}",
        header = kernel_header("BeamCase", "vec4f"),
        entry = kernel_entry(
            "beam_kernel",
            "    let c = inputs[i];\n    \
             let shaft = ShaftView(c.view_proj, c.eye, c.forward, c.size);\n    \
             let b = Beam(c.origin, c.dir, c.power);\n    \
             let band = beam_band(shaft, c.medium, b);\n    \
             outputs[i] = vec4f(beam_fragment(shaft, c.medium, b, band, c.pixel.xy, c.pixel.z), \
             select(0.0, 1.0, band.ok));",
        ),
    );
    // The module with `tent` as the band's profile (a mutation test's broken copy).
    let beam_module = |tent: &str| {
        let text = shafts::BEAM_WGSL.replace("max(1.0 - abs(across) / BAND_HALF_WIDTH, 0.0)", tent);
        shafts::BEAM.with_source(text)
    };
    let compare = |tent: &str| {
        let got: Vec<Vec4> = {
            let beam = beam_module(tent);
            let imports = [&beam];
            let kernel = gpu::wgsl::Shader::new("beam", &source).importing(&imports);
            run_kernel(ctx, kernel, "beam_kernel", &cases, 1).expect("kernel")
        };
        let lit = twins.iter().filter(|t| t.max_element() > 0.0).count();
        let bad = got
            .iter()
            .zip(&twins)
            .filter(|(g, t)| {
                g.w != 1.0
                    || (g.truncate() - **t).abs().max_element() > 1e-5 + 2e-3 * t.max_element()
            })
            .count();
        (bad, lit)
    };
    let (bad, lit) = compare("max(1.0 - abs(across) / BAND_HALF_WIDTH, 0.0)");
    println!(
        "beam fragments: {bad} of {} differ ({lit} lit)",
        cases.len()
    );
    assert!(lit > 1000, "only {lit} cases light their pixel");
    assert_eq!(bad, 0);
    let (bad, _) = compare("max(1.0 - abs(across) / (2.0 * BAND_HALF_WIDTH), 0.0)");
    assert!(bad > 500, "a wider tent went unnoticed ({bad} differ)");
}
