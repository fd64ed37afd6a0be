// ---------------------------------------------------------------------------------------------
// The two queries the ray tracer's passes ask, answered by one traversal's `trace`: the BVH's
// (raytracer::bvh), or the hardware's ray queries (raytracer::ray_query) with the definition
// RAY_QUERY.
// ---------------------------------------------------------------------------------------------
#define_import_path raytracer::queries

#import raytracer::triangles::{NO_HIT, TraceHit}
#ifdef RAY_QUERY
#import raytracer::ray_query::trace
#else
#import raytracer::bvh::trace
#endif

// The nearest hit on o + t d, t in [0, t_max].
fn trace_closest(o: vec3f, d: vec3f, t_max: f32) -> TraceHit {
    return trace(o, d, t_max, false);
}

// Whether anything lies on o + t d, t in [0, t_max].
fn trace_any(o: vec3f, d: vec3f, t_max: f32) -> bool {
    return trace(o, d, t_max, true).triangle != NO_HIT;
}
