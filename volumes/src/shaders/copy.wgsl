// Full-screen copies between the intermediate colour buffers and the target (the vertex stage
// is gpu::fullscreen's). The definition COPY_ALPHA: false writes alpha 1 (the final image,
// like the reference).
#import gpu::fullscreen::FullscreenOut

const COPY_ALPHA: bool = #{COPY_ALPHA};

@group(0) @binding(0) var copy_source: texture_2d<f32>;

// Copies the source texel; the quantisation to the destination format happens on store.
@fragment
fn fs_main(in: FullscreenOut) -> @location(0) vec4f {
    let c = textureLoad(copy_source, vec2i(in.position.xy), 0);
    return select(vec4f(c.rgb, 1.0), c, COPY_ALPHA);
}
