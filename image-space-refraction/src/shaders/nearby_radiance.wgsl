// Radiance along a ray leaving the refractor, for the variants with nearby geometry: the texel
// of the nearest rectangle impostor the ray meets (image_space_refraction::nearby), else the
// environment map in the ray's direction. It overrides image_space_refraction::refract's.
#define_import_path image_space_refraction::nearby_radiance

#import image_space_refraction::nearby::{impostor_color, impostor_texel, nearby_hit, rects}
#import image_space_refraction::refract::env_lookup

override fn image_space_refraction::refract::outgoing_radiance(origin: vec3f, dir: vec3f) -> vec3f {
    let h = nearby_hit(origin, dir);
    if (h.hit) {
        let r = rects[h.rect];
        return textureLoad(impostor_color, impostor_texel(r, h.uv), i32(r.origin.w), 0).rgb;
    }
    return env_lookup(dir);
}
