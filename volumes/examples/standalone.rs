//! Soft volumes in your own wgpu renderer: no harness, no test kit.
//!
//! What is this crate's own: pick the variant by id (particles and the large volume, nine
//! slices), take the built-in `smoke` scene with four particles (a yard with posts, a log, a
//! large textured smoke volume and soft particles rising beside it) and move the camera
//! sideways through it. The rest (your wgpu
//! device, your colour and depth textures, the frame loop, the PNG) is
//! `example_framework`'s, each step a function you can lift.
//!
//! ```text
//! cargo run -p rtapprox-volumes --example volumes-standalone [-- [scene.gltf|scene.glb] [out.png]]
//! ```
//!
//! Writes `target/examples/volumes-standalone.png` unless given another path. A glTF file
//! must hold a volume (`harness export-scene smoke` writes one); it brings its own camera,
//! which the example moves the same way.

use example_framework::{Example, Result, pick, sideways};
use scene::{Camera, Scene, Technique};

struct Volumes;

impl Example for Volumes {
    const NAME: &'static str = "volumes-standalone";
    const NEEDS: &'static str = "a volume (scene::Volume)";

    fn technique() -> Result<Box<dyn Technique>> {
        pick(volumes::techniques(), "volumes/particles-slices-9")
    }

    fn built_in_scene() -> Result<Scene> {
        // The built-in yard (posts, a log, a large textured smoke volume) with four soft
        // particles rising beside it: `scene::builtin::smoke` shows how it is built.
        Ok(scene::load("smoke:particles=4")?)
    }

    fn view(scene: &Scene, frame: u32) -> (Camera, f32) {
        sideways(scene, frame, Self::FRAMES, 1.0)
    }
}

fn main() -> std::process::ExitCode {
    example_framework::main::<Volumes>()
}

#[cfg(test)]
mod tests {
    /// `cargo test -p rtapprox-volumes --example volumes-standalone`: the example renders its built-in
    /// scene to a finite image that is not black.
    #[test]
    fn renders_the_built_in_scene() {
        let image = example_framework::run_for_test::<super::Volumes>();
        let mean = example_framework::mean_radiance(&image.pixels);
        assert!(
            mean > 0.02,
            "the image is almost black (mean radiance {mean})"
        );
    }
}
