// The photon buffer (Hu and Qin 2006, section 3.1), over image_space_refraction::refract's
// bindings: the refractor drawn from a light (camera = the light's view, eye_params = the
// same view with size.z the pixel size at unit distance and size.w the light's index; the
// front/back buffers are the light's). Each pixel is one photon: the light's power through the
// pixel's solid angle, followed through the refractor exactly as an eye ray (the two-interface
// search on the light's buffers, Fresnel transmission at both interfaces) or reflected by a
// metal, then to the nearest rectangle impostor (the corrected lookup). It writes which texel
// of which rectangle it reaches, and its power; a photon that reaches none writes zeros.
#import gpu::prelude::fresnel_dielectric
#import scene::shading::{camera, emission_jitter, jittered_point, lights, objects, specular_event}
#import image_space_refraction::search::{Iteration, hu_qin_exit, exit_direction}
#import image_space_refraction::nearby::{nearby_hit, rects}
#import image_space_refraction::refract::{RefractorOut, SURFACE_OFFSET, back_buffer, eye_params, front_buffer, params}

struct PhotonOut {
    // u, v on the rectangle's texture, texture array layer + 1 (0: no photon), unused.
    @location(0) hit: vec4f,
    // rgb power (W), unused.
    @location(1) power: vec4f,
};

@fragment
fn photon_fs(pixel_in: RefractorOut) -> PhotonOut {
    // The photon leaves from a random point of its pixel (jittered_emission in scene.wgsl) or,
    // with params.photon_jitter 0, from the pixel centre.
    let jitter = emission_jitter(pixel_in.clip.xy, 0u) * f32(params.photon_jitter);
    let point = jittered_point(pixel_in.world, pixel_in.normal, jitter);
    var in = pixel_in;
    in.world = point.world;
    in.normal = point.normal;
    let light = camera.eye.xyz;
    let v = normalize(in.world - light);
    let e = specular_event(in.object, in.normal, in.world, light, v);
    var origin = in.world;
    var dir = e.reflected;
    var weight = e.reflectance;
    var valid = true;
    if (!e.is_metal) {
        valid = e.entering && e.refracted.w > 0.5;
        let t1 = e.refracted.xyz;
        let ior = objects[in.object].material.y;
        let it = Iteration(params.tolerance, params.max_iterations, params.initial_step);
        let exit = hu_qin_exit(front_buffer, back_buffer, eye_params, in.world, v, t1, params.strategy, it);
        let t2 = exit_direction(exit, t1, ior);
        valid = valid && t2.w > 0.5;
        let n = normalize(exit.normal);
        let outward = select(-n, n, dot(n, t1) > 0.0);
        let f2 = fresnel_dielectric(abs(dot(outward, t1)), 1.0 / ior);
        weight = vec3f((1.0 - e.reflectance.x) * (1.0 - f2));
        origin = exit.point + outward * SURFACE_OFFSET;
        dir = t2.xyz;
    }
    var out: PhotonOut;
    out.hit = vec4f(0.0);
    out.power = vec4f(0.0);
    let h = nearby_hit(origin, dir);
    if (valid && h.hit) {
        let r = rects[h.rect];
        let cos_theta = dot(v, eye_params.forward.xyz);
        let solid_angle = eye_params.size.z * eye_params.size.z * cos_theta * cos_theta * cos_theta;
        let intensity = lights[u32(eye_params.size.w)].intensity.rgb;
        out.hit = vec4f(h.uv, r.origin.w + 1.0, 0.0);
        out.power = vec4f(intensity * solid_angle * weight, 0.0);
    }
    return out;
}
