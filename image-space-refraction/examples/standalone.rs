//! Image-space refraction with caustics in your own wgpu renderer: no harness, no test kit.
//!
//! What is this crate's own: pick the variant by id, set the photon buffer's size by name,
//! and render the built-in `hu-qin` scene along its camera path (the refractor deforms:
//! nothing is precomputed); each frame prints its buffer and caustic passes' times. The rest
//! (your wgpu device, your colour and depth textures, the frame loop, the PNG) is
//! `example_framework`'s, each step a function you can lift.
//!
//! ```text
//! cargo run -p rtapprox-image-space-refraction --example image-space-refraction-standalone [-- [scene.gltf|scene.glb] [out.png]]
//! ```
//!
//! Writes `target/examples/image-space-refraction-standalone.png` unless given another path.

use example_framework::{Example, Result, pick};
use scene::{Scene, Technique};

struct ImageSpaceRefraction;

impl Example for ImageSpaceRefraction {
    const NAME: &'static str = "image-space-refraction-standalone";
    const FRAMES: u32 = 3;
    const NEEDS: &'static str = "a glass or mirror object";
    const SPANS: &'static [&'static str] = &["buffers", "caustics"];

    fn technique() -> Result<Box<dyn Technique>> {
        let mut technique = pick(
            image_space_refraction::techniques(),
            "image-space-refraction/caustics",
        )?;
        technique.set_param("photon_buffer", 64.0)?;
        Ok(technique)
    }

    fn built_in_scene() -> Result<Scene> {
        Ok(scene::load("hu-qin:refractor=morph")?)
    }
}

fn main() -> std::process::ExitCode {
    example_framework::main::<ImageSpaceRefraction>()
}

#[cfg(test)]
mod tests {
    /// `cargo test -p rtapprox-image-space-refraction --example image-space-refraction-standalone`: the
    /// example renders the deforming refractor to a finite image whose caustic lights the
    /// floor inside the refractor's shadow.
    #[test]
    fn renders_the_morphing_refractor_with_a_caustic() {
        let image = example_framework::run_for_test::<super::ImageSpaceRefraction>();
        let brightest = example_framework::brightest(&image);
        assert!(
            brightest > 1.0,
            "no caustic brighter than the lit floor ({brightest})"
        );
    }
}
