//! Renders the known failure cases from close cameras the harness's default view does not
//! reach: the seam at a box building's corner and the window/furniture distortion on the
//! cylinder and sphere buildings. Writes PNGs (sRGB of the clamped value) into a folder.
//!
//! `cargo run -p rtapprox-interior-mapping --example failure_cases -- interior-mapping/docs`

use glam::Vec3;
use scene::Camera;
use std::path::Path;
use testkit::Shot;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args().nth(1).unwrap_or_else(|| ".".into());
    let size = 192;
    let scene = scene::load("city")?;
    // Building 0 is a box at the origin (20 x 40 x 20 m), building 1 the cylinder at x = 32,
    // building 2 the sphere (radius 10) centred at (64, 10, 0).
    let views = [
        (
            "box-corner",
            Vec3::new(16.0, 9.0, 16.0),
            Vec3::new(10.0, 8.0, 10.0),
        ),
        (
            "cylinder",
            Vec3::new(50.0, 9.0, 14.0),
            Vec3::new(32.0, 9.0, 0.0),
        ),
        (
            "sphere",
            Vec3::new(82.0, 12.0, 14.0),
            Vec3::new(64.0, 10.0, 0.0),
        ),
    ];
    for (name, eye, target) in views {
        let camera = Camera {
            eye,
            target,
            up: Vec3::Y,
            fov_y_deg: 60.0,
            orthographic: None,
        };
        for id in ["interior-mapping/textured", "interior-mapping/furniture"] {
            let mut technique = testkit::technique(interior_mapping::techniques(), id);
            let shot = Shot {
                camera,
                time: 0.0,
                size,
            };
            let image = testkit::render(technique.as_mut(), &scene, shot);
            let path = Path::new(&out).join(format!(
                "failure-{name}-{}.png",
                id.replace("interior-mapping/", "")
            ));
            testkit::save_png(&image, &path);
            println!("wrote {}", path.display());
        }
    }
    Ok(())
}
