//! The `city` scene's real interiors and what this crate builds from a building's hull and room
//! layout (`geometry`, `textures`: the scene's own generators, called with the technique's
//! reading of the hull) must agree exactly: the polygon baseline and the reference then see
//! the same rooms interior mapping casts against.

use interior_mapping::{geometry, textures};

#[test]
fn city_interiors_match_this_crates_generators() {
    for rooms in [1000.0f32, 20000.0, 7.0] {
        let scene = scene::load(&format!("city:rooms_per_building={rooms}")).unwrap();
        let b = scene
            .objects
            .iter()
            .find(|o| o.name == "building 0 (box, window holes)")
            .expect("building 0 has real interiors");
        let room = b.building.unwrap().room_size;
        let (lo, hi) = b.mesh.bounds();
        assert_eq!(
            b.mesh,
            geometry::facade_with_windows(lo, hi, room),
            "facade, rooms {rooms}"
        );
        // The closed bounding box interior mapping draws has the same texture coordinates.
        let cube = scene::mesh::cuboid(lo, hi);
        assert_eq!(
            b.mesh.positions[..8],
            cube.positions[8..16],
            "roof and floor faces first"
        );
        for (family, name) in [
            (1, "floors"),
            (4, "ceilings"),
            (0, "walls x"),
            (2, "walls z"),
        ] {
            let o = scene
                .objects
                .iter()
                .find(|o| o.name == format!("building 0 {name}"))
                .unwrap();
            assert_eq!(
                o.mesh,
                geometry::room_planes(lo, hi, room, family),
                "{name}, rooms {rooms}"
            );
            let scene::Material::Diffuse {
                texture: Some(t), ..
            } = o.material
            else {
                panic!("{name} untextured")
            };
            let mine = &textures::scene_textures(scene.textures[t].width)[match family {
                1 => 0,
                4 => 1,
                0 => 2,
                _ => 3,
            }];
            assert_eq!(&scene.textures[t], mine, "{name} texture");
        }
    }
}

#[test]
fn polygon_scene_adds_rooms_to_box_hulls_only() {
    let scene = scene::load("city:interiors=0").unwrap();
    let poly = interior_mapping::technique::polygon_scene(&scene, 1.0, 32);
    let holed = poly
        .objects
        .iter()
        .filter(|o| o.name.contains("window holes") && o.building.is_some())
        .count();
    assert_eq!(holed, 14, "16 buildings minus the cylinder and the sphere");
    assert_eq!(poly.objects.len(), scene.objects.len() + 4 * 14);
    poly.validate().unwrap();
}
