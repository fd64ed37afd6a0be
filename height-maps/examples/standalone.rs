//! Refractor height maps in your own wgpu renderer: no harness, no test kit.
//!
//! What is this crate's own: pick the variant by id (section 5.2's many-object algorithm
//! with every search in the pieces' height maps and every piece drawn as its billboard),
//! lower the height maps' resolution by name (from 256 to 128 texels), and render the built-in chess scene (glass and
//! mirror pieces of revolution and the knight, each with a plane of symmetry) along its
//! camera path, closer in. The rest (your wgpu device, your colour and depth textures, the frame loop,
//! the PNG) is `example_framework`'s, each step a function you can lift.
//!
//! ```text
//! cargo run -p rtapprox-height-maps --example height-maps-standalone [-- [scene.gltf|scene.glb] [out.png]]
//! ```
//!
//! Writes `target/examples/height-maps-standalone.png` unless given another path. A glTF
//! file must hold glass or mirror pieces marked as kinds of piece with a plane of symmetry
//! (`harness export-scene chess` writes one); it brings its own camera and camera path.

use example_framework::{Example, Result, along_path, pick};
use scene::{Camera, Scene, Technique};

struct HeightMaps;

impl Example for HeightMaps {
    const NAME: &'static str = "height-maps-standalone";
    const FRAMES: u32 = 3;
    const NEEDS: &'static str =
        "glass or mirror pieces of a few kinds, each with a plane of symmetry";
    const SPANS: &'static [&'static str] = &["update impostors"];

    fn technique() -> Result<Box<dyn Technique>> {
        let mut technique = pick(height_maps::techniques(), "height-maps/separated")?;
        // Parameters by name (`technique.params()` lists them, with ranges and help).
        technique.set_param("resolution", 128.0)?;
        Ok(technique)
    }

    fn built_in_scene() -> Result<Scene> {
        Ok(scene::load("chess")?)
    }

    /// Along the scene's camera path, at 40% of its distance to what it looks at: at 128
    /// pixels the whole board leaves a piece a dozen pixels.
    fn view(scene: &Scene, frame: u32) -> (Camera, f32) {
        let (camera, time) = along_path(scene, frame, Self::FRAMES);
        let eye = camera.target + 0.4 * (camera.eye - camera.target);
        (Camera { eye, ..camera }, time)
    }
}

fn main() -> std::process::ExitCode {
    example_framework::main::<HeightMaps>()
}

#[cfg(test)]
mod tests {
    /// `cargo test -p rtapprox-height-maps --example height-maps-standalone`: the example renders the
    /// chess scene to a finite image that is not black.
    #[test]
    fn renders_the_chess_scene() {
        let image = example_framework::run_for_test::<super::HeightMaps>();
        let mean = example_framework::mean_radiance(&image.pixels);
        assert!(
            mean > 0.02,
            "the image is almost black (mean radiance {mean})"
        );
    }
}
