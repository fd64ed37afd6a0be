//! GPU conformance of `shaders/interior.wgsl` (`cast_rooms`) against its Rust twin
//! (`interior_mapping::rooms::cast_rooms`): random rays (negative coordinates, axis-parallel
//! directions, displaced walls, starts on planes) run in a compute shader and are compared.
//!
//! Tolerances: `t` and the hit point within `1e-4 (1 + |t|)` relative; family, plane and room
//! index exact. A case may disagree only where the CPU itself is within rounding of a
//! decision (two families within 1e-4 of a tie, or a plane within 1e-3 rooms of the
//! `ROOM_EPS` threshold), since a GPU may fuse multiply-adds; at most 1% of the cases.

use glam::{IVec3, Vec3};
use gpu::compute::{kernel_entry, kernel_header, run_kernel};
use interior_mapping::rooms::*;

/// A case: (origin, seed bits), direction, room size, displacement.
type Input = [[f32; 4]; 4];
/// (family, t bits, plane, -), (hit point, -) bits, (room, -).
type Output = [[u32; 4]; 3];

/// A kernel importing `interior_mapping::rooms`, the module the technique's shader imports.
fn rooms_kernel(source: &str) -> gpu::wgsl::Shader<'_> {
    static ROOMS: [&gpu::wgsl::Module; 1] = [&interior_mapping::ROOMS];
    gpu::wgsl::Shader::new("rooms kernel", source).importing(&ROOMS)
}

/// `cast_rooms` on each case, `main` of the kernel convention of `gpu::compute`.
fn kernel() -> String {
    kernel_header("array<vec4f, 4>", "array<vec4u, 3>")
        + &kernel_entry(
            "main",
            r#"
    let o = inputs[i][0];
    let d = inputs[i][1];
    let s = inputs[i][2];
    let m = inputs[i][3];
    let hit = cast_rooms(o.xyz, d.xyz, s.xyz, m.xyz, bitcast<u32>(o.w));
    outputs[i][0] = vec4u(hit.family, bitcast<u32>(hit.t), bitcast<u32>(hit.plane), 0u);
    outputs[i][1] = bitcast<vec4u>(vec4f(hit.point, 0.0));
    outputs[i][2] = bitcast<vec4u>(vec4i(hit.room, 0));"#,
        )
}

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
    let cases = cases();
    let input: Vec<Input> = cases
        .iter()
        .map(|c| {
            [
                [c.origin.x, c.origin.y, c.origin.z, f32::from_bits(c.seed)],
                c.dir.extend(0.0).to_array(),
                c.size.extend(0.0).to_array(),
                c.disp.extend(0.0).to_array(),
            ]
        })
        .collect();
    let source = format!("#import interior_mapping::rooms::cast_rooms\n{}", kernel());
    let results: Vec<Output> =
        run_kernel(testkit::context(), rooms_kernel(&source), "main", &input, 1)
            .unwrap_or_else(|e| panic!("interior conformance kernel: {e}"));

    let mut disagreements = 0;
    for (i, c) in cases.iter().enumerate() {
        let [w, p, r] = results[i];
        let (family, t, plane) = (w[0], f32::from_bits(w[1]), w[2] as i32);
        let point = Vec3::new(
            f32::from_bits(p[0]),
            f32::from_bits(p[1]),
            f32::from_bits(p[2]),
        );
        let room = IVec3::new(r[0] as i32, r[1] as i32, r[2] as i32);
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

/// (t bits, family, atlas, -), (point, -) bits, (room, -), (lookup, -) bits.
type CubemapOutput = [[u32; 4]; 4];

/// `cubemap_room` (the cube-map interiors) against its twin on the same rays (regular grid),
/// with and without variation. Tolerances: t, point and lookup within 1e-4 relative; atlas
/// exact; room exact unless the start is within 1e-3 rooms of a boundary (the floor() of a
/// division a GPU may round differently); family exact unless the exit is within 1e-3 of a
/// room edge (two faces tie, a fused multiply-add may pick the other). At most 1% of the cases
/// may be such ties.
#[test]
fn wgsl_cubemap_room_matches_twin() {
    let cases = cases();
    let input: Vec<Input> = cases
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let variants = if i % 2 == 0 { 1.0 } else { 4.0 };
            [
                [c.origin.x, c.origin.y, c.origin.z, f32::from_bits(c.seed)],
                c.dir.extend(0.0).to_array(),
                c.size.extend(variants).to_array(),
                [0.0; 4],
            ]
        })
        .collect();
    let kernel = kernel_header("array<vec4f, 4>", "array<vec4u, 4>")
        + &kernel_entry(
            "main",
            r#"
    let o = inputs[i][0];
    let d = inputs[i][1];
    let s = inputs[i][2];
    let hit = cubemap_room(o.xyz, d.xyz, s.xyz, u32(s.w), bitcast<u32>(o.w));
    outputs[i][0] = vec4u(bitcast<u32>(hit.t), hit.family, hit.atlas, 0u);
    outputs[i][1] = bitcast<vec4u>(vec4f(hit.point, 0.0));
    outputs[i][2] = bitcast<vec4u>(vec4i(hit.room, 0));
    outputs[i][3] = bitcast<vec4u>(vec4f(hit.lookup, 0.0));"#,
        );
    let source = format!("#import interior_mapping::rooms::cubemap_room\n{kernel}");
    let results: Vec<CubemapOutput> =
        run_kernel(testkit::context(), rooms_kernel(&source), "main", &input, 1)
            .unwrap_or_else(|e| panic!("cube-map interiors conformance kernel: {e}"));
    let float3 = |v: [u32; 4]| {
        Vec3::new(
            f32::from_bits(v[0]),
            f32::from_bits(v[1]),
            f32::from_bits(v[2]),
        )
    };
    let mut ties = 0;
    for (i, c) in cases.iter().enumerate() {
        let variants = if i % 2 == 0 { 1 } else { 4 };
        let cpu = cubemap_room(c.origin, c.dir, c.size, variants, c.seed);
        let [w, p, r, l] = results[i];
        let (t, family, atlas) = (f32::from_bits(w[0]), w[1], w[2]);
        let (point, lookup) = (float3(p), float3(l));
        let room = IVec3::new(r[0] as i32, r[1] as i32, r[2] as i32);
        assert!(
            t.is_finite() && point.is_finite() && lookup.is_finite(),
            "case {i}: non-finite GPU result"
        );
        let close =
            |a: Vec3, b: Vec3| (a - b).abs().max_element() <= 1e-4 * (1.0 + b.abs().max_element());
        if room != cpu.room {
            // Only where the start lies within rounding of a room boundary (a GPU's division
            // may differ by an ulp there, and floor() decides the room) may the room differ.
            let u = c.origin / c.size;
            let near_plane = (0..3).any(|a| (u[a] - u[a].round()).abs() < 1e-3);
            assert!(near_plane, "case {i}: room {room} vs CPU {cpu:?}");
            ties += 1;
            continue;
        }
        assert_eq!(atlas, cpu.atlas, "case {i}: {cpu:?}");
        assert!(
            (t - cpu.t).abs() <= 1e-4 * (1.0 + cpu.t.abs()) && close(lookup, cpu.lookup),
            "case {i}: GPU t {t} lookup {lookup} vs CPU {cpu:?}"
        );
        if family != cpu.family {
            let a = cpu.lookup.abs();
            let mut sorted = [a.x, a.y, a.z];
            sorted.sort_by(f32::total_cmp);
            assert!(
                sorted[2] - sorted[1] < 1e-3,
                "case {i}: family {family} vs CPU {cpu:?}"
            );
            ties += 1;
        } else {
            assert!(
                close(point, cpu.point),
                "case {i}: point {point} vs {cpu:?}"
            );
        }
    }
    assert!(ties * 100 <= cases.len(), "{ties} ties");
    eprintln!("{} cases, {ties} edge ties", cases.len());
}
