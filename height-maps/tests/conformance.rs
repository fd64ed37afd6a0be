//! GPU conformance of the height-map search (`shaders/height_search.wgsl`) against its Rust
//! twin (`height_maps::search`): two maps sampled from analytic solids (an ellipsoid and a
//! vase) in one texture array, rays from outside (the billboard's view: origin in front on
//! the axis) and from inside, with the paper's binary search and with a linear bracket.
//!
//! Tolerance: found flags equal and t within 1e-4 (abs) + 1e-4 (rel), normals within 1e-3,
//! except where a sample lands within float rounding of the surface (the two sides may then
//! take different halves of a bracket): at most 1 case in 400 is excused (none differed on
//! lavapipe).
//! `a_mutated_search_is_detected` shows the comparison can fail.

mod common;

use common::*;
use glam::{Vec3, Vec4};
use gpu::wgpu::{self, util::DeviceExt};
use height_maps::search::{
    HEIGHT_SEARCH_WGSL, HeightField, SEARCH, SampledField, Steps, exit_from_inside,
    search_from_outside,
};

const RAYS: usize = 1536;

/// One case: origin (w: layer), direction (w: 0 from outside, 1 from inside), bounds,
/// steps (linear, binary).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Case {
    o: [f32; 4],
    d: [f32; 4],
    bounds: [f32; 4],
    steps: [u32; 4],
}

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 % 1_000_000) as f32 / 1_000_000.0
    }
    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.next()
    }
}

fn maps() -> [SampledField; 2] {
    [sample(&ellipsoid(), 64), sample(&vase(), 64)]
}

fn cases(maps: &[SampledField; 2]) -> Vec<Case> {
    let mut rng = Rng(0x5eed);
    (0..RAYS)
        .map(|i| {
            let layer = i % 2;
            let b = maps[layer].bounds;
            let from_inside = i % 3 == 2;
            let steps = if i % 4 < 2 {
                [0, 8, 0, 0]
            } else {
                [16, 10, 0, 0]
            };
            let (o, d) = if from_inside {
                let o = Vec3::new(
                    rng.range(-0.3, 0.3),
                    rng.range(-0.5, 0.5),
                    rng.range(-0.1, 0.1),
                );
                let d = Vec3::new(
                    rng.range(-1.0, 1.0),
                    rng.range(-1.0, 1.0),
                    rng.range(-1.0, 1.0),
                );
                (o, d.normalize())
            } else if i % 3 == 1 {
                // Steep, over the top to behind the plane: what the second search is for.
                let o = Vec3::new(0.0, rng.range(1.5, 3.0), rng.range(1.0, 2.0));
                let target = Vec3::new(
                    rng.range(-0.3, 0.3),
                    rng.range(0.4, 0.9),
                    rng.range(-0.6, 0.0),
                );
                (o, (target - o).normalize())
            } else {
                let o = Vec3::new(0.0, rng.range(-2.0, 2.0), rng.range(1.0, 4.0));
                let target = Vec3::new(
                    rng.range(-0.7, 0.7),
                    rng.range(-1.0, 1.0),
                    rng.range(-0.6, 0.6),
                );
                (o, (target - o).normalize())
            };
            Case {
                o: o.extend(layer as f32).to_array(),
                d: d.extend(if from_inside { 1.0 } else { 0.0 }).to_array(),
                bounds: [b.half_width, b.v_min, b.v_max, b.height],
                steps,
            }
        })
        .collect()
}

/// The twin's answer: (t, found) and the normal.
fn twin(maps: &[SampledField; 2], c: &Case) -> [Vec4; 2] {
    let field = &maps[c.o[3] as usize];
    let o = Vec3::from_slice(&c.o[..3]);
    let d = Vec3::from_slice(&c.d[..3]);
    let steps = Steps {
        linear: c.steps[0],
        binary: c.steps[1],
    };
    let hit = if c.d[3] > 0.5 {
        exit_from_inside(field, o, d, steps)
    } else {
        search_from_outside(field, o, d, steps)
    };
    match hit {
        Some(h) => [Vec4::new(h.t, 1.0, 0.0, 0.0), h.normal.extend(0.0)],
        None => [Vec4::ZERO, Vec4::ZERO],
    }
}

fn kernel() -> String {
    format!(
        "#import height_maps::search::{{HeightBounds, HeightHit, Steps, exit_from_inside, \
         search_from_outside}}\n\
         @group(0) @binding(2) var height_maps: texture_2d_array<f32>;\n\
         struct Case {{ o: vec4f, d: vec4f, bounds: vec4f, steps: vec4u }};\n{}\n{}",
        gpu::compute::kernel_header("Case", "vec4f"),
        gpu::compute::kernel_entry(
            "k_height",
            "    let c = inputs[i];
    let hb = HeightBounds(c.bounds.x, c.bounds.y, c.bounds.z, c.bounds.w);
    let steps = Steps(c.steps.x, c.steps.y);
    var h: HeightHit;
    if (c.d.w > 0.5) {
        h = exit_from_inside(height_maps, i32(c.o.w), hb, c.o.xyz, c.d.xyz, steps);
    } else {
        h = search_from_outside(height_maps, i32(c.o.w), hb, c.o.xyz, c.d.xyz, steps);
    }
    outputs[2u * i] = vec4f(0.0);
    outputs[2u * i + 1u] = vec4f(0.0);
    if (h.found) {
        outputs[2u * i] = vec4f(h.t, 1.0, 0.0, 0.0);
        outputs[2u * i + 1u] = vec4f(h.normal, 0.0);
    }"
        )
    )
}

/// The kernel importing `search` as `height_maps::search` (the module the technique imports,
/// or a mutated copy of it) on the maps and cases.
fn run_gpu(maps: &[SampledField; 2], cases: &[Case], search: &gpu::wgsl::Module) -> Vec<Vec4> {
    let ctx = testkit::context();
    let (w, h) = (maps[0].width, maps[0].height);
    let data: Vec<f32> = maps
        .iter()
        .flat_map(|m| m.texels.iter().flatten().copied())
        .collect();
    let texture = ctx.device.create_texture_with_data(
        &ctx.queue,
        &wgpu::TextureDescriptor {
            label: Some("height maps"),
            size: wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: 2,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: height_maps::map::HEIGHT_MAP_FORMAT,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        bytemuck::cast_slice(&data),
    );
    let view = texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    });
    let kernel = kernel();
    gpu::compute::run_kernel_with(
        ctx,
        gpu::wgsl::Shader::new("k_height", &kernel).importing(&[search]),
        "k_height",
        cases,
        2,
        &[(
            gpu::bind::texture(wgpu::TextureViewDimension::D2Array, false),
            gpu::bind::view(&view),
        )],
    )
    .unwrap()
}

/// Cases where GPU and twin disagree.
fn mismatches(maps: &[SampledField; 2], cases: &[Case], gpu: &[Vec4]) -> usize {
    cases
        .iter()
        .enumerate()
        .filter(|(i, c)| {
            let [tw, tn] = twin(maps, c);
            let (gw, gn) = (gpu[2 * i], gpu[2 * i + 1]);
            let same_found = (tw.y > 0.5) == (gw.y > 0.5);
            let same_t = (tw.x - gw.x).abs() <= 1e-4 + 1e-4 * tw.x.abs();
            let same_n = (tn - gn).length() <= 1e-3;
            !(same_found && same_t && same_n)
        })
        .count()
}

#[test]
fn the_wgsl_search_matches_its_twin() {
    let _lock = testkit::gpu_lock();
    let maps = maps();
    let cases = cases(&maps);
    let gpu = run_gpu(&maps, &cases, &SEARCH);
    let found = cases.iter().filter(|c| twin(&maps, c)[0].y > 0.5).count();
    let bad = mismatches(&maps, &cases, &gpu);
    println!("{} cases, {found} hits, {bad} mismatches", cases.len());
    assert!(found > cases.len() / 3, "too few hits to compare: {found}");
    assert!(
        bad * 400 <= cases.len(),
        "{bad} of {} cases differ",
        cases.len()
    );
}

#[test]
fn a_mutated_search_is_detected() {
    let _lock = testkit::gpu_lock();
    let maps = maps();
    let cases = cases(&maps);
    for (what, from, to) in [
        ("the reflection through the plane", "abs(p.z) <", "p.z <"),
        (
            "the second search",
            "t < 0.0 && s.case_id == CASE_IN_FRONT",
            "false",
        ),
        (
            "the bracket's midpoint",
            "let m = 0.5 * (a + b);",
            "let m = 0.4 * a + 0.6 * b;",
        ),
    ] {
        assert!(HEIGHT_SEARCH_WGSL.contains(from), "{what}: not in the WGSL");
        let mutated = HEIGHT_SEARCH_WGSL.replace(from, to);
        let gpu = run_gpu(&maps, &cases, &SEARCH.with_source(mutated));
        let bad = mismatches(&maps, &cases, &gpu);
        assert!(
            bad * 400 > cases.len(),
            "{what}: mutation not detected ({bad} mismatches)"
        );
    }
}

#[test]
fn the_maps_hold_their_fields() {
    // The twin reads what the analytic field says at texel centres.
    let maps = maps();
    let f = ellipsoid();
    let (h, _) = maps[0].sample(0.0, 0.0);
    assert!((h - f.sample(0.0, 0.0).0).abs() < 1e-3);
}
