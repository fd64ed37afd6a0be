//! Screen-space photon tracing in your own wgpu renderer: no harness, no test kit.
//!
//! What is this crate's own: pick the variant by id, set the photon count by name, and
//! render the built-in `pool` seen by a swimmer along its camera path (the waves drift, the
//! caustics move); each frame prints its caustic and splat passes' times. The rest (your wgpu
//! device, your colour and depth textures, the frame loop, the PNG) is
//! `example_framework`'s, each step a function you can lift.
//!
//! ```text
//! cargo run -p rtapprox-screen-photons --example screen-photons-standalone [-- [scene.gltf|scene.glb] [out.png]]
//! ```
//!
//! Writes `target/examples/screen-photons-standalone.png` unless given another path.

use example_framework::{Example, Result, pick};
use scene::{Scene, Technique};

struct ScreenPhotons;

impl Example for ScreenPhotons {
    const NAME: &'static str = "screen-photons-standalone";
    const FRAMES: u32 = 3;
    const NEEDS: &'static str = "a glass or mirror object";
    const SPANS: &'static [&'static str] = &["caustics", "splat"];

    fn technique() -> Result<Box<dyn Technique>> {
        let mut technique = pick(screen_photons::techniques(), "screen-photons/dda")?;
        technique.set_param("photons", 192.0)?;
        Ok(technique)
    }

    fn built_in_scene() -> Result<Scene> {
        Ok(scene::load("pool")?)
    }
}

fn main() -> std::process::ExitCode {
    example_framework::main::<ScreenPhotons>()
}

#[cfg(test)]
mod tests {
    /// `cargo test -p rtapprox-screen-photons --example screen-photons-standalone`: the example renders
    /// the pool to a finite image in which the caustics light the floor.
    #[test]
    fn renders_the_pool_with_caustics() {
        let image = example_framework::run_for_test::<super::ScreenPhotons>();
        // The lower half is the pool's floor, lit only by caustics.
        let floor = example_framework::mean_radiance(&image.pixels[image.pixels.len() / 2..]);
        assert!(floor > 0.05, "the floor is dark (mean radiance {floor})");
    }
}
