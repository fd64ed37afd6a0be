//! What the importer leaves out or approximates, named: the notes of cameras, lights, meshes,
//! materials and the file's extensions ([`super::import_noted`]), and the lights it reads.

use super::*;

impl Importer<'_> {
    /// The first camera met in the node tree (perspective or orthographic) is the view: glTF
    /// marks no camera as active. A file's own camera (not ours, whose extras carry it
    /// exactly) is named in a note, and so is every other camera, which is not used (and not
    /// read: a flaw of its own is no error), and an orthographic camera's `xmag` where the
    /// view's width does not follow it.
    pub(super) fn choose_camera(&mut self, node: &gltf::Node, world: Mat4) -> Result<(), String> {
        let Some(camera) = node.camera() else {
            return Ok(());
        };
        let json = self.doc.as_json().cameras.get(camera.index());
        let lens = json.and_then(Lens::of);
        let kind = match (&lens, json.map(|c| &c.type_)) {
            (Some(Lens::Orthographic { .. }), _) => "orthographic",
            (Some(Lens::Pinhole { .. }), _) => "perspective",
            (None, Some(t)) => match t {
                gltf::json::validation::Checked::Valid(gltf::json::camera::Type::Orthographic) => {
                    "orthographic"
                }
                _ => "perspective",
            },
            (None, None) => "perspective",
        };
        let what = format!(
            "{kind} camera {} of node {}",
            describe_camera(&camera),
            describe_node(node)
        );
        if self.camera.is_some() {
            self.notes.push(format!(
                "{what} is not used: the view is the first camera in the node tree"
            ));
            return Ok(());
        }
        let Some(lens) = lens else {
            self.notes.push(format!(
                "{what} has no {kind} projection in the file: skipped"
            ));
            return Ok(());
        };
        let found = self.camera_at(node, world, &lens)?;
        if let FoundCamera::Derived { .. } = found {
            self.notes.push(format!(
                "the view is {what}, the first camera in the node tree (glTF marks no camera as \
                 active)"
            ));
        }
        if let Lens::Orthographic { xmag, ymag } = lens {
            if (xmag.abs() - ymag.abs()).abs() > 1e-4 * ymag.abs() {
                self.notes.push(format!(
                    "{what} has xmag {xmag} and ymag {ymag}: the view is {} high and as wide \
                     as the rendered image's aspect makes it (xmag is not used)",
                    2.0 * ymag.abs()
                ));
            }
        }
        self.camera = Some(found);
        Ok(())
    }

    /// Notes of what the file as a whole has that the importer ignores: animations, and
    /// extensions it does not read.
    pub(super) fn note_file(&mut self) {
        let animations = self.doc.animations().count();
        if animations > 0 {
            self.notes.push(format!(
                "the file's {animations} animation(s) are ignored: objects stand where the node \
                 tree places them"
            ));
        }
        for extension in self.doc.extensions_used() {
            if let Some(note) = unread_extension(extension) {
                self.notes.push(note);
            }
        }
    }

    /// Notes of what a mesh's primitives carry that the importer leaves out: primitives that
    /// are not triangles, vertex colours, morph targets.
    pub(super) fn note_mesh(&mut self, mesh: &gltf::Mesh) {
        let what = format!("mesh {}", describe_mesh(mesh));
        for prim in mesh.primitives() {
            if !triangle_mode(prim.mode()) {
                self.notes.push(format!(
                    "{what} primitive {} draws {:?}, not triangles: skipped",
                    prim.index(),
                    prim.mode()
                ));
            }
            if prim.get(&gltf::mesh::Semantic::Colors(0)).is_some() {
                self.notes.push(format!(
                    "{what} has vertex colours (COLOR_0), which are ignored: the material's \
                     colour alone"
                ));
            }
            if prim.morph_targets().next().is_some() {
                self.notes.push(format!(
                    "{what} has morph targets, which are ignored: its base shape is drawn"
                ));
            }
        }
    }

    /// Notes of what `m` has that its import as `material` leaves out or approximates:
    /// emission, alpha masks and blending, rough transmission, rough metal.
    pub(super) fn note_material(&mut self, m: &gltf::Material, material: &Material) {
        let what = match (m.index(), m.name()) {
            (Some(i), Some(name)) => format!("material {i} (\"{name}\")"),
            (Some(i), None) => format!("material {i}"),
            (None, _) => return, // the default material has nothing to leave out
        };
        let mut notes = Vec::new();
        let emissive = Vec3::from(m.emissive_factor()) * m.emissive_strength().unwrap_or(1.0);
        let textured = m.emissive_texture().is_some();
        if emissive.max_element() > 0.0 || textured {
            let texture = if textured {
                "; its emissive texture is left out (the factor alone)"
            } else {
                ""
            };
            notes.push(match material {
                Material::Diffuse { .. } => format!(
                    "{what} emits radiance {emissive} (emissive factor times strength): seen \
                     directly and in reflections and refractions, but it lights nothing (emissive \
                     surfaces are not light sources here){texture}"
                ),
                _ => format!(
                    "{what} emits radiance {emissive} but is imported as {}: left out (only \
                     diffuse surfaces emit)",
                    material.kind_name()
                ),
            });
        }
        let alpha = m.pbr_metallic_roughness().base_color_factor()[3];
        let mode = match m.alpha_mode() {
            gltf::material::AlphaMode::Mask => {
                format!(
                    "alpha-masked (MASK, cutoff {})",
                    m.alpha_cutoff().unwrap_or(0.5)
                )
            }
            _ => "alpha-blended (BLEND)".to_string(),
        };
        match alpha_coverage(m) {
            Coverage::All => {}
            Coverage::None => {
                // Nothing else of a material no one sees is worth a note.
                self.notes.push(format!(
                    "{what} is {mode} with alpha {alpha}: nothing of it is seen, so its \
                     primitives are left out"
                ));
                return;
            }
            Coverage::Cutout(_) if matches!(material, Material::Diffuse { .. }) => {}
            Coverage::Cutout(_) => notes.push(format!(
                "{what} is {mode} with a texture, but it imports as {}, which reads no \
                 texture: rendered opaque (only diffuse surfaces are cut out)",
                material.kind_name()
            )),
            Coverage::Partial => notes.push(format!(
                "{what} is {mode} with alpha {alpha}{}, which is not supported yet: rendered \
                 opaque",
                if m.pbr_metallic_roughness().base_color_texture().is_some() {
                    " times its texture's"
                } else {
                    ""
                }
            )),
        }
        let roughness = m.pbr_metallic_roughness().roughness_factor();
        match material {
            Material::Glass { .. } if roughness > 0.0 => notes.push(format!(
                "{what} transmits with roughness {roughness}: rendered as smooth glass"
            )),
            Material::Metal { .. } if roughness > 0.0 => notes.push(format!(
                "{what} is metal with roughness {roughness}: rendered as a smooth mirror"
            )),
            _ => {}
        }
        self.notes.extend(notes);
    }
}

fn describe_light(light: &gltf::khr_lights_punctual::Light) -> String {
    match light.name() {
        Some(n) => format!("{} (\"{n}\")", light.index()),
        None => light.index().to_string(),
    }
}

/// The note of a glTF extension the importer does not read (`None` for those it reads).
fn unread_extension(name: &str) -> Option<String> {
    let effect = match name {
        "KHR_lights_punctual"
        | "KHR_materials_ior"
        | "KHR_materials_transmission"
        | "KHR_materials_emissive_strength" => return None,
        "KHR_materials_volume" => {
            "absorption inside glass (attenuation colour and distance) is left out, the glass is clear"
        }
        "KHR_texture_transform" => "textures repeat untransformed",
        "KHR_materials_unlit" => "unlit materials are shaded as diffuse",
        _ => "what it adds is left out",
    };
    Some(format!(
        "the file uses {name}, which the importer does not read: {effect}"
    ))
}

/// A `KHR_lights_punctual` light at its node: the exact intensity (and direction) from the
/// extras while they agree with the core light, else the core colour and intensity (candela
/// for point and spot lights, lux for directional ones) over 683 lm/W, and the node's -Z
/// axis. A spot keeps its inner and outer cone angles (exact from the extras) and glTF's
/// falloff between them. With the notes of what the light has that is ignored or mended: a
/// range, an outer angle past pi/2, an inner angle past the outer.
pub(super) fn punctual_light(
    node: &gltf::Node,
    light: &gltf::khr_lights_punctual::Light,
    world: Mat4,
) -> Result<(Light, Vec<String>), String> {
    let about = format!(
        "light {} of node {}",
        describe_light(light),
        describe_node(node)
    );
    let mut notes = Vec::new();
    if let Some(range) = light.range() {
        notes.push(format!(
            "{about} has a range of {range} m, which is ignored: its light falls off with the \
             inverse square at any distance"
        ));
    }
    let what = format!("light {}", light.index());
    let c = Vec3::from(light.color());
    let derived = c * light.intensity() / LUMENS_PER_WATT;
    let exact: Option<LightExtras> = read_extras(light.extras(), &what)?;
    let intensity = match &exact {
        Some(x) if close(vec3(x.intensity), derived, 1e-4) => vec3(x.intensity),
        _ => derived,
    };
    let axis = world
        .transform_vector3(Vec3::NEG_Z)
        .normalize_or(Vec3::NEG_Z);
    let direction = match exact.as_ref().and_then(|x| x.direction) {
        Some(d) if close(vec3(d), axis, 1e-4) => vec3(d),
        _ => axis,
    };
    let name = light
        .name()
        .or(node.name())
        .map(str::to_string)
        .unwrap_or_else(|| format!("light {}", light.index()));
    let kind = match light.kind() {
        gltf::khr_lights_punctual::Kind::Point => LightKind::Point,
        gltf::khr_lights_punctual::Kind::Directional => LightKind::Directional { direction },
        gltf::khr_lights_punctual::Kind::Spot {
            inner_cone_angle,
            outer_cone_angle,
        } => {
            let exact_cone = exact.as_ref().and_then(|x| x.cone);
            let (inner_cone, outer_cone) = spot_cone(
                inner_cone_angle,
                outer_cone_angle,
                exact_cone,
                &about,
                &mut notes,
            );
            LightKind::Spot {
                direction,
                inner_cone,
                outer_cone,
            }
        }
    };
    let light = Light {
        name,
        position: world.transform_point3(Vec3::ZERO),
        intensity,
        kind,
    };
    Ok((light, notes))
}

/// A spot's inner and outer cone angles: exact from the extras while they agree with the
/// core's, the outer at most pi/2 and the inner at most the outer (glTF's rules; Blender
/// writes equal angles for a spot without blend), each mend noted.
fn spot_cone(
    inner: f32,
    outer: f32,
    exact: Option<[f64; 2]>,
    about: &str,
    notes: &mut Vec<String>,
) -> (f32, f32) {
    if let Some([i, o]) = exact
        && (i as f32 - inner).abs() <= 1e-4
        && (o as f32 - outer).abs() <= 1e-4
    {
        return (i as f32, o as f32);
    }
    let right = std::f32::consts::FRAC_PI_2;
    let outer_taken = outer.min(right);
    if outer > right {
        notes.push(format!(
            "{about} has an outer cone angle of {outer} rad, past glTF's pi/2: taken as pi/2"
        ));
    }
    if inner > outer_taken {
        notes.push(format!(
            "{about} has an inner cone angle of {inner} rad, past its outer one: taken as the \
             outer (a hard edge)"
        ));
    }
    (inner.min(outer_taken), outer_taken)
}
