// ---------------------------------------------------------------------------------------------
// The billboard's proxy box (Dancsik and Minarik, section 6), importing scene::shading and
// height_maps::search: a piece is drawn as the bounding box of its height map's proxy, turned
// about the vertical to face the eye, 36 vertices (12 triangles) per piece, no vertex buffer.
// Its fragments cast the eye ray into the box and search the height map; the box only bounds
// where they can hit.
// ---------------------------------------------------------------------------------------------
#define_import_path height_maps::billboard_box

#import scene::shading::camera
#import height_maps::search::{HeightBounds, billboard_facing, dir_to_world, height_box_min, height_box_max}

// The 36 corners of a box's 12 triangles, as (corner bits, face): bit 0 = x max, 1 = y max,
// 2 = z max; faces -x, +x, -y, +y, -z, +z.
const BOX_CORNERS = array<u32, 36>(
    0u, 2u, 6u, 0u, 6u, 4u,   1u, 5u, 7u, 1u, 7u, 3u,
    0u, 4u, 5u, 0u, 5u, 1u,   2u, 3u, 7u, 2u, 7u, 6u,
    0u, 1u, 3u, 0u, 3u, 2u,   4u, 6u, 7u, 4u, 7u, 5u,
);
const BOX_NORMALS = array<vec3f, 6>(
    vec3f(-1.0, 0.0, 0.0), vec3f(1.0, 0.0, 0.0), vec3f(0.0, -1.0, 0.0),
    vec3f(0.0, 1.0, 0.0), vec3f(0.0, 0.0, -1.0), vec3f(0.0, 0.0, 1.0),
);
struct BoxVertex {
    world: vec3f,
    // The box face's outward normal, world.
    face_normal: vec3f,
};

// Vertex `vertex` of the box of bounds `hb` about `centre`, turned to face `eye`.
fn billboard_box_vertex(vertex: u32, centre: vec3f, hb: HeightBounds, eye: vec3f) -> BoxVertex {
    let b = billboard_facing(centre, eye);
    let corner = BOX_CORNERS[vertex];
    let q = select(height_box_min(hb), height_box_max(hb),
                   vec3<bool>((corner & 1u) != 0u, (corner & 2u) != 0u, (corner & 4u) != 0u));
    return BoxVertex(b.centre + dir_to_world(b, q), dir_to_world(b, BOX_NORMALS[vertex / 6u]));
}

// What the billboard's vertex passes to its fragment.
struct BillboardOut {
    @builtin(position) clip: vec4f,
    @location(0) world: vec3f,
    @location(1) @interpolate(flat) piece: u32,
    // The box face's outward normal, world.
    @location(2) @interpolate(flat) face_normal: vec3f,
};

// What a billboard's fragment writes: the shaded colour (alpha: the hit's distance from the
// eye) and the hit's own depth.
struct BillboardTargets {
    @location(0) color: vec4f,
    @builtin(frag_depth) depth: f32,
};

// Vertex `vertex` of piece `piece`'s box (bounds `hb` about `centre`) in the camera's view,
// turned to face the camera's eye.
fn billboard_out(vertex: u32, piece: u32, centre: vec3f, hb: HeightBounds) -> BillboardOut {
    let v = billboard_box_vertex(vertex, centre, hb, camera.eye.xyz);
    var out: BillboardOut;
    out.world = v.world;
    out.clip = camera.view_proj * vec4f(v.world, 1.0);
    out.piece = piece;
    out.face_normal = v.face_normal;
    return out;
}

// Whether a fragment at `world` on a face of outward normal `face_normal` faces the eye:
// only those search (each pixel of the box once).
fn faces_eye(face_normal: vec3f, world: vec3f, eye: vec3f) -> bool {
    return dot(face_normal, world - eye) < 0.0;
}

// The depth of world point `point` in the view of `view_proj`.
fn frag_depth_of(view_proj: mat4x4f, point: vec3f) -> f32 {
    let clip = view_proj * vec4f(point, 1.0);
    return clamp(clip.z / clip.w, 0.0, 1.0);
}
