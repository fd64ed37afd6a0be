// The entry points of image-space refraction (image_space_refraction::refract): the refractor's
// vertex stage, its front and back buffers, and the refractor shaded from the eye. The nearby
// variants compose this file with image_space_refraction::nearby_radiance overriding the
// radiance that leaves the refractor.
#import scene::shading::{SceneVertexIn, SceneVertexOut, camera, in_cutout_hole, scene_vertex, specular_event, specular_shade}
#import image_space_refraction::refract::{RefractorOut, buffer_fragment, normal_thickness, outgoing_radiance, through_refractor}

@vertex
fn refractor_vs(v: SceneVertexIn, @builtin(instance_index) object: u32,
                @builtin(vertex_index) vertex: u32) -> RefractorOut {
    // scene_vs's placement, and Wyman's d_N of this vertex.
    let placed = scene_vertex(v, object);
    var out: RefractorOut;
    out.clip = placed.clip;
    out.world = placed.world;
    out.normal = placed.normal;
    out.uv = placed.uv;
    out.object = placed.object;
    out.d_n = normal_thickness[vertex];
    return out;
}

@fragment
fn front_buffer_fs(in: SceneVertexOut) -> @location(0) vec4f {
    if (in_cutout_hole(in.object, in.uv)) { discard; }
    return buffer_fragment(in, true);
}

@fragment
fn back_buffer_fs(in: SceneVertexOut) -> @location(0) vec4f {
    if (in_cutout_hole(in.object, in.uv)) { discard; }
    return buffer_fragment(in, false);
}

@fragment
fn refract_fs(in: RefractorOut) -> @location(0) vec4f {
    let eye = camera.eye.xyz;
    let v = normalize(in.world - eye);
    let e = specular_event(in.object, in.normal, in.world, eye, v);
    let reflected = outgoing_radiance(in.world, e.reflected);
    var refracted = reflected;
    if (e.refracted.w > 0.5) {
        if (e.entering) {
            refracted = through_refractor(in, e, v);
        } else {
            refracted = outgoing_radiance(in.world, e.refracted.xyz);
        }
    }
    return vec4f(specular_shade(e, reflected, refracted), distance(in.world, eye));
}
