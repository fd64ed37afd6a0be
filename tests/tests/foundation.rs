//! The foundation's cross-crate claims: the shared raster pass agrees with the reference where
//! nothing is specular, and the classic environment map renders every specular scene.

use gpu::HdrImage;
use scene::foundation::{ClassicEnvMap, RasterTechnique};
use testkit::{Shot, reference, render};

/// Where nothing is specular, `raster` and `reference` compute the same diffuse model; they
/// differ only at shadow edges (shadow map vs shadow ray) and silhouettes (one sample per
/// pixel in both, but triangle rasterization rules vs exact BVH hits).
#[test]
fn raster_matches_reference_on_diffuse_cornell_sphere() {
    let spec = "cornell-sphere:material=diffuse";
    let (m, _) = raster_vs_reference(spec, &scene::load(spec).unwrap());
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

/// `raster` against the reference on `scene` (whose reference is cached under `key`), both at
/// 128 x 128 from the scene's camera at time 0: the metrics, printed, and the reference image.
fn raster_vs_reference(key: &str, scene: &scene::Scene) -> (truth::metrics::Metrics, HdrImage) {
    let shot = Shot::default_camera(scene, 0.0, 128);
    let truth = reference(key, scene, shot, 0);
    let image = render(&mut RasterTechnique, scene, shot);
    let (m, _) = truth::metrics::compare(&image, &truth.image, None);
    println!("raster vs reference, {key} 128^2: {m:?}");
    assert_eq!(m.nan_pixels, 0, "{key}");
    (m, truth.image)
}

/// The built-in scene `spec` with every specular object made grey diffuse, and the key its
/// reference is cached under.
fn all_diffuse(spec: &str) -> (String, scene::Scene) {
    let mut scene = scene::load(spec).unwrap();
    for o in &mut scene.objects {
        if o.material.is_specular() {
            o.material = scene::Material::diffuse(0.6, 0.6, 0.6);
        }
    }
    (format!("{spec} (all diffuse)"), scene)
}

/// The same under a spot (its cone's falloff, the cube shadow map) and a sun (the
/// orthographic shadow map fitted to the scene): the pool seen from above with every surface
/// diffuse, so that the sun lights the water, the coping and the ladder's shadows directly.
#[test]
fn raster_matches_reference_under_a_spot_and_a_sun() {
    for spec in [
        "cornell-sphere:material=diffuse,light=spot",
        "pool:view=above,light=sun",
        // And seen through an orthographic camera (`scene::foundation::viewpoint`).
        "cornell-box:camera=orthographic,light=spot",
    ] {
        let (key, scene) = all_diffuse(spec);
        let (m, _) = raster_vs_reference(&key, &scene);
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

/// An alpha cut-out (the perforated screen of `scene::builtin::CUTOUT_VARIANTS`, every surface
/// diffuse): the shared raster pass discards the holes, in the view and in the light's shadow
/// map, as the reference's rays pass through them. The screen's holes and its dotted shadow
/// agree but for their edges (bilinear alpha decided per pixel centre in both, the shadow
/// map's texels against exact shadow rays).
#[test]
fn raster_matches_reference_through_an_alpha_cut_out() {
    let (key, scene) = all_diffuse(scene::builtin::CUTOUT_VARIANTS[0]);
    let (m, truth) = raster_vs_reference(&key, &scene);
    // Measured 2026-11: FLIP 0.0047, RMSE 0.0025, 0.31% of pixels over 0.1.
    assert!(m.flip_mean < 0.01, "FLIP mean {}", m.flip_mean);
    assert!(
        m.flip_over_0_1_pct < 1.0,
        "{}% over 0.1",
        m.flip_over_0_1_pct
    );
    assert!(m.rmse < 0.01, "RMSE {}", m.rmse);
    // Without the cut-out the screen is opaque: far from the reference.
    let mut opaque = scene.clone();
    for o in &mut opaque.objects {
        if let scene::Material::Diffuse { cutout, .. } = &mut o.material {
            *cutout = None;
        }
    }
    let shot = Shot::default_camera(&scene, 0.0, 128);
    let solid = render(&mut RasterTechnique, &opaque, shot);
    let (without, _) = truth::metrics::compare(&solid, &truth, None);
    assert!(
        without.flip_mean > 2.0 * m.flip_mean,
        "an opaque screen is as close ({}) as the cut-out one ({})",
        without.flip_mean,
        m.flip_mean
    );
}
