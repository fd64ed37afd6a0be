// ---------------------------------------------------------------------------------------------
// The paper's section-5.2 pipeline with refractor height maps (Dancsik and Minarik, section 6:
// "in the algorithm described in 5.2, the refractor distance map can be replaced by the
// refractor height map"): the proxy entry points of scene's section-5 driver
// (scene::environment_pieces), composed with the height-map search (height_maps::object_search)
// and the billboard's box (height_maps::billboard_box).
//
// Each piece is its billboard's proxy box, turned to face the eye (the camera, or the centre
// of the impostor being built); the billboard decides visibility: a fragment casts the eye
// ray into the box and searches the piece's height map from outside (piece_hit), discarding a
// miss and writing the hit's depth. The hit is shaded through the per-piece impostors as the
// distance-map pieces are (shade_piece): reflection and the exits through the height map
// (chord) looked up in the piece's impostor, the moving piece found from outside.
// ---------------------------------------------------------------------------------------------
#import scene::shading::camera
#import scene::environment_pieces::shade_piece
#import scene::pieces::{piece_hit, piece_hit_normal, piece_kind, pieces}
#import height_maps::object_search::kind_height_bounds
#import height_maps::billboard_box::{BillboardOut, BillboardTargets, billboard_out, faces_eye, frag_depth_of}

@vertex
fn separated_billboard_vs(@builtin(vertex_index) vertex: u32,
                          @builtin(instance_index) piece: u32) -> BillboardOut {
    return billboard_out(vertex, piece, pieces[piece].centre.xyz,
                         kind_height_bounds(piece_kind(piece)));
}

@fragment
fn separated_billboard_fs(in: BillboardOut) -> BillboardTargets {
    let eye = camera.eye.xyz;
    if (!faces_eye(in.face_normal, in.world, eye)) { discard; }
    let dir = normalize(in.world - eye);
    let h = piece_hit(in.piece, eye, dir);
    if (h.w < 0.0) { discard; }
    let point = eye + dir * h.w;
    let normal = piece_hit_normal(in.piece, eye, dir, h);
    let n = select(normal, -normal, dot(normal, dir) > 0.0);
    var out: BillboardTargets;
    out.color = shade_piece(in.piece, point, n, eye);
    out.depth = frag_depth_of(camera.view_proj, point);
    return out;
}
