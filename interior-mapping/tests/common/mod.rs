//! Shared helpers of the image tests: one GPU context per test binary, a small close view of
//! building 0 of the `city` scene, and rendering a technique into an `HdrImage`.
#![allow(dead_code, unused_imports)]

use glam::Vec3;
use scene::{Camera, Scene, Technique, View};
use testkit::Shot;

pub use testkit::context as ctx;

/// A camera on the street, 7 m from building 0's +x facade, seeing that face and the +z face
/// with the corner between them (the building has real interiors in the default `city`).
pub fn close_camera() -> Camera {
    Camera {
        eye: Vec3::new(17.0, 8.0, 16.0),
        target: Vec3::new(10.0, 9.5, 4.0),
        up: Vec3::Y,
        fov_y_deg: 50.0,
        orthographic: None,
    }
}

pub fn view(size: u32, time: f32) -> View {
    View {
        camera: close_camera(),
        time,
        width: size,
        height: size,
    }
}

/// Renders one frame of `technique` (prepared on the spot) and reads it back.
pub fn render(scene: &Scene, technique: &mut dyn Technique, view: &View) -> gpu::HdrImage {
    testkit::render(technique, scene, shot(view))
}

/// The reference of `view` on the default `city` (cached under that spec: load it with
/// `scene::load("city")`), without caustic photons (the city has no caustic casters).
pub fn reference(scene: &Scene, view: &View) -> truth::reference::ReferenceImage {
    testkit::reference("city", scene, shot(view), 0)
}

fn shot(view: &View) -> Shot {
    Shot {
        camera: view.camera,
        time: view.time,
        size: view.width,
    }
}

pub fn technique(id: &str) -> Box<dyn Technique> {
    testkit::technique(interior_mapping::techniques(), id)
}

/// Writes a PNG (sRGB of the clamped value) when INTERIOR_TEST_PNG names a folder.
pub fn dump(name: &str, image: &gpu::HdrImage) {
    let Ok(dir) = std::env::var("INTERIOR_TEST_PNG") else {
        return;
    };
    let path = std::path::Path::new(&dir).join(format!("{}.png", name.replace('/', "_")));
    testkit::save_png(image, &path);
}
