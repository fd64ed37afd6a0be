// Radiance along a ray leaving the refractor, for the variants with nearby geometry: the texel
// of the nearest rectangle impostor the ray meets (image_space_refraction::nearby), else the
// environment map in the ray's direction. After refract.wgsl (env_lookup).
#import image_space_refraction::nearby::{impostor_color, impostor_texel, nearby_hit, rects}

fn outgoing_radiance(origin: vec3f, dir: vec3f) -> vec3f {
    let h = nearby_hit(origin, dir);
    if (h.hit) {
        let r = rects[h.rect];
        return textureLoad(impostor_color, impostor_texel(r, h.uv), i32(r.origin.w), 0).rgb;
    }
    return env_lookup(dir);
}
