// ---------------------------------------------------------------------------------------------
// The same queries through the hardware's ray queries (wgpu's experimental `ray_query`): one
// BLAS of every world triangle, in the order of `bvh_triangles` (so the committed
// intersection's primitive index names the triangle), under one TLAS instance with the
// identity transform, `scene_tlas` at @group(0) @binding(#{TRACE_FIRST_BINDING}). The hardware decides the hit (its
// own watertight test); the distance is the hardware's, the attributes ours
// (raytracer::triangles).
// ---------------------------------------------------------------------------------------------
enable wgpu_ray_query;
#define_import_path raytracer::ray_query

#import raytracer::triangles::{NO_HIT, TraceHit, in_hole}

@group(0) @binding(#{TRACE_FIRST_BINDING}) var scene_tlas: acceleration_structure;

const RAY_FLAG_TERMINATE_ON_FIRST_HIT: u32 = 0x04u;
const RAY_QUERY_TRIANGLE: u32 = 1u;

// The geometry is opaque unless an object is cut out (raytracer::tracer marks the BLAS); then
// each candidate is kept unless it lies in a hole (raytracer::triangles::in_hole), so the
// hardware's traversal skips holes as the BVH's does.
fn trace(o: vec3f, d: vec3f, t_max: f32, any: bool) -> TraceHit {
    var flags = 0u;
    if (any) { flags |= RAY_FLAG_TERMINATE_ON_FIRST_HIT; }
    var rq: ray_query;
    rayQueryInitialize(&rq, scene_tlas, RayDesc(flags, 0xffu, 0.0, t_max, o, d));
    while (rayQueryProceed(&rq)) {
        let candidate = rayQueryGetCandidateIntersection(&rq);
        if (!in_hole(candidate.primitive_index, candidate.barycentrics)) {
            rayQueryConfirmIntersection(&rq);
        }
    }
    let hit = rayQueryGetCommittedIntersection(&rq);
    if (hit.kind != RAY_QUERY_TRIANGLE) {
        return TraceHit(NO_HIT, t_max);
    }
    return TraceHit(hit.primitive_index, hit.t);
}
