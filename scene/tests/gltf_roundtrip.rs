//! Export to .glb and import back: lossless for every built-in scene, and the core glTF
//! (what Blender reads) carries the materials, lights and camera on its own.

use glam::{Mat4, Quat, Vec2, Vec3};
use scene::gltf_io::{export_glb, import, import_slice, to_glb_bytes};
use scene::{Building, Material, Motion, Roles, Scene, Texture, Volume};

/// Compares two scenes field by field so that a failure names the first difference, then
/// compares them whole (so nothing added to the model later escapes the check).
fn assert_same(back: &Scene, original: &Scene, what: &str) {
    assert_eq!(back.name, original.name, "{what}: name");
    assert_eq!(back.background, original.background, "{what}: background");
    assert_eq!(back.camera, original.camera, "{what}: camera");
    assert_eq!(
        back.camera_path, original.camera_path,
        "{what}: camera path"
    );
    assert_eq!(back.lights, original.lights, "{what}: lights");
    assert_eq!(back.volumes, original.volumes, "{what}: volumes");
    assert_eq!(
        back.textures.len(),
        original.textures.len(),
        "{what}: texture count"
    );
    for (b, o) in back.textures.iter().zip(&original.textures) {
        assert_eq!(
            (&b.name, b.width, b.height),
            (&o.name, o.width, o.height),
            "{what}: texture"
        );
        assert!(
            b.rgba8 == o.rgba8,
            "{what}: texels of texture \"{}\" differ",
            o.name
        );
    }
    assert_eq!(
        back.objects.len(),
        original.objects.len(),
        "{what}: object count"
    );
    for (b, o) in back.objects.iter().zip(&original.objects) {
        let w = format!("{what}: object \"{}\"", o.name);
        assert_eq!(b.name, o.name, "{w}: name");
        assert_eq!(b.material, o.material, "{w}: material");
        assert_eq!(b.transform, o.transform, "{w}: transform");
        assert_eq!(b.roles, o.roles, "{w}: roles");
        assert_eq!(b.motion, o.motion, "{w}: motion");
        assert_eq!(b.building, o.building, "{w}: building");
        assert!(
            b.mesh.positions == o.mesh.positions,
            "{w}: positions differ"
        );
        assert!(b.mesh.normals == o.mesh.normals, "{w}: normals differ");
        assert!(b.mesh.uvs == o.mesh.uvs, "{w}: uvs differ");
        assert!(b.mesh.indices == o.mesh.indices, "{w}: indices differ");
    }
    assert!(back == original, "{what}: scenes differ");
}

fn round_trip(scene: &Scene, what: &str) {
    let bytes = to_glb_bytes(scene).unwrap_or_else(|e| panic!("{what}: export failed: {e}"));
    let back = import_slice(&bytes, &format!("{what}.glb"))
        .unwrap_or_else(|e| panic!("{what}: import failed: {e}"));
    assert_same(&back, scene, what);
}

#[test]
fn every_builtin_scene_round_trips_exactly() {
    let infos = scene::builtin::builtin_scenes();
    assert!(infos.len() >= 5);
    for info in infos {
        let original = scene::load(info.name).unwrap();
        round_trip(&original, info.name);
    }
}

#[test]
fn builtin_variants_round_trip_exactly() {
    for spec in [
        "cornell-sphere:material=glass-0.75",
        "cornell-sphere:material=gold,sphere_x=0.3",
        "cornell-box:material=copper",
        "cornell-box:material=diffuse",
        "refraction-bunny:ior=1.1",
        "city:buildings=5,rooms_per_building=77",
        "smoke:particles=3",
    ]
    .into_iter()
    .chain(scene::builtin::LIGHT_VARIANTS)
    .chain(scene::builtin::CAMERA_VARIANTS)
    .chain(scene::builtin::CUTOUT_VARIANTS)
    {
        round_trip(&scene::load(spec).unwrap(), spec);
    }
}

/// Values the built-in scenes do not exercise: albedo at the ends of its range (1 and -0.0),
/// awkward floats, a scaled and
/// rotated transform, a tilted camera, odd texture sizes with alpha, empty and non-ASCII
/// names, an empty camera path.
#[test]
fn awkward_values_round_trip_exactly() {
    let mut s = scene::load("cornell-sphere").unwrap();
    s.name = "ünïcode \"quoted\" scene".into();
    // A spot whose cones are equal (a hard edge, as Blender writes a spot without blend).
    s.lights.push(scene::Light {
        kind: scene::LightKind::Spot {
            direction: Vec3::new(0.3, -1.0, 0.2).normalize(),
            inner_cone: 0.4,
            outer_cone: 0.4,
        },
        ..scene::Light::point("hard spot", Vec3::new(0.1, 1.7, 0.2), Vec3::splat(1.5))
    });
    // Emission above 1 (the strength extension) and below it.
    let diffuse: Vec<usize> = (0..s.objects.len())
        .filter(|&i| !s.objects[i].material.is_specular())
        .collect();
    s.objects[diffuse[0]].emission = Vec3::new(3.7, 0.1, 0.0);
    s.objects[diffuse[1]].emission = Vec3::new(0.3, 0.2, 1.0 / 3.0);
    s.background = Vec3::new(0.1, 1.0e-30, 3.4e38);
    s.camera.up = Vec3::new(0.1, 0.9, 0.05);
    s.camera.fov_y_deg = 0.1f32 + 33.3;
    s.camera_path.keys.clear();
    s.objects[0].name = String::new();
    s.objects[0].material = Material::Diffuse {
        albedo: Vec3::new(1.0, 0.1, -0.0),
        texture: Some(1),
        cutout: None,
    };
    s.objects[1].transform = Mat4::from_scale_rotation_translation(
        Vec3::new(0.3, 1.7, 2.1),
        Quat::from_rotation_z(0.3),
        Vec3::splat(0.1),
    );
    s.objects[1].roles = Roles::VOLUME | Roles::HEIGHT_FIELD;
    s.objects[1].building = Some(Building {
        room_size: Vec3::new(1.0 / 3.0, 2.0, 0.7),
    });
    s.objects[1].motion = Motion {
        keys: vec![(0.25, Vec3::new(1e-7, -2.0, 1.0 / 7.0))],
    };
    s.objects[2].material = Material::Metal {
        n: Vec3::new(0.2, 1.0 / 3.0, 5.0),
        k: Vec3::new(0.0, 7.5, 1e-3),
    };
    s.objects[2].mesh.uvs[0] = Vec2::new(-3.25, 1.0e6);
    s.textures.push(Texture {
        name: String::new(),
        width: 1,
        height: 1,
        rgba8: vec![1, 2, 3, 4],
    });
    s.textures.push(Texture {
        name: "odd".into(),
        width: 3,
        height: 5,
        rgba8: (0..60).map(|i| (i * 37 % 256) as u8).collect(),
    });
    s.volumes.push(Volume {
        name: "v".into(),
        center: Vec3::new(0.1, 0.2, 0.3),
        radius: 0.7,
        color: Vec3::new(0.3, 0.2, 0.1),
        density: 2.5,
        profile: scene::DensityProfile {
            falloff: 1.5,
            noise: 0.35,
            noise_frequency: 2.75,
        },
        particle: true,
        motion: Motion::default(),
    });
    s.validate().unwrap();
    round_trip(&s, "awkward");
}

#[test]
fn export_to_file_and_import_from_path() {
    let original = scene::load("refraction-bunny").unwrap();
    let dir = std::env::temp_dir().join(format!("scene-gltf-roundtrip-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("bunny scene.glb");
    export_glb(&original, &path).unwrap();
    let back = import(&path).unwrap();
    assert_same(&back, &original, "refraction-bunny via file");
    // The loader used by the harness takes the same path.
    let loaded = scene::load(path.to_str().unwrap()).unwrap();
    assert!(loaded == original);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn invalid_scenes_are_not_exported() {
    let mut s = scene::load("cornell-sphere").unwrap();
    s.objects[0].transform.x_axis.x = f32::NAN;
    let e = to_glb_bytes(&s).unwrap_err().to_string();
    assert!(e.contains("non-finite transform"), "{e}");
    let mut s = scene::load("smoke").unwrap();
    s.volumes[0].density = f32::INFINITY;
    let e = to_glb_bytes(&s).unwrap_err().to_string();
    assert!(e.contains("volume"), "{e}");
    let mut s = scene::load("cornell-sphere").unwrap();
    s.objects[0].mesh = scene::Mesh::default();
    assert!(to_glb_bytes(&s).is_err());
}

// ---------------------------------------------------------------------------------------
// The core glTF, read by other tools, and the importer's reading of it without extras.

fn glb_json(bytes: &[u8]) -> (serde_json::Value, Vec<u8>) {
    let json_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let json: serde_json::Value = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
    let bin = bytes.get(20 + json_len + 8..).unwrap_or(&[]).to_vec();
    (json, bin)
}

fn make_glb(json: &serde_json::Value, bin: &[u8]) -> Vec<u8> {
    let mut j = serde_json::to_vec(json).unwrap();
    while !j.len().is_multiple_of(4) {
        j.push(b' ');
    }
    let total = 12 + 8 + j.len() + 8 + bin.len();
    let mut out = b"glTF".to_vec();
    for w in [2u32, total as u32, j.len() as u32, 0x4E4F534A] {
        out.extend_from_slice(&w.to_le_bytes());
    }
    out.extend_from_slice(&j);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(&0x004E4942u32.to_le_bytes());
    out.extend_from_slice(bin);
    out
}

fn strip_extras(v: &mut serde_json::Value) {
    match v {
        serde_json::Value::Object(map) => {
            map.remove("extras");
            map.values_mut().for_each(strip_extras);
        }
        serde_json::Value::Array(items) => items.iter_mut().for_each(strip_extras),
        _ => {}
    }
}

#[test]
fn core_gltf_is_what_blender_needs() {
    let s = scene::load("cornell-box:material=gold").unwrap();
    let doc = gltf::Gltf::from_slice(&to_glb_bytes(&s).unwrap()).unwrap();
    // Gold: metallic, smooth, base colour = normal-incidence reflectance (yellowish).
    let gold = doc
        .materials()
        .find(|m| m.name() == Some("sphere material"))
        .unwrap();
    let pbr = gold.pbr_metallic_roughness();
    assert_eq!((pbr.metallic_factor(), pbr.roughness_factor()), (1.0, 0.0));
    let c = pbr.base_color_factor();
    assert!(
        c[0] > 0.8 && c[1] > 0.5 && c[2] < 0.5,
        "gold base colour {c:?}"
    );
    // Lights: KHR_lights_punctual point light, 683 cd per W/sr.
    let light = doc.lights().unwrap().next().unwrap();
    assert!(matches!(
        light.kind(),
        gltf::khr_lights_punctual::Kind::Point
    ));
    assert_eq!(light.intensity(), 2.5 * 683.0);
    // The camera is a node with a perspective camera at the eye.
    let cam_node = doc.nodes().find(|n| n.camera().is_some()).unwrap();
    let (t, _, _) = cam_node.transform().decomposed();
    assert_eq!(Vec3::from(t), s.camera.eye);
    let camera = cam_node.camera().unwrap();
    let gltf::camera::Projection::Perspective(p) = camera.projection() else {
        panic!("not perspective")
    };
    assert!((p.yfov().to_degrees() - s.camera.fov_y_deg).abs() < 1e-4);

    // Glass: transmission and ior.
    let s = scene::load("refraction-bunny").unwrap();
    let doc = gltf::Gltf::from_slice(&to_glb_bytes(&s).unwrap()).unwrap();
    let glass = doc
        .materials()
        .find(|m| m.name() == Some("bunny material"))
        .unwrap();
    assert_eq!(glass.transmission().unwrap().transmission_factor(), 1.0);
    assert_eq!(glass.ior(), Some(1.5));
    assert!(
        doc.extensions_used()
            .any(|e| e == "KHR_materials_transmission")
    );
    // The checker texture is an embedded PNG.
    let image = doc.images().next().unwrap();
    assert!(matches!(
        image.source(),
        gltf::image::Source::View {
            mime_type: "image/png",
            ..
        }
    ));
}

/// With every `extras` removed, the importer reads the core glTF back into (nearly) the same
/// scene: that is what it does with files from other tools.
#[test]
fn core_gltf_alone_imports_to_nearly_the_same_scene() {
    for spec in [
        "cornell-box:material=gold",
        "cornell-sphere:material=glass-1.5",
        "refraction-bunny",
        "city:buildings=4",
        "cornell-sphere:light=spot",
        "pool:light=sun",
        scene::builtin::CUTOUT_VARIANTS[0],
    ] {
        let mut s = scene::load(spec).unwrap();
        if spec == "cornell-sphere:material=glass-1.5" {
            // Emission above 1 (factor and strength) and below it (factor alone).
            let diffuse: Vec<usize> = (0..s.objects.len())
                .filter(|&i| !s.objects[i].material.is_specular())
                .collect();
            s.objects[diffuse[0]].emission = Vec3::new(3.7, 0.1, 0.0);
            s.objects[diffuse[1]].emission = Vec3::new(0.3, 0.2, 1.0 / 3.0);
        }
        let (mut json, bin) = glb_json(&to_glb_bytes(&s).unwrap());
        strip_extras(&mut json);
        let back = import_slice(&make_glb(&json, &bin), "stripped.glb").unwrap();
        assert_eq!(back.objects.len(), s.objects.len(), "{spec}");
        for (b, o) in back.objects.iter().zip(&s.objects) {
            assert_eq!(b.name, o.name);
            assert!(
                b.mesh == o.mesh && b.transform == o.transform,
                "{spec}: {} geometry",
                o.name
            );
            match (&b.material, &o.material) {
                (Material::Glass { ior: a }, Material::Glass { ior: e }) => assert_eq!(a, e),
                (
                    Material::Diffuse {
                        albedo: a,
                        texture: ta,
                        cutout: ca,
                    },
                    Material::Diffuse {
                        albedo: e,
                        texture: te,
                        cutout: ce,
                    },
                ) => {
                    // A cut-out is glTF's own MASK: it needs no extras.
                    assert_eq!((ta, ca), (te, ce), "{spec}: {}", o.name);
                    assert!((*a - e.clamp(Vec3::ZERO, Vec3::ONE)).abs().max_element() < 1e-6);
                }
                (Material::Metal { n, k }, Material::Metal { n: n0, k: k0 }) => {
                    // The seeds' approximation is Schlick's form in F0, so the same
                    // normal-incidence reflectance gives the same reflectance at every angle.
                    for cos in [1.0, 0.5, 0.1] {
                        let f = gpu::prelude::fresnel_nk(cos, *n, *k);
                        let f0 = gpu::prelude::fresnel_nk(cos, *n0, *k0);
                        assert!(
                            (f - f0).abs().max_element() < 1e-4,
                            "{spec}: {f} vs {f0} at cos {cos}"
                        );
                    }
                }
                (a, e) => panic!("{spec}: {} became {a:?}, was {e:?}", o.name),
            }
            if !matches!(o.material, Material::Diffuse { .. }) {
                assert_eq!(b.roles, o.roles, "{spec}: default roles of {}", o.name);
            }
            let tolerance = 1e-6 * o.emission.max_element().max(1.0);
            assert!(
                (b.emission - o.emission).abs().max_element() <= tolerance,
                "{spec}: {} emits {} back, {} before",
                o.name,
                b.emission,
                o.emission
            );
        }
        assert_eq!(back.textures.len(), s.textures.len());
        for (b, o) in back.lights.iter().zip(&s.lights) {
            assert_eq!((&b.name, b.position), (&o.name, o.position));
            assert_eq!(b.kind_name(), o.kind_name(), "{spec}: {}", o.name);
            if let (Some(d), Some(d0)) = (b.direction(), o.direction()) {
                assert!(
                    d.dot(d0) > 1.0 - 1e-6,
                    "{spec}: {} points {d}, was {d0}",
                    o.name
                );
            }
            if let (
                scene::LightKind::Spot {
                    inner_cone: i,
                    outer_cone: u,
                    ..
                },
                scene::LightKind::Spot {
                    inner_cone: i0,
                    outer_cone: u0,
                    ..
                },
            ) = (b.kind, o.kind)
            {
                assert_eq!((i, u), (i0, u0), "{spec}: cone of {}", o.name);
            }
            assert!(
                (b.intensity - o.intensity).abs().max_element() <= 1e-5 * o.intensity.max_element()
            );
        }
        assert!(back.camera.eye.distance(s.camera.eye) < 1e-5, "{spec}: eye");
        let dir = |c: &scene::Camera| (c.target - c.eye).normalize();
        assert!(
            dir(&back.camera).dot(dir(&s.camera)) > 1.0 - 1e-6,
            "{spec}: view direction"
        );
        assert!((back.camera.fov_y_deg - s.camera.fov_y_deg).abs() < 1e-4);
        assert_eq!(back.name, spec, "the glTF scene name");
    }
}

/// Moving the camera in an editor (the core node changes, the extras stay) is respected.
#[test]
fn edited_camera_node_wins_over_stale_extras() {
    let s = scene::load("cornell-sphere").unwrap();
    let (mut json, bin) = glb_json(&to_glb_bytes(&s).unwrap());
    let nodes = json["nodes"].as_array_mut().unwrap();
    let cam = nodes
        .iter_mut()
        .find(|n| n.get("camera").is_some())
        .unwrap();
    cam["translation"] = serde_json::json!([0.5, 1.5, 0.9]);
    let back = import_slice(&make_glb(&json, &bin), "edited.glb").unwrap();
    assert_eq!(back.camera.eye, Vec3::new(0.5, 1.5, 0.9));
    assert_eq!(back.camera_path, s.camera_path);
}
