//! The light-map footprints of `shaders/footprint.wgsl` (`footprint_cut2`,
//! `footprint_covariance`) against their twin `scene::lightmap::Footprint`, on cells of every
//! size and tilt, the capped ones and the fixed quad included.

use glam::Vec2;
use gpu::compute::{kernel_entry, kernel_header, run_kernel};
use scene::lightmap::{FOOTPRINT, Footprint};

#[test]
fn the_wgsl_footprints_match_the_twin() {
    let _lock = testkit::gpu_lock();
    let ctx = testkit::context();
    let source = format!(
        "#import scene::footprint::{{FIXED_CUT2, footprint_covariance, footprint_cut2}}\n{}{}",
        kernel_header("array<vec4f, 2>", "vec4f"),
        kernel_entry(
            "footprint_test",
            // As splat_quad_vs: the fixed quad (no footprints) has no cell and the fixed cut.
            "let c = inputs[i]; var ex = vec2f(0.0); var ey = vec2f(0.0); \
             var cut2 = FIXED_CUT2; \
             if (c[1].y > 0.5) { ex = c[0].yz; ey = vec2f(c[0].w, c[1].x); \
                                 cut2 = footprint_cut2(c[0].x, ex, ey); } \
             outputs[i] = vec4f(footprint_covariance(c[0].x, ex, ey, cut2), cut2);"
        )
    );
    let mut cases = Vec::new();
    for i in 0..256 {
        let f = i as f32 * 0.61;
        let radius = 1.0 + 5.0 * (f * 0.3).sin().abs();
        // No cell (the fixed quad), cells smaller than it, larger, and past the cap.
        let scale = [0.0, 0.5, 8.0, 300.0][i % 4];
        let ex = Vec2::new(f.cos(), f.sin()) * scale;
        let ey = Vec2::new(-(f * 1.7).sin(), (f * 1.3).cos()) * scale * 0.3;
        let of_cell = if i % 8 == 0 { 0.0 } else { 1.0 };
        cases.push([[radius, ex.x, ex.y, ey.x], [ey.y, of_cell, 0.0, 0.0]]);
    }
    let got: Vec<[f32; 4]> = run_kernel(
        ctx,
        gpu::wgsl::Shader::new("footprints", &source).importing(&[&FOOTPRINT]),
        "footprint_test",
        &cases,
        1,
    )
    .expect("kernel");
    let close = |a: f32, b: f32| (a - b).abs() <= 1e-4 * a.abs().max(b.abs()).max(1e-3);
    for (case, got) in cases.iter().zip(&got) {
        let [c0, c1] = case;
        let (radius, ex, ey) = (c0[0], Vec2::new(c0[1], c0[2]), Vec2::new(c0[3], c1[0]));
        let twin = if c1[1] > 0.5 {
            Footprint::of_cell(radius, ex, ey)
        } else {
            Footprint::fixed(radius)
        };
        let want = [
            twin.covariance[0],
            twin.covariance[1],
            twin.covariance[2],
            twin.cut2,
        ];
        assert!(
            want.iter().zip(got).all(|(w, g)| close(*w, *g)),
            "{case:?}: gpu {got:?}, twin {want:?}"
        );
    }
}
