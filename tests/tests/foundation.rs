//! The foundation's cross-crate claims: the shared raster pass agrees with the reference where
//! nothing is specular, and the classic environment map renders every specular scene.

use scene::foundation::{ClassicEnvMap, RasterTechnique};
use testkit::{Shot, reference, render};

/// Where nothing is specular, `raster` and `reference` compute the same diffuse model; they
/// differ only at shadow edges (shadow map vs shadow ray) and silhouettes (one sample per
/// pixel in both, but triangle rasterization rules vs exact BVH hits).
#[test]
fn raster_matches_reference_on_diffuse_cornell_sphere() {
    let spec = "cornell-sphere:material=diffuse";
    let scene = scene::load(spec).unwrap();
    let shot = Shot::default_camera(&scene, 0.0, 128);
    let truth = reference(spec, &scene, shot, 0);
    let image = render(&mut RasterTechnique, &scene, shot);
    let (m, _) = truth::metrics::compare(&image, &truth.image, None);
    println!("raster vs reference, diffuse cornell-sphere 128^2: {m:?}");
    assert_eq!(m.nan_pixels, 0);
    // Measured 2026-11: FLIP 0.00085, RMSE 0.0025, 0.24% of pixels over 0.1 (shadow edges).
    assert!(
        m.flip_mean < 0.005,
        "FLIP mean {} over bound 0.005",
        m.flip_mean
    );
    assert!(
        m.flip_over_0_1_pct < 1.0,
        "{}% pixels with FLIP > 0.1",
        m.flip_over_0_1_pct
    );
    assert!(m.rmse < 0.01, "RMSE {}", m.rmse);
}

/// The same under a spot (its cone's falloff, the cube shadow map) and a sun (the
/// orthographic shadow map fitted to the scene): the pool seen from above with every surface
/// diffuse, so that the sun lights the water, the coping and the ladder's shadows directly.
#[test]
fn raster_matches_reference_under_a_spot_and_a_sun() {
    for spec in [
        "cornell-sphere:material=diffuse,light=spot",
        "pool:view=above,light=sun",
    ] {
        let mut scene = scene::load(spec).unwrap();
        for o in &mut scene.objects {
            if o.material.is_specular() {
                o.material = scene::Material::Diffuse {
                    albedo: glam::Vec3::splat(0.6),
                    texture: None,
                };
            }
        }
        let key = format!("{spec} (all diffuse)");
        let shot = Shot::default_camera(&scene, 0.0, 128);
        let truth = reference(&key, &scene, shot, 0);
        let image = render(&mut RasterTechnique, &scene, shot);
        let (m, _) = truth::metrics::compare(&image, &truth.image, None);
        println!("raster vs reference, {key} 128^2: {m:?}");
        assert_eq!(m.nan_pixels, 0);
        assert!(m.flip_mean < 0.01, "{spec}: FLIP mean {}", m.flip_mean);
        assert!(
            m.flip_over_0_1_pct < 2.0,
            "{spec}: {}% pixels with FLIP > 0.1",
            m.flip_over_0_1_pct
        );
        assert!(m.rmse < 0.02, "{spec}: RMSE {}", m.rmse);
    }
}

/// Every built-in scene (and material variant) with a reflector or refractor renders finite
/// pixels with the classic environment map, and its specular object is not black.
#[test]
fn classic_envmap_renders_every_specular_scene() {
    let specs = [
        "cornell-sphere",
        "cornell-sphere:material=glass-1.1",
        "cornell-sphere:material=glass-0.75",
        "cornell-sphere:material=mirror",
        "cornell-sphere:material=gold",
        "cornell-sphere:material=copper",
        "cornell-box",
        "cornell-box:material=glass-1.5",
        "refraction-bunny",
    ];
    let size = 64;
    for spec in specs {
        let scene = scene::load(spec).unwrap();
        let shot = Shot::default_camera(&scene, 0.0, size);
        let image = render(&mut ClassicEnvMap::default(), &scene, shot);
        assert_eq!(image.non_finite_count(), 0, "{spec}: non-finite pixels");
        let truth = reference(spec, &scene, shot, 0);
        let special = scene.special_objects();
        let lit = (0..image.pixels.len())
            .filter(|&i| {
                truth.object_ids[i] >= 0 && special.contains(&(truth.object_ids[i] as usize))
            })
            .filter(|&i| image.pixels[i][..3].iter().sum::<f32>() > 1e-3)
            .count();
        assert!(lit > 20, "{spec}: specular object shows {lit} lit pixels");
    }
}

/// The classic map is direction-only, so it cannot match the reference exactly; it must at
/// least be in the right range on the sphere (a sanity bound, not a quality claim).
#[test]
fn classic_envmap_is_near_reference_on_mirror_sphere() {
    let spec = "cornell-sphere:material=mirror";
    let scene = scene::load(spec).unwrap();
    let shot = Shot::default_camera(&scene, 0.0, 96);
    let truth = reference(spec, &scene, shot, 0);
    let image = render(&mut ClassicEnvMap::default(), &scene, shot);
    let (m, _) = truth::metrics::compare(&image, &truth.image, Some(&truth.mask));
    println!("classic vs reference, mirror cornell-sphere 96^2: {m:?}");
    assert!(m.masked_pixels > 500);
    assert!(
        m.flip_mean_masked < 0.5,
        "masked FLIP {}",
        m.flip_mean_masked
    );
}
