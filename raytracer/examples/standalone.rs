//! The exact GPU ray tracer in your own wgpu renderer: no harness, no test kit.
//!
//! What is this crate's own: the tracer with caustics, with fewer photons than the
//! reference's density (the caustic is then grainier, and the frame cheaper), on the built-in
//! `hu-qin` scene whose refractor deforms along the camera path (the BVH is rebuilt for each
//! frame's time); each frame prints its eye and photon passes' times. The rest (your wgpu
//! device, your colour and depth textures, the frame loop, the PNG) is
//! `example_framework`'s, each step a function you can lift.
//!
//! ```text
//! cargo run -p rtapprox-raytracer --example raytracer-standalone [-- [scene.gltf|scene.glb] [out.png]]
//! ```
//!
//! Writes `target/examples/raytracer-standalone.png` unless given another path.

use example_framework::{Example, Result};
use scene::{Scene, Technique};

struct RayTracer;

impl Example for RayTracer {
    const NAME: &'static str = "raytracer-standalone";
    const SIZE: u32 = 96;
    const FRAMES: u32 = 3;
    const NEEDS: &'static str = "any object";
    const SPANS: &'static [&'static str] = &["eye", "photons"];

    fn technique() -> Result<Box<dyn Technique>> {
        let mut technique = Box::new(raytracer::RayTracer::new(raytracer::Variant::Caustics));
        technique.set_param("photons", 200_000.0)?;
        Ok(technique)
    }

    fn built_in_scene() -> Result<Scene> {
        Ok(scene::load("hu-qin:refractor=morph")?)
    }
}

fn main() -> std::process::ExitCode {
    example_framework::main::<RayTracer>()
}

#[cfg(test)]
mod tests {
    /// `cargo test -p rtapprox-raytracer --example raytracer-standalone`: the example traces the
    /// deforming refractor to a finite image whose caustic lights the floor.
    #[test]
    fn traces_the_morphing_refractor_with_a_caustic() {
        let image = example_framework::run_for_test::<super::RayTracer>();
        let brightest = example_framework::brightest(&image);
        assert!(
            brightest > 1.0,
            "no caustic brighter than the lit floor ({brightest})"
        );
    }
}
