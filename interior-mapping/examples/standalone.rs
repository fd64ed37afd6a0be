//! Interior mapping in your own wgpu renderer: no harness, no test kit.
//!
//! What is this crate's own: pick the variant by id, set a parameter by name, build a scene
//! in code (a street with two box buildings and a round tower, each hull marked as a
//! building with its room size) and move the camera sideways along the street. The rest
//! (your wgpu device, your colour and depth textures, the frame loop, the PNG) is
//! `example_framework`'s, each step a function you can lift.
//!
//! ```text
//! cargo run -p rtapprox-interior-mapping --example interior-mapping-standalone [-- [scene.gltf|scene.glb] [out.png]]
//! ```
//!
//! Writes `target/examples/interior-mapping-standalone.png` unless given another path. A
//! glTF file must hold building hulls with a room layout (`harness export-scene city` writes
//! them); it brings its own camera, which the example moves the same way.

use example_framework::{Example, Result, pick, scenes, sideways};
use scene::{Camera, Scene, Technique};

struct InteriorMapping;

impl Example for InteriorMapping {
    const NAME: &'static str = "interior-mapping-standalone";
    const NEEDS: &'static str = "building hulls (role building, with a room layout)";

    fn technique() -> Result<Box<dyn Technique>> {
        let mut technique = pick(interior_mapping::techniques(), "interior-mapping/textured")?;
        // Parameters by name (`technique.params()` lists them): a light in every room,
        // radiance = albedo x 0.5, so the rooms show even where the sun does not reach
        // through a window.
        technique.set_param("interior_light", 0.5)?;
        Ok(technique)
    }

    fn built_in_scene() -> Result<Scene> {
        Ok(scenes::street())
    }

    fn view(scene: &Scene, frame: u32) -> (Camera, f32) {
        sideways(scene, frame, Self::FRAMES, 6.0)
    }
}

fn main() -> std::process::ExitCode {
    example_framework::main::<InteriorMapping>()
}

#[cfg(test)]
mod tests {
    /// `cargo test -p rtapprox-interior-mapping --example interior-mapping-standalone`: the example
    /// renders its built-in scene to a finite image that is not black.
    #[test]
    fn renders_the_built_in_scene() {
        let image = example_framework::run_for_test::<super::InteriorMapping>();
        let mean = example_framework::mean_radiance(&image.pixels);
        assert!(
            mean > 0.02,
            "the image is almost black (mean radiance {mean})"
        );
    }
}
