//! Refractor distance maps in your own wgpu renderer: no harness, no test kit.
//!
//! What is this crate's own: pick the variant by id, render the shared mirror-and-glass room
//! (two kinds of refractor map, rays bouncing between the mirror and the glass sphere up to
//! four times) while the camera moves sideways. The rest (your wgpu device, your colour and
//! depth textures, the frame loop, the PNG) is `example_framework`'s, each step a function
//! you can lift.
//!
//! ```text
//! cargo run -p rtapprox-refractor-maps --example refractor-maps-standalone [-- [scene.gltf|scene.glb] [out.png]]
//! ```
//!
//! Writes `target/examples/refractor-maps-standalone.png` unless given another path. A glTF
//! file must hold a mirror, metal or glass object; it brings its own camera, which the example
//! moves the same way.

use example_framework::{Example, Result, pick, scenes, sideways};
use scene::{Camera, Scene, Technique};

struct RefractorMaps;

impl Example for RefractorMaps {
    const NAME: &'static str = "refractor-maps-standalone";
    const NEEDS: &'static str = "a mirror, metal or glass object";

    fn technique() -> Result<Box<dyn Technique>> {
        // Every variant of the crate, picked by id: up to four bounces between the maps.
        pick(
            refractor_maps::techniques(),
            "refractor-maps/multi-bounce-4",
        )
    }

    fn built_in_scene() -> Result<Scene> {
        Ok(scenes::mirror_and_glass_room())
    }

    fn view(scene: &Scene, frame: u32) -> (Camera, f32) {
        sideways(scene, frame, Self::FRAMES, 0.4)
    }
}

fn main() -> std::process::ExitCode {
    example_framework::main::<RefractorMaps>()
}

#[cfg(test)]
mod tests {
    /// `cargo test -p rtapprox-refractor-maps --example refractor-maps-standalone`: the example renders
    /// its built-in scene to a finite image that is not black.
    #[test]
    fn renders_the_built_in_scene() {
        let image = example_framework::run_for_test::<super::RefractorMaps>();
        let mean = example_framework::mean_radiance(&image.pixels);
        assert!(
            mean > 0.02,
            "the image is almost black (mean radiance {mean})"
        );
    }
}
