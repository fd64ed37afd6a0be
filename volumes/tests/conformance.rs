//! GPU conformance of `shaders/path_length.wgsl` against its Rust twin
//! (`volumes::path_length`): every function runs in a compute shader on a few thousand
//! deterministic random inputs plus edge cases, and the results are compared with the twin.
//!
//! Tolerances (`|gpu - cpu| <= tol`):
//!
//! | function | tolerance |
//! | --- | --- |
//! | `opacity_from_length` | 2e-5 + 2e-5 relative (`log2`, `sqrt` on the GPU) |
//! | `visible_length` | 1e-6 relative to the inputs (a min, a max and a subtraction) |
//! | `sphere_path_length` | 1e-4 (|o - c| + r + 1) plus twice the rounding of the discriminant's square root, `2 sqrt(8 eps (b^2 + |o - c|^2 + r^2))` (tangent rays are ill-conditioned) |
//! | `billboard_coords` | 1e-4 (|o - c| + 1) / r on u, v and 1e-4 (|o - c| + 1) on t; rays meet the plane at `|dot(d, n)| >= 0.05` |
//! | billboard primitive lengths | 2e-4 (|o - c| + r); where uv lies within 1e-3 of the disc's edge or the pyramid's diagonals the mask may flip and any value in [0, 2R] is accepted |
//! | `slice_alpha` | 1e-4 + 1e-5 / (1 - a_near); when `a_near` is within 1e-4 of 1 (the clamp to an opaque front) any value in [0, 1] is accepted |

use glam::{Vec2, Vec3, Vec4};
use gpu::compute::{kernel_entry, kernel_header};
use gpu::prelude::hash_to_unit;
use volumes::path_length::*;

const RANDOM_CASES: u32 = 4096;
const EPS: f32 = f32::EPSILON;

/// Four `vec4` arguments per case; two `vec4` results.
type Case = [Vec4; 4];
type Output = [Vec4; 2];

/// What the kernels share: argument `k` and result `k` of case `i`, and the billboard's axes.
const HELPERS: &str = r#"
fn arg(i: u32, k: u32) -> vec4f { return inputs[i][k]; }
fn put(i: u32, k: u32, v: vec4f) { outputs[i][k] = v; }

// In-plane axes of a billboard with normal n, rotated by `angle` (the same construction as the
// Rust side of this test).
fn billboard_axes(n: vec3f, angle: f32) -> array<vec3f, 2> {
    var helper = vec3f(0.0, 1.0, 0.0);
    if (abs(n.y) > 0.9) { helper = vec3f(1.0, 0.0, 0.0); }
    let r0 = normalize(cross(helper, n));
    let u0 = cross(n, r0);
    let right = r0 * cos(angle) + u0 * sin(angle);
    return array<vec3f, 2>(right, cross(n, right));
}
"#;

/// One kernel per function: (entry point, body for case `i`).
const KERNELS: [(&str, &str); 6] = [
    // a0 = (t_particle, t_scene, fade, -)
    (
        "k_fade",
        r#"
    let a = arg(i, 0u);
    put(i, 0u, vec4f(depth_fade(a.x, a.y, a.z), 0.0, 0.0, 0.0));"#,
    ),
    // a0 = (len, density, kind, -)
    (
        "k_opacity",
        r#"
    let a = arg(i, 0u);
    put(i, 0u, vec4f(opacity_from_length(u32(a.z), a.x, a.y), 0.0, 0.0, 0.0));"#,
    ),
    // a0 = (t_front, t_back, t_scene, -)
    (
        "k_visible",
        r#"
    let a = arg(i, 0u);
    put(i, 0u, vec4f(visible_length(a.x, a.y, a.z), 0.0, 0.0, 0.0));"#,
    ),
    // a0 = (o, t_scene), a1 = (d, -), a2 = (c, r)
    (
        "k_sphere",
        r#"
    let a0 = arg(i, 0u); let a1 = arg(i, 1u); let a2 = arg(i, 2u);
    put(i, 0u, vec4f(sphere_path_length(a0.xyz, a1.xyz, a2.xyz, a2.w, a0.w), 0.0, 0.0, 0.0));"#,
    ),
    // a0 = (o, t_scene), a1 = (d, texture value), a2 = (c, r), a3 = (normal, angle of right)
    (
        "k_billboard",
        r#"
    let a0 = arg(i, 0u); let a1 = arg(i, 1u); let a2 = arg(i, 2u); let a3 = arg(i, 3u);
    let n = a3.xyz;
    let axes = billboard_axes(n, a3.w);
    let b = billboard_coords(a0.xyz, a1.xyz, a2.xyz, axes[0], axes[1], n, a2.w);
    let r = a2.w;
    let l_const = billboard_path_length(b.z, r * half_thickness(PRIMITIVE_CONSTANT, b.xy, a1.w), a0.w);
    let l_lin = billboard_path_length(b.z, r * half_thickness(PRIMITIVE_LINEAR, b.xy, a1.w), a0.w);
    let l_tex = billboard_path_length(b.z, r * half_thickness(PRIMITIVE_TEXTURE, b.xy, a1.w), a0.w);
    put(i, 0u, vec4f(b, half_thickness_sphere(b.xy)));
    put(i, 1u, vec4f(l_const, l_lin, l_tex, 0.0));"#,
    ),
    // a0 = (kind, density, half_len, obliquity), a1 = (slab_near, slab_far, -, -)
    (
        "k_slice",
        r#"
    let a0 = arg(i, 0u); let a1 = arg(i, 1u);
    put(i, 0u, vec4f(slice_alpha(u32(a0.x), a0.y, a0.z, a1.x, a1.y, a0.w), 0.0, 0.0, 0.0));"#,
    ),
];

/// The kernels' WGSL: the binding header of `gpu::compute::run_kernel` for [`Case`] and
/// [`Output`], the helpers and one entry point per function.
fn kernels() -> String {
    let mut source = String::from(
        "#import volumes::path_length::{PRIMITIVE_CONSTANT, PRIMITIVE_LINEAR, PRIMITIVE_TEXTURE, \
         billboard_coords, billboard_path_length, depth_fade, half_thickness, \
         half_thickness_sphere, opacity_from_length, slice_alpha, sphere_path_length, \
         visible_length}\n",
    );
    source.push_str(&kernel_header("array<vec4f, 4>", "array<vec4f, 2>"));
    source.push_str(HELPERS);
    for (entry, body) in KERNELS {
        source.push_str(&kernel_entry(entry, body));
    }
    source
}

/// The Rust side of `billboard_axes` in the kernel.
fn billboard_axes(n: Vec3, angle: f32) -> (Vec3, Vec3) {
    let helper = if n.y.abs() > 0.9 { Vec3::X } else { Vec3::Y };
    let r0 = helper.cross(n).normalize();
    let u0 = n.cross(r0);
    let right = r0 * angle.cos() + u0 * angle.sin();
    (right, n.cross(right))
}

fn run_kernel(entry: &str, cases: &[Case]) -> Vec<Output> {
    run_kernel_with(&PATH_LENGTH, entry, cases)
}

/// Runs kernel `entry` importing `path_length` as `volumes::path_length` (the module the
/// technique's shader imports, or a test's broken copy of it).
fn run_kernel_with(path_length: &gpu::wgsl::Module, entry: &str, cases: &[Case]) -> Vec<Output> {
    let source = kernels();
    let imports = [path_length];
    let shader = gpu::wgsl::Shader::new(entry, &source).importing(&imports);
    gpu::compute::run_kernel(testkit::context(), shader, entry, cases, 1)
        .unwrap_or_else(|e| panic!("kernel {entry}: {e}"))
}

/// Deterministic random numbers: stream `s`, case `i`, component `k`.
fn rnd(s: u32, i: u32, k: u32) -> f32 {
    hash_to_unit(s.wrapping_mul(0x9e37_79b9) ^ i.wrapping_mul(16).wrapping_add(k))
}

fn range(s: u32, i: u32, k: u32, lo: f32, hi: f32) -> f32 {
    lo + (hi - lo) * rnd(s, i, k)
}

fn unit(s: u32, i: u32, k: u32) -> Vec3 {
    let z = range(s, i, k, -1.0, 1.0);
    let phi = range(s, i, k + 1, 0.0, std::f32::consts::TAU);
    let r = (1.0 - z * z).max(0.0).sqrt();
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

fn check(
    entry: &str,
    cases: &[Case],
    failures: &mut Vec<String>,
    ok: impl Fn(&Case, &Output) -> Result<(), String>,
) {
    let out = run_kernel(entry, cases);
    for (case, o) in cases.iter().zip(&out) {
        if let Err(msg) = ok(case, o) {
            failures.push(format!("{entry}: {msg} (case {case:?}, gpu {o:?})"));
        }
    }
}

/// Fails the test with the number of mismatches and the first 20 of them.
fn assert_no_mismatches(failures: &[String]) {
    assert!(
        failures.is_empty(),
        "{} mismatches:\n{}",
        failures.len(),
        failures[..failures.len().min(20)].join("\n")
    );
}

fn close(gpu: f32, cpu: f32, tol: f32) -> bool {
    gpu == cpu || (gpu - cpu).abs() <= tol
}

fn scene_t(s: u32, i: u32) -> f32 {
    match i % 5 {
        0 => gpu::prelude::BIG,
        1 => range(s, i, 15, -1.0, 0.0),
        _ => range(s, i, 15, 0.0, 20.0),
    }
}

#[test]
fn opacity_and_visible_length_match_the_twin() {
    let mut failures = Vec::new();
    let mut cases: Vec<Case> = (0..RANDOM_CASES)
        .map(|i| {
            let len = if i % 7 == 0 {
                range(1, i, 0, -1.0, 0.0)
            } else {
                range(1, i, 0, 0.0, 8.0)
            };
            [
                Vec4::new(len, range(1, i, 1, 0.0, 3.0), (i % 3) as f32, 0.0),
                Vec4::ZERO,
                Vec4::ZERO,
                Vec4::ZERO,
            ]
        })
        .collect();
    for kind in 0..3 {
        for len in [0.0, 1.0, 1e-7, 1e30] {
            cases.push([
                Vec4::new(len, 0.6, kind as f32, 0.0),
                Vec4::ZERO,
                Vec4::ZERO,
                Vec4::ZERO,
            ]);
        }
    }
    check("k_opacity", &cases, &mut failures, |c, o| {
        let cpu = opacity_from_length(c[0].z as u32, c[0].x, c[0].y);
        close(o[0].x, cpu, 2e-5 + 2e-5 * cpu)
            .then_some(())
            .ok_or_else(|| format!("opacity {} vs {cpu}", o[0].x))
    });

    let cases: Vec<Case> = (0..RANDOM_CASES)
        .map(|i| {
            let (a, b) = (range(2, i, 0, -10.0, 10.0), range(2, i, 1, -10.0, 10.0));
            [
                Vec4::new(a.min(b), a.max(b), scene_t(2, i), 0.0),
                Vec4::ZERO,
                Vec4::ZERO,
                Vec4::ZERO,
            ]
        })
        .collect();
    check("k_visible", &cases, &mut failures, |c, o| {
        let cpu = visible_length(c[0].x, c[0].y, c[0].z);
        let tol = 1e-6 * (c[0].x.abs() + c[0].y.abs() + c[0].z.abs().min(100.0));
        close(o[0].x, cpu, tol)
            .then_some(())
            .ok_or_else(|| format!("visible {} vs {cpu}", o[0].x))
    });
    assert_no_mismatches(&failures);
}

#[test]
fn depth_fade_matches_the_twin() {
    let mut failures = Vec::new();
    let mut cases: Vec<Case> = (0..RANDOM_CASES)
        .map(|i| {
            let fade = if i % 9 == 0 {
                0.0
            } else {
                range(7, i, 2, 0.0, 4.0)
            };
            [
                Vec4::new(range(7, i, 0, 0.0, 20.0), scene_t(7, i), fade, 0.0),
                Vec4::ZERO,
                Vec4::ZERO,
                Vec4::ZERO,
            ]
        })
        .collect();
    // Edges: the billboard exactly on the scene, one fade distance in front, a negative fade.
    for (tp, ts, f) in [
        (5.0, 5.0, 1.0),
        (4.0, 5.0, 1.0),
        (5.0, 5.0, 0.0),
        (2.0, 3.0, -1.0),
    ] {
        cases.push([
            Vec4::new(tp, ts, f, 0.0),
            Vec4::ZERO,
            Vec4::ZERO,
            Vec4::ZERO,
        ]);
    }
    check("k_fade", &cases, &mut failures, |c, o| {
        let cpu = depth_fade(c[0].x, c[0].y, c[0].z);
        close(
            o[0].x,
            cpu,
            1e-6 + 1e-6 * (c[0].y.abs().min(100.0) / c[0].z.max(1e-3)),
        )
        .then_some(())
        .ok_or_else(|| format!("fade {} vs {cpu} for {}", o[0].x, c[0]))
    });
    assert_no_mismatches(&failures);
}

#[test]
fn sphere_path_length_matches_the_twin() {
    let mut cases: Vec<Case> = (0..RANDOM_CASES)
        .map(|i| {
            let c = Vec3::new(
                range(3, i, 0, -5.0, 5.0),
                range(3, i, 1, -5.0, 5.0),
                range(3, i, 2, -5.0, 5.0),
            );
            let r = range(3, i, 3, 0.05, 3.0);
            let o = if i % 4 == 0 {
                c + unit(3, i, 4) * r * range(3, i, 6, 0.0, 0.95) // eye inside
            } else {
                Vec3::new(
                    range(3, i, 7, -8.0, 8.0),
                    range(3, i, 8, -8.0, 8.0),
                    range(3, i, 9, -8.0, 8.0),
                )
            };
            let aim = c + unit(3, i, 10) * r * range(3, i, 12, 0.0, 1.2);
            let d = (aim - o).normalize_or(Vec3::X);
            [
                o.extend(scene_t(3, i)),
                d.extend(0.0),
                c.extend(r),
                Vec4::ZERO,
            ]
        })
        .collect();
    // Tangent rays and an eye at the centre.
    for i in 0..64 {
        let c = Vec3::new(0.5, 1.0, -0.25);
        let r = 1.5;
        let n = unit(4, i, 0);
        let d = (unit(4, i, 2) - n * unit(4, i, 2).dot(n)).normalize_or(n.any_orthonormal_vector());
        let o = c + n * r - d * range(4, i, 4, 0.0, 6.0);
        cases.push([
            o.extend(scene_t(4, i)),
            d.extend(0.0),
            c.extend(r),
            Vec4::ZERO,
        ]);
    }
    cases.push([
        Vec3::ZERO.extend(10.0),
        Vec3::X.extend(0.0),
        Vec3::ZERO.extend(1.0),
        Vec4::ZERO,
    ]);
    let mut failures = Vec::new();
    check("k_sphere", &cases, &mut failures, |c, o| {
        let (orig, d, center, r, s) = (
            c[0].truncate(),
            c[1].truncate(),
            c[2].truncate(),
            c[2].w,
            c[0].w,
        );
        let cpu = sphere_path_length(orig, d, center, r, s);
        let oc = orig - center;
        let b = oc.dot(d);
        let disc_err = 8.0 * EPS * (b * b + oc.length_squared() + r * r);
        let tol = 1e-4 * (oc.length() + r + 1.0) + 2.0 * disc_err.sqrt();
        if !o[0].x.is_finite() {
            return Err("non-finite".into());
        }
        close(o[0].x, cpu, tol)
            .then_some(())
            .ok_or_else(|| format!("length {} vs {cpu} (tol {tol})", o[0].x))
    });
    assert_no_mismatches(&failures);
}

#[test]
fn billboard_primitives_match_the_twin() {
    let mut cases: Vec<Case> = Vec::new();
    for i in 0..RANDOM_CASES {
        let c = Vec3::new(
            range(5, i, 0, -5.0, 5.0),
            range(5, i, 1, -5.0, 5.0),
            range(5, i, 2, -5.0, 5.0),
        );
        let r = range(5, i, 3, 0.05, 3.0);
        let o = c + unit(5, i, 4) * range(5, i, 6, 0.2, 10.0);
        let n = (o - c).normalize();
        let angle = range(5, i, 7, 0.0, std::f32::consts::TAU);
        let (right, up) = billboard_axes(n, angle);
        // Aim at a point of the billboard quad (scale up to 1.3), sometimes exactly on the
        // disc's edge.
        let mut q = Vec2::new(range(5, i, 8, -1.3, 1.3), range(5, i, 9, -1.3, 1.3));
        if i % 8 == 0 {
            q = q.normalize_or(Vec2::X);
        }
        let p = c + (right * q.x + up * q.y) * r;
        let d = (p - o).normalize();
        if d.dot(n).abs() < 0.05 {
            continue;
        }
        let tex = range(5, i, 10, -0.2, 1.2);
        cases.push([
            o.extend(scene_t(5, i)),
            d.extend(tex),
            c.extend(r),
            n.extend(angle),
        ]);
    }
    let mut failures = Vec::new();
    check("k_billboard", &cases, &mut failures, |c, o| {
        let (orig, d, center, r, s, tex) = (
            c[0].truncate(),
            c[1].truncate(),
            c[2].truncate(),
            c[2].w,
            c[0].w,
            c[1].w,
        );
        let n = c[3].truncate();
        let (right, up) = billboard_axes(n, c[3].w);
        let b = billboard_coords(orig, d, center, right, up, n, r);
        let scale = (orig - center).length() + 1.0;
        let uv_tol = 1e-4 * scale / r;
        if !(close(o[0].x, b.x, uv_tol)
            && close(o[0].y, b.y, uv_tol)
            && close(o[0].z, b.z, 1e-4 * scale))
        {
            return Err(format!("coords {:?} vs {b:?}", o[0].truncate()));
        }
        let uv = Vec2::new(b.x, b.y);
        let hs = half_thickness_sphere(uv);
        if !close(o[0].w, hs, 2e-3) {
            return Err(format!("sphere profile {} vs {hs}", o[0].w));
        }
        let near_edge =
            (uv.length_squared() - 1.0).abs() < 1e-3 || (b.x.abs() - b.y.abs()).abs() < 1e-3;
        let tol = 2e-4 * ((orig - center).length() + r);
        for (k, kind) in [PRIMITIVE_CONSTANT, PRIMITIVE_LINEAR, PRIMITIVE_TEXTURE]
            .into_iter()
            .enumerate()
        {
            let cpu = billboard_path_length(b.z, r * half_thickness(kind, uv, tex), s);
            let gpu = o[1][k];
            if !gpu.is_finite() || gpu < 0.0 || gpu > 2.0 * r + tol {
                return Err(format!("kind {kind}: {gpu} outside [0, 2R]"));
            }
            if !near_edge && !close(gpu, cpu, tol) {
                return Err(format!("kind {kind}: length {gpu} vs {cpu}"));
            }
        }
        Ok(())
    });
    assert!(cases.len() > 3000);
    assert_no_mismatches(&failures);
}

#[test]
fn slice_alpha_matches_the_twin() {
    let mut cases: Vec<Case> = Vec::new();
    for i in 0..RANDOM_CASES {
        let r = range(6, i, 0, 0.1, 2.0);
        let n = [5u32, 9, 19, 39, 79][(i % 5) as usize];
        let k = (rnd(6, i, 1) * n as f32) as u32 % n;
        let delta = 2.0 * r / n as f32;
        let near = -r + k as f32 * delta;
        let h = range(6, i, 2, 0.0, 1.0) * r;
        cases.push([
            Vec4::new(
                (i % 3) as f32,
                range(6, i, 3, 0.0, 2.0),
                h,
                range(6, i, 4, 1.0, 3.0),
            ),
            Vec4::new(near, near + delta, 0.0, 0.0),
            Vec4::ZERO,
            Vec4::ZERO,
        ]);
    }
    let mut failures = Vec::new();
    check("k_slice", &cases, &mut failures, |c, o| {
        let (kind, density, h, obliquity, near, far) =
            (c[0].x as u32, c[0].y, c[0].z, c[0].w, c[1].x, c[1].y);
        let cpu = slice_alpha(kind, density, h, near, far, obliquity);
        let gpu = o[0].x;
        if !(0.0..=1.0).contains(&gpu) {
            return Err(format!("alpha {gpu} outside [0, 1]"));
        }
        let l_near = (near + h).clamp(0.0, 2.0 * h) * obliquity;
        let a_near = opacity_from_length(kind, l_near, density);
        if a_near > 1.0 - 1e-4 {
            return Ok(());
        }
        let tol = 1e-4 + 1e-5 / (1.0 - a_near);
        close(gpu, cpu, tol)
            .then_some(())
            .ok_or_else(|| format!("alpha {gpu} vs {cpu}"))
    });
    assert_no_mismatches(&failures);
}

/// The comparison can fail: a copy of the WGSL with the logarithmic function's argument 1%
/// off, or the slice share's ratio inverted, is caught.
#[test]
fn mutated_shaders_are_detected() {
    let broken_log = PATH_LENGTH_WGSL.replace("g = log2(1.0 + l);", "g = log2(1.0 + 1.01 * l);");
    assert_ne!(broken_log, PATH_LENGTH_WGSL);
    let cases: Vec<Case> = (0..256)
        .map(|i| {
            [
                Vec4::new(range(7, i, 0, 0.1, 2.0), 0.3, OPACITY_LOG as f32, 0.0),
                Vec4::ZERO,
                Vec4::ZERO,
                Vec4::ZERO,
            ]
        })
        .collect();
    let out = run_kernel_with(&PATH_LENGTH.with_source(broken_log), "k_opacity", &cases);
    let caught = cases
        .iter()
        .zip(&out)
        .filter(|(c, o)| {
            !close(
                o[0].x,
                opacity_from_length(OPACITY_LOG, c[0].x, 0.3),
                2e-5 + 2e-5 * o[0].x,
            )
        })
        .count();
    assert!(
        caught > 250,
        "only {caught} of {} cases caught a 1% error in the log function",
        cases.len()
    );

    let broken_slice = PATH_LENGTH_WGSL.replace(
        "(1.0 - a_far) / (1.0 - a_near)",
        "(1.0 - a_near) / (1.0 - a_far)",
    );
    assert_ne!(broken_slice, PATH_LENGTH_WGSL);
    let cases: Vec<Case> = (0..256)
        .map(|i| {
            [
                Vec4::new(0.0, 0.5, 1.0, 1.0),
                Vec4::new(range(8, i, 0, -1.0, 0.8), 0.0, 0.0, 0.0),
                Vec4::ZERO,
                Vec4::ZERO,
            ]
        })
        .map(|mut c| {
            c[1].y = c[1].x + 0.2;
            c
        })
        .collect();
    let out = run_kernel_with(&PATH_LENGTH.with_source(broken_slice), "k_slice", &cases);
    let caught = cases
        .iter()
        .zip(&out)
        .filter(|(c, o)| !close(o[0].x, slice_alpha(0, 0.5, 1.0, c[1].x, c[1].y, 1.0), 1e-3))
        .count();
    assert!(
        caught > 200,
        "only {caught} of {} cases caught an inverted slice share",
        cases.len()
    );
}
