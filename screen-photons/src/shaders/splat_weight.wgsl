// The splat kernel and weight (section 3.1): the WGSL twin of `src/splat.rs`.

// The cone kernel of radius s, normalised to integrate to 1 over its plane.
fn splat_kernel(d: f32, s: f32) -> f32 {
    return 3.0 / (PI * s * s) * max(0.0, 1.0 - d / s);
}

// The splat weight at a pixel whose unit view ray from `eye` is `view`: the kernel at the
// point of the splat's plane (normal n through c) that the ray meets, and that point's
// distance from the eye (0 when the ray misses the plane).
fn splat_weight(eye: vec3f, view: vec3f, c: vec3f, n: vec3f, s: f32) -> vec2f {
    let denom = dot(view, n);
    if (abs(denom) < 1e-6) { return vec2f(0.0); }
    let tau = dot(c - eye, n) / denom;
    if (tau <= 0.0) { return vec2f(0.0); }
    let x = eye + view * tau;
    return vec2f(splat_kernel(distance(x, c), s), tau);
}
