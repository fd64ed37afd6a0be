//! GPU conformance of `shaders/interior.wgsl` (`cast_rooms`) against its Rust twin
//! (`interior_mapping::rooms::cast_rooms`): random rays (negative coordinates, axis-parallel
//! directions, displaced walls, starts on planes) run in a compute shader and are compared.
//!
//! Tolerances: `t` and the hit point within `1e-4 (1 + |t|)` relative; family, plane and room
//! index exact. A case may disagree only where the CPU itself is within rounding of a
//! decision (two families within 1e-4 of a tie, or a plane within 1e-3 rooms of the
//! `ROOM_EPS` threshold), since a GPU may fuse multiply-adds; at most 1% of the cases.

use glam::{IVec3, Vec3};
use gpu::wgpu;
use gpu::wgpu::util::DeviceExt;
use interior_mapping::rooms::*;

const KERNEL: &str = r#"
@group(0) @binding(0) var<storage, read> cases: array<vec4f>;
@group(0) @binding(1) var<storage, read_write> results: array<vec4u>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) g: vec3u) {
    let i = g.x;
    if (i >= arrayLength(&results) / 3u) { return; }
    let o = cases[4u * i];
    let d = cases[4u * i + 1u];
    let s = cases[4u * i + 2u];
    let m = cases[4u * i + 3u];
    let hit = cast_rooms(o.xyz, d.xyz, s.xyz, m.xyz, bitcast<u32>(o.w));
    results[3u * i] = vec4u(hit.family, bitcast<u32>(hit.t), bitcast<u32>(hit.plane), 0u);
    results[3u * i + 1u] = bitcast<vec4u>(vec4f(hit.point, 0.0));
    results[3u * i + 2u] = bitcast<vec4u>(vec4i(hit.room, 0));
}
"#;

struct Case {
    origin: Vec3,
    dir: Vec3,
    size: Vec3,
    disp: Vec3,
    seed: u32,
}

fn cases() -> Vec<Case> {
    let mut state = 12345u32;
    let mut next = || {
        state = gpu::prelude::pcg_hash(state);
        state as f32 / u32::MAX as f32
    };
    let mut out = Vec::new();
    for i in 0..4096u32 {
        let mut origin = Vec3::new(next(), next(), next()) * 400.0 - 200.0;
        let mut dir = Vec3::new(next(), next(), next()) * 2.0 - 1.0;
        let size = Vec3::new(next(), next(), next()) * 5.0 + 0.3;
        if i % 4 == 1 {
            dir[(i / 4 % 3) as usize] = 0.0;
        }
        if i % 8 == 3 {
            // Start exactly on a plane (a facade coinciding with a wall plane).
            let a = (i / 8 % 3) as usize;
            origin[a] = (origin[a] / size[a]).round() * size[a];
        }
        let disp = if i % 2 == 0 {
            Vec3::ZERO
        } else {
            Vec3::new(next(), next(), next()) * MAX_DISPLACEMENT
        };
        if dir.length() < 1e-3 {
            dir = Vec3::X;
        }
        out.push(Case {
            origin,
            dir: dir.normalize(),
            size,
            disp,
            seed: i * 7919,
        });
    }
    out
}

#[test]
fn wgsl_cast_rooms_matches_twin() {
    let ctx =
        gpu::Context::new().unwrap_or_else(|e| panic!("conformance test needs a GPU adapter: {e}"));
    let cases = cases();
    let mut input: Vec<[f32; 4]> = Vec::new();
    for c in &cases {
        input.push([c.origin.x, c.origin.y, c.origin.z, f32::from_bits(c.seed)]);
        input.push(c.dir.extend(0.0).to_array());
        input.push(c.size.extend(0.0).to_array());
        input.push(c.disp.extend(0.0).to_array());
    }
    let device = &ctx.device;
    let module = gpu::shader_with_prelude(
        &ctx,
        "interior conformance",
        &format!("{}\n{KERNEL}", interior_mapping::INTERIOR_WGSL),
    );
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("interior conformance"),
        layout: None,
        module: &module,
        entry_point: Some("main"),
        compilation_options: Default::default(),
        cache: None,
    });
    let cases_buf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("cases"),
        contents: bytemuck::cast_slice(&input),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let results = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("results"),
        size: (cases.len() * 48) as u64,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let bind = gpu::bind::group(
        &ctx,
        "interior conformance",
        &pipeline.get_bind_group_layout(0),
        &[cases_buf.as_entire_binding(), results.as_entire_binding()],
    );
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.dispatch_workgroups((cases.len() as u32).div_ceil(64), 1, 1);
    }
    ctx.queue.submit([encoder.finish()]);
    let bytes = gpu::read_buffer(&ctx, &results).expect("read back");
    let words: &[u32] = bytemuck::cast_slice(&bytes);

    let mut disagreements = 0;
    for (i, c) in cases.iter().enumerate() {
        let w = &words[12 * i..12 * i + 12];
        let (family, t, plane) = (w[0], f32::from_bits(w[1]), w[2] as i32);
        let point = Vec3::new(
            f32::from_bits(w[4]),
            f32::from_bits(w[5]),
            f32::from_bits(w[6]),
        );
        let room = IVec3::new(w[8] as i32, w[9] as i32, w[10] as i32);
        let cpu = cast_rooms(c.origin, c.dir, c.size, c.disp, c.seed);
        assert!(
            t.is_finite() && point.is_finite(),
            "case {i}: non-finite GPU result"
        );
        let tol = 1e-4 * (1.0 + cpu.t.abs());
        let same = family == cpu.family
            && plane == cpu.plane
            && room == cpu.room
            && (t - cpu.t).abs() <= tol
            && (point - cpu.point).abs().max_element()
                <= 1e-4 * (1.0 + cpu.point.abs().max_element());
        if !same {
            // Accept only ill-conditioned decisions.
            let u = c.origin / c.size;
            let near_eps = (0..3).any(|a| {
                let (k, _) =
                    room_next_plane(a as u32, u[a], c.dir[a] / c.size[a], c.disp[a], c.seed);
                (room_plane_pos(a as u32, k - 1, c.disp[a], c.seed) - u[a]).abs() < 1e-3
                    || (room_plane_pos(a as u32, k + 1, c.disp[a], c.seed) - u[a]).abs() < 1e-3
                    || (room_plane_pos(a as u32, k, c.disp[a], c.seed) - u[a]).abs() < 1e-3
            });
            let near_tie = (t - cpu.t).abs() <= tol;
            assert!(
                near_eps || near_tie,
                "case {i}: GPU ({family}, {t}, {plane}, {room}, {point}) vs CPU {cpu:?}"
            );
            disagreements += 1;
        }
    }
    assert!(
        disagreements * 100 <= cases.len(),
        "{disagreements} ill-conditioned disagreements"
    );
    eprintln!(
        "{} cases, {disagreements} ill-conditioned disagreements",
        cases.len()
    );
}
