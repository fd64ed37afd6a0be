// Interior mapping techniques (van Dongen 2008, chapter 5 and the appendix's pixel shader).
// Imports gpu::prelude, scene::shading and interior_mapping::rooms (interior.wgsl). The hull of
// each building is drawn with scene_vs; per pixel the ray from the eye through the hull point
// is cast in object space against the room planes (cast_rooms), the nearest plane is textured
// by family and shaded with the scene's diffuse model (shade_diffuse, shadow maps included),
// and the result shows through the windows of the facade.
#import gpu::prelude::{PI, cube_dir_to_face_uv, fresnel_dielectric, hash_to_unit, pcg_hash, ray_box, reflect_dir}
#import scene::shading::{LIGHT_DIRECTIONAL, SceneVertexOut, camera, facing_normal, in_cutout_hole, light_intensity_toward, light_toward, light_visibility, lights, object_emission, objects, scene_info, shade_diffuse, surface_albedo}
#import interior_mapping::rooms::{RoomHit, cast_rooms, plane_uv, room_hash, cubemap_room}

struct BuildingGpu {
    world_to_object: mat4x4f,
    // xyz: object-space origin of the room grid; w: building number (hash seed).
    grid_origin: vec4f,
    // xyz: room size (m); w: 1 for a building, 0 for other objects.
    room_size: vec4f,
    // xyz: wall displacement in rooms (varied variant), w: 1 when the hull is its bounding box.
    displacement: vec4f,
    // xyz: object-space maximum of the hull's bounding box (the minimum is grid_origin).
    hull_max: vec4f,
};

struct Settings {
    // x: variant (0 basic, 1 textured, 2 exterior, 3 furniture, 4 varied, 5 ceiling-only,
    // 6 single-texture, 7 reflection-only, 8 cubemap, 9 cubemap-varied); y: light probability;
    // z: interior light (radiance scale of a lit room); w: furniture frame.
    a: vec4f,
    // x: furniture depth (rooms); y: window glass ior; z: 1 = room shadows through the windows
    // (box hulls), 0 = the scene's shadow maps; w: unused.
    b: vec4f,
};

const VARIANT_BASIC: f32 = 0.0;
const VARIANT_EXTERIOR: f32 = 2.0;
const VARIANT_FURNITURE: f32 = 3.0;
const VARIANT_VARIED: f32 = 4.0;
const VARIANT_CEILING_ONLY: f32 = 5.0;
const VARIANT_SINGLE_TEXTURE: f32 = 6.0;
const VARIANT_REFLECTION_ONLY: f32 = 7.0;
const VARIANT_CUBEMAP: f32 = 8.0;
const VARIANT_CUBEMAP_VARIED: f32 = 9.0;
const SURFACE_CEILING: u32 = 1u;
const WINDOW_SIDE: f32 = 0.2;
const WINDOW_SILL: f32 = 0.3;
const WINDOW_TOP: f32 = 0.85;
const ATLAS_VARIANTS: u32 = 4u;
const FURNITURE_LAYER: i32 = 16;

@group(2) @binding(0) var<storage, read> buildings: array<BuildingGpu>;
@group(2) @binding(1) var<uniform> settings: Settings;
@group(2) @binding(2) var room_textures: texture_2d_array<f32>;
@group(2) @binding(3) var room_sampler: sampler;
@group(2) @binding(4) var env_map: texture_cube<f32>;
@group(2) @binding(5) var env_sampler: sampler;
// The 2 x 2 atlas of the single-texture variant (1 x 1 and unread otherwise).
@group(2) @binding(6) var single_texture: texture_2d<f32>;
// The room cube maps of the cube-map interiors: six faces per room (cube-layer order), addressed
// with cube_dir_to_face_uv (one placeholder texel, unread, for the other variants).
@group(2) @binding(7) var room_faces: texture_2d_array<f32>;

fn in_window(h: f32, v: f32) -> bool {
    let fh = h - floor(h);
    let fv = v - floor(v);
    return fh >= WINDOW_SIDE && fh <= 1.0 - WINDOW_SIDE && fv >= WINDOW_SILL && fv <= WINDOW_TOP;
}

// Flat colours of the basic variant (figure 5.13, top left: lighting, no textures).
fn basic_albedo(surface: u32) -> vec3f {
    switch surface {
        case 0u: { return vec3f(0.45, 0.32, 0.2); }
        case 1u: { return vec3f(0.8, 0.8, 0.75); }
        case 2u: { return vec3f(0.55, 0.6, 0.4); }
        default: { return vec3f(0.6, 0.42, 0.38); }
    }
}

// Single-texture variant (5.3.2): the tile of `surface` in the 2 x 2 atlas, at the room-face
// coordinate fract(uv) kept half a texel inside the tile so that bilinear filtering never
// reads a neighbouring tile. These are the "extra instructions to calculate which texture
// coordinates to use" that the paper found slower than four separate textures.
fn single_texture_albedo(uv: vec2f, surface: u32) -> vec3f {
    let tile = vec2f(f32(surface % 2u), f32(surface / 2u));
    let half_texel = 0.5 / (0.5 * f32(textureDimensions(single_texture).x));
    let local = clamp(fract(uv), vec2f(half_texel), vec2f(1.0 - half_texel));
    return textureSampleLevel(single_texture, room_sampler, (tile + local) * 0.5, 0.0).rgb;
}

// The room surface's albedo per variant: flat colours (basic; ceiling-only below the
// ceilings), one atlas (single-texture) or the texture array layer of the surface.
fn room_albedo(variant: f32, surface: u32, uv: vec2f, atlas: u32) -> vec3f {
    if (variant == VARIANT_BASIC || (variant == VARIANT_CEILING_ONLY && surface != SURFACE_CEILING)) {
        return basic_albedo(surface);
    }
    if (variant == VARIANT_SINGLE_TEXTURE) {
        return single_texture_albedo(uv, surface);
    }
    return textureSampleLevel(room_textures, room_sampler, uv, i32(atlas * 4u + surface), 0.0).rgb;
}

// The environment seen in the window glass (the cube map rendered around the eye).
fn window_reflection(v: vec3f, n_world: vec3f) -> vec3f {
    return textureSampleLevel(env_map, env_sampler, reflect_dir(v, n_world), 0.0).rgb;
}

// Visibility of light i from a point p_o (object space) on a room surface of a box hull: the
// segment toward the light must stay in the room until it leaves the hull, and leave it
// through a window; beyond the window the scene's shadow map decides, looked up at the exit
// point on the facade. (Exact where the shared shadow map's bias, about 2.5 m for the city's
// distant sun, would light room surfaces behind the facade.)
fn room_visibility(i: u32, p_o: vec3f, b: BuildingGpu, model: mat4x4f, normal_matrix: mat4x4f) -> f32 {
    let l_o = (b.world_to_object * vec4f(lights[i].position.xyz, 1.0)).xyz;
    var d = l_o - p_o;
    if (lights[i].direction.w == LIGHT_DIRECTIONAL) {
        // Toward a sun: any length does, the walk and the exit share its parameter.
        d = (b.world_to_object * vec4f(-lights[i].direction.xyz, 0.0)).xyz;
    }
    let lo = b.grid_origin.xyz;
    let hi = b.hull_max.xyz;
    let t_exit = ray_box(p_o, d, lo, hi).y;
    let seed = bitcast<u32>(i32(b.grid_origin.w)) * 7u;
    let hit = cast_rooms(p_o - lo, d, b.room_size.xyz, b.displacement.xyz, seed);
    if (hit.t < t_exit || t_exit <= 0.0) { return 0.0; }
    let q = p_o + t_exit * d;
    let g = (q - lo) / b.room_size.xyz;
    // The face the segment leaves by: the slab whose boundary q is closest to (in rooms).
    let e = min(abs(q - lo), abs(hi - q)) / b.room_size.xyz;
    var axis = vec3f(0.0);
    var h: f32;
    if (e.x <= e.y && e.x <= e.z) {
        axis = vec3f(1.0, 0.0, 0.0);
        h = g.z;
    } else if (e.z <= e.y) {
        axis = vec3f(0.0, 0.0, 1.0);
        h = g.x;
    } else {
        return 0.0;
    }
    if (!in_window(h, g.y)) { return 0.0; }
    let q_world = (model * vec4f(q, 1.0)).xyz;
    let n_world = normalize((normal_matrix * vec4f(axis, 0.0)).xyz);
    let to_l = light_toward(i, q_world);
    return light_visibility(i, q_world, select(-n_world, n_world, dot(n_world, to_l) > 0.0));
}

// shade_diffuse (scene.wgsl) with room_visibility in place of the shadow-map visibility.
fn shade_room(p: vec3f, n: vec3f, albedo: vec3f, p_o: vec3f, b: BuildingGpu, model: mat4x4f, normal_matrix: mat4x4f) -> vec3f {
    if (settings.b.z < 0.5 || b.displacement.w < 0.5) { return shade_diffuse(p, n, albedo); }
    var sum = vec3f(0.0);
    for (var i = 0u; i < scene_info.light_count; i++) {
        let to_l = light_toward(i, p);
        let d2 = dot(to_l, to_l);
        let cos_l = dot(n, to_l) * inverseSqrt(d2);
        if (cos_l <= 0.0) { continue; }
        let intensity = light_intensity_toward(i, to_l * inverseSqrt(d2));
        sum += albedo / PI * intensity * cos_l / d2 * room_visibility(i, p_o, b, model, normal_matrix);
    }
    return sum;
}

struct InteriorOut {
    @location(0) color: vec4f,
    // The hull's own depth, except when the eye is inside the hull: then the depth of the room
    // surface seen, so that scene geometry inside the hull (the ground under a building, which
    // coincides with the hull's bottom face) is hidden by the rooms as in the reference.
    @builtin(frag_depth) depth: f32,
};

// Without frag_depth (early depth test kept: the pre-pass pays): used while the eye is outside
// every hull.
@fragment
fn interior_fs(in: SceneVertexOut) -> @location(0) vec4f {
    if (in_cutout_hole(in.object, in.uv)) { discard; }
    return interior_shade(in).color;
}

// With frag_depth: used while the eye is inside a hull's bounding box.
@fragment
fn interior_inside_fs(in: SceneVertexOut) -> InteriorOut {
    if (in_cutout_hole(in.object, in.uv)) { discard; }
    return interior_shade(in);
}

fn interior_shade(in: SceneVertexOut) -> InteriorOut {
    var out: InteriorOut;
    out.depth = in.clip.z;
    let eye = camera.eye.xyz;
    let o = objects[in.object];
    let b = buildings[in.object];
    let variant = settings.a.x;
    let n_world = facing_normal(in.normal, in.world, eye);
    let distance_to_eye = distance(in.world, eye);
    let facade = shade_diffuse(in.world, n_world, surface_albedo(in.object, in.uv))
        + object_emission(in.object);

    let p = (b.world_to_object * vec4f(in.world, 1.0)).xyz;
    let eye_o = (b.world_to_object * vec4f(eye, 1.0)).xyz;
    // Object-space normal: n_obj = M^T n_world.
    let m3 = mat3x3f(o.model[0].xyz, o.model[1].xyz, o.model[2].xyz);
    let n_o = normalize(transpose(m3) * in.normal);
    let dir = p - eye_o;
    // The eye is inside when it is inside the hull's bounding box (exact for box hulls). With
    // the eye outside, back faces are hidden behind front faces: discard them (they would
    // otherwise write the depth of a cast from the eye).
    let eye_inside = all(eye_o > b.grid_origin.xyz) && all(eye_o < b.hull_max.xyz);
    let front = dot(n_o, dir) < 0.0;
    if (!front && !eye_inside) { discard; }
    let outside = front;
    let origin = b.grid_origin.xyz;
    let size = b.room_size.xyz;

    // Windows (section 5.2.3): a rectangle in every room cell of the side faces. The tangent
    // axis is the horizontal axis of the dominant normal component.
    let g = (p - origin) / size;
    let an = abs(n_o);
    let h = select(g.x, g.z, an.x >= an.z);
    let window = an.y < 0.7 && in_window(h, g.y);
    if (variant == VARIANT_REFLECTION_ONLY) {
        // No interior (5.3): fully reflective windows, the diffuse facade elsewhere. With the
        // eye inside a hull the glass is seen from behind and reflects the same way.
        let reflected = window_reflection(normalize(in.world - eye), n_world);
        out.color = vec4f(select(facade, reflected, window), distance_to_eye);
        return out;
    }
    if (outside && !window) {
        out.color = vec4f(facade, distance_to_eye);
        return out;
    }

    // The ray cast (5.2.1-5.2.2): from the hull point, or from the eye when it is inside.
    let start = select(eye_o, p, outside);
    // Per building: the seed of the displaced walls' offsets, and the number the room hash
    // (varied lights and tints, the cube maps' choice and mirroring) is keyed on.
    let seed = bitcast<u32>(i32(b.grid_origin.w)) * 7u;
    let building = u32(b.grid_origin.w);
    // Cube-map interiors (engine baseline): the exit of the room box instead of the planes, and
    // the albedo from the room's cube map in the direction of that exit.
    let cubemap = variant == VARIANT_CUBEMAP || variant == VARIANT_CUBEMAP_VARIED;
    var cube_albedo = vec3f(0.0);
    var hit: RoomHit;
    if (cubemap) {
        let variants = select(1u, ATLAS_VARIANTS, variant == VARIANT_CUBEMAP_VARIED);
        let c = cubemap_room(start - origin, dir, size, variants, building);
        hit.family = c.family;
        hit.t = c.t;
        hit.point = c.point;
        hit.room = c.room;
        let face = cube_dir_to_face_uv(c.lookup);
        let layer = i32(c.atlas * 6u + u32(face.x));
        cube_albedo = textureSampleLevel(room_faces, env_sampler, face.yz, layer, 0.0).rgb;
    } else {
        hit = cast_rooms(start - origin, dir, size, b.displacement.xyz, seed);
    }
    var surface: u32;
    switch hit.family {
        case 0u: { surface = 2u; }
        case 1u: { surface = select(0u, 1u, dir.y > 0.0); }
        default: { surface = 3u; }
    }
    let uh = hit.point / size;
    let uv = plane_uv(hit.family, uh);
    var atlas = 0u;
    var room_light = 0.0;
    if (variant == VARIANT_VARIED) {
        // Per-room light on/off by hash against the probability (5.4.1) and texture variant (5.4.2).
        let hr = room_hash(hit.room, building);
        room_light = select(0.0, settings.a.z, hash_to_unit(hr) < settings.a.y);
        atlas = pcg_hash(hr) % ATLAS_VARIANTS;
    } else {
        room_light = settings.a.z;
    }
    var albedo = cube_albedo;
    if (!cubemap) { albedo = room_albedo(variant, surface, uv, atlas); }
    var axis = vec3f(0.0);
    axis[hit.family] = 1.0;
    let hit_world = (o.model * vec4f(hit.point + origin, 1.0)).xyz;
    if (!outside) {
        let clip = camera.view_proj * vec4f(hit_world, 1.0);
        out.depth = clamp(clip.z / clip.w, 0.0, 1.0);
    }
    let n_hit = facing_normal((o.normal_matrix * vec4f(axis, 0.0)).xyz, hit_world, eye);
    var interior = shade_room(hit_world, n_hit, albedo, hit.point + origin, b, o.model, o.normal_matrix) + albedo * room_light;

    // Furniture plane (5.2.4): parallel to the surface, a fixed depth inside, alpha tested.
    if (variant == VARIANT_FURNITURE && outside) {
        let depth = settings.b.x * dot(an, size);
        let t_f = depth / max(-dot(n_o, dir), 1e-6);
        if (t_f < hit.t) {
            let pf = p + t_f * dir;
            let gf = (pf - origin) / size;
            let hf = select(gf.x, gf.z, an.x >= an.z);
            let suv = vec2f(hf - floor(hf), ceil(gf.y) - gf.y);
            let layer = FURNITURE_LAYER + i32(settings.a.w);
            let f = textureSampleLevel(room_textures, room_sampler, suv, layer, 0.0);
            if (f.a > 0.5) {
                let pf_world = (o.model * vec4f(pf, 1.0)).xyz;
                interior = shade_room(pf_world, n_world, f.rgb, pf, b, o.model, o.normal_matrix) + f.rgb * room_light;
            }
        }
    }

    var color = interior;
    if (variant == VARIANT_EXTERIOR && outside) {
        // Window glass: the interior blended with a reflection from the environment map,
        // weighted by the shared Fresnel approximation.
        let v = normalize(in.world - eye);
        let f = fresnel_dielectric(-dot(v, n_world), settings.b.y);
        let reflected = window_reflection(v, n_world);
        color = f * reflected + (1.0 - f) * interior;
    }
    out.color = vec4f(color, select(distance(hit_world, eye), distance_to_eye, outside));
    return out;
}
