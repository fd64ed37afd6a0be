// Split layout (paper section 6: "the speed improves by an additional 20 percent if the
// distance values are separated from the color data"): copies the distance (alpha) of one
// face of the packed radiance+distance impostor into a one-channel face of its own.
#import gpu::fullscreen::FullscreenOut

@group(0) @binding(0) var packed_face: texture_2d<f32>;

@fragment
fn fs_main(in: FullscreenOut) -> @location(0) vec4f {
    let texel = vec2i(in.position.xy);
    return vec4f(textureLoad(packed_face, texel, 0).a, 0.0, 0.0, 0.0);
}
