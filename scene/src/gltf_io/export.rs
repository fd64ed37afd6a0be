//! The `.glb` exporter: core glTF a viewer shows, the exact data in `extras`.

use super::*;

pub(super) fn check_finite_extras(scene: &Scene) -> Result<(), String> {
    if scene.objects.is_empty() {
        return Err("the scene has no objects; a glTF file needs at least one mesh".into());
    }
    let keys_ok = |m: &Motion| m.keys.iter().all(|(t, v)| t.is_finite() && v.is_finite());
    let cam_ok = |c: &Camera| {
        c.eye.is_finite() && c.target.is_finite() && c.up.is_finite() && c.fov_y_deg.is_finite()
    };
    if !scene.background.is_finite() {
        return Err("the background colour is not finite".into());
    }
    if !cam_ok(&scene.camera) {
        return Err("the camera is not finite".into());
    }
    if !scene
        .camera_path
        .keys
        .iter()
        .all(|(t, c)| t.is_finite() && cam_ok(c))
    {
        return Err("the camera path has a non-finite key".into());
    }
    for o in &scene.objects {
        if !keys_ok(&o.motion) || o.building.is_some_and(|b| !b.room_size.is_finite()) {
            return Err(format!(
                "object \"{}\" has a non-finite motion key or room size",
                o.name
            ));
        }
        if !o.mesh.uvs.iter().all(|uv| uv.is_finite()) {
            return Err(format!(
                "object \"{}\" has non-finite texture coordinates",
                o.name
            ));
        }
        let material_ok = match o.material {
            Material::Diffuse { albedo, .. } => albedo.is_finite(),
            Material::Metal { n, k } => n.is_finite() && k.is_finite(),
            Material::Glass { .. } => true, // checked by validate()
        };
        if !material_ok {
            return Err(format!(
                "object \"{}\" has a non-finite material parameter",
                o.name
            ));
        }
        if o.mesh.indices.is_empty() {
            return Err(format!(
                "object \"{}\" has no triangles; glTF cannot store an empty mesh",
                o.name
            ));
        }
    }
    for v in &scene.volumes {
        if !(v.center.is_finite()
            && v.radius.is_finite()
            && v.color.is_finite()
            && v.density.is_finite()
            && keys_ok(&v.motion))
        {
            return Err(format!("volume \"{}\" is not finite", v.name));
        }
    }
    if let Some(m) = &scene.medium {
        m.validate().map_err(|e| e.to_string())?;
    }
    for t in &scene.textures {
        if t.width == 0
            || t.height == 0
            || t.rgba8.len() != 4 * t.width as usize * t.height as usize
        {
            return Err(format!(
                "texture \"{}\" is empty or its data does not match {}x{} RGBA8",
                t.name, t.width, t.height
            ));
        }
    }
    Ok(())
}

pub(super) fn num(x: f32) -> Value {
    Value::from(x as f64)
}
pub(super) fn arr(v: &[f32]) -> Value {
    Value::Array(v.iter().map(|&x| num(x)).collect())
}

pub(super) const ARRAY_BUFFER: u32 = 34962;
pub(super) const ELEMENT_ARRAY_BUFFER: u32 = 34963;
pub(super) const FLOAT: u32 = 5126;
pub(super) const UNSIGNED_INT: u32 = 5125;

#[derive(Default)]
pub(super) struct Exporter {
    pub(super) bin: Vec<u8>,
    pub(super) views: Vec<Value>,
    pub(super) accessors: Vec<Value>,
}

impl Exporter {
    pub(super) fn view(&mut self, bytes: &[u8], target: Option<u32>) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let mut v = json!({ "buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len() });
        if let Some(t) = target {
            v["target"] = json!(t);
        }
        self.bin.extend_from_slice(bytes);
        self.views.push(v);
        self.views.len() - 1
    }

    pub(super) fn accessor(
        &mut self,
        bytes: &[u8],
        target: u32,
        component: u32,
        count: usize,
        ty: &str,
    ) -> usize {
        let view = self.view(bytes, Some(target));
        self.accessors.push(
            json!({ "bufferView": view, "componentType": component, "count": count, "type": ty }),
        );
        self.accessors.len() - 1
    }

    /// The accessors of a mesh's positions (with their bounds), normals, texture
    /// coordinates and indices.
    fn mesh_accessors(&mut self, m: &crate::Mesh) -> [usize; 4] {
        let pos = self.accessor(
            bytemuck::cast_slice(&m.positions),
            ARRAY_BUFFER,
            FLOAT,
            m.positions.len(),
            "VEC3",
        );
        let (lo, hi) = m.bounds();
        self.accessors[pos]["min"] = arr(&lo.to_array());
        self.accessors[pos]["max"] = arr(&hi.to_array());
        let nor = self.accessor(
            bytemuck::cast_slice(&m.normals),
            ARRAY_BUFFER,
            FLOAT,
            m.normals.len(),
            "VEC3",
        );
        let uv = self.accessor(
            bytemuck::cast_slice(&m.uvs),
            ARRAY_BUFFER,
            FLOAT,
            m.uvs.len(),
            "VEC2",
        );
        let idx = self.accessor(
            bytemuck::cast_slice(&m.indices),
            ELEMENT_ARRAY_BUFFER,
            UNSIGNED_INT,
            m.indices.len(),
            "SCALAR",
        );
        [pos, nor, uv, idx]
    }

    pub(super) fn run(mut self, scene: &Scene) -> Result<Vec<u8>, SceneError> {
        let (mut nodes, mut meshes, mut materials) = (vec![], vec![], vec![]);
        for o in &scene.objects {
            let [pos, nor, uv, idx] = self.mesh_accessors(&mesh_at_zero(o));
            materials.push(material_json(o));
            meshes.push(json!({
                "name": o.name,
                "primitives": [{
                    "attributes": { "POSITION": pos, "NORMAL": nor, "TEXCOORD_0": uv },
                    "indices": idx,
                    "material": materials.len() - 1,
                    "mode": 4,
                }],
            }));
            nodes.push(object_node(o, meshes.len() - 1));
        }

        let mut lights = vec![];
        for l in &scene.lights {
            lights.push(light_json(l));
            nodes.push(light_node(l, lights.len() - 1));
        }

        let c = &scene.camera;
        let rotation = camera_rotation(c);
        nodes.push(json!({
            "name": "camera",
            "camera": 0,
            "translation": arr(&c.eye.to_array()),
            "rotation": arr(&rotation.to_array()),
            "extras": wrap(&CameraExtras::from_camera(c)),
        }));
        let cameras = match c.orthographic {
            // xmag = ymag: the width follows the image's aspect, as the importer reads it.
            Some(h) => json!([{
                "name": "camera",
                "type": "orthographic",
                "orthographic": { "xmag": num(h), "ymag": num(h), "znear": num(Camera::NEAR), "zfar": num(Camera::FAR) },
            }]),
            None => json!([{
                "name": "camera",
                "type": "perspective",
                "perspective": { "yfov": num(c.fov_y_deg.to_radians()), "znear": num(Camera::NEAR), "zfar": num(Camera::FAR) },
            }]),
        };

        let (mut images, mut textures) = (vec![], vec![]);
        for (i, t) in scene.textures.iter().enumerate() {
            let png = encode_png(t).map_err(|e| SceneError::Gltf(scene.name.clone(), e))?;
            let view = self.view(&png, None);
            images.push(json!({ "name": t.name, "mimeType": "image/png", "bufferView": view }));
            textures.push(json!({ "name": t.name, "sampler": 0, "source": i }));
        }

        let scene_extras = scene_extras(scene);

        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let mut used = vec![];
        let any = |f: &dyn Fn(&Material) -> bool| scene.objects.iter().any(|o| f(&o.material));
        if !lights.is_empty() {
            used.push("KHR_lights_punctual");
        }
        if any(&|m| matches!(m, Material::Glass { .. })) {
            used.extend(["KHR_materials_transmission", "KHR_materials_ior"]);
        }
        if scene.objects.iter().any(|o| o.emission.max_element() > 1.0) {
            used.push("KHR_materials_emissive_strength");
        }
        let node_count = nodes.len();
        let mut root = json!({
            "asset": { "version": "2.0", "generator": concat!("scene crate ", env!("CARGO_PKG_VERSION"), " (gltf_io)") },
            "scene": 0,
            "scenes": [{ "name": scene.name, "nodes": (0..node_count).collect::<Vec<_>>(), "extras": wrap(&scene_extras) }],
            "nodes": nodes,
            "meshes": meshes,
            "materials": materials,
            "cameras": cameras,
            "accessors": self.accessors,
            "bufferViews": self.views,
            "buffers": [{ "byteLength": self.bin.len() }],
        });
        if !used.is_empty() {
            root["extensionsUsed"] = json!(used);
        }
        if !lights.is_empty() {
            root["extensions"] = json!({ "KHR_lights_punctual": { "lights": lights } });
        }
        if !images.is_empty() {
            root["images"] = json!(images);
            root["textures"] = json!(textures);
            // LINEAR filters, REPEAT wrapping: what Texture::sample does.
            root["samplers"] =
                json!([{ "magFilter": 9729, "minFilter": 9729, "wrapS": 10497, "wrapT": 10497 }]);
        }
        let json_text = serde_json::to_vec(&root).map_err(|e| {
            SceneError::Gltf(
                scene.name.clone(),
                format!("cannot encode the glTF JSON: {e}"),
            )
        })?;
        Ok(glb(json_text, self.bin))
    }
}

/// The camera node's rotation: the camera looks down its -Z with +Y up.
pub(super) fn camera_rotation(c: &Camera) -> Quat {
    let (forward, right, up) = c.basis();
    Quat::from_mat3(&Mat3::from_cols(right, up, -forward)).normalize()
}

/// A light as `KHR_lights_punctual` has it: colour times intensity (candela for point and spot
/// lights, lux for directional ones) at 683 lm/W, a spot's cone (glTF wants the inner angle
/// below the outer: equal angles, a hard edge, are written a hair apart), the exact values in
/// the extras.
fn light_json(l: &Light) -> Value {
    let peak = l.intensity.max_element().max(0.0);
    let color = if peak > 0.0 {
        (l.intensity / peak).max(Vec3::ZERO)
    } else {
        Vec3::ONE
    };
    let mut exact = LightExtras {
        intensity: v3(l.intensity),
        direction: l.direction().map(v3),
        cone: None,
    };
    let spot = if let LightKind::Spot {
        inner_cone,
        outer_cone,
        ..
    } = l.kind
    {
        exact.cone = Some([inner_cone as f64, outer_cone as f64]);
        Some(json!({
            "innerConeAngle": num(inner_cone.min(outer_cone * (1.0 - 1e-6))),
            "outerConeAngle": num(outer_cone),
        }))
    } else {
        None
    };
    let mut light = json!({
        "name": l.name,
        "type": l.kind_name(),
        "color": arr(&color.to_array()),
        "intensity": num(peak * LUMENS_PER_WATT),
        "extras": wrap(&exact),
    });
    if let Some(spot) = spot {
        light["spot"] = spot;
    }
    light
}

/// The node of light `index`, at the light's position, its -Z along the light's direction.
fn light_node(l: &Light, index: usize) -> Value {
    let mut node = json!({
        "name": l.name,
        "translation": arr(&l.position.to_array()),
        "extensions": { "KHR_lights_punctual": { "light": index } },
    });
    if let Some(direction) = l.direction() {
        let rotation = Quat::from_rotation_arc(Vec3::NEG_Z, direction.normalize());
        node["rotation"] = arr(&rotation.to_array());
    }
    node
}

/// A diffuse surface's emission as glTF has it: the emissive factor (each channel at most 1)
/// times `KHR_materials_emissive_strength` where the radiance exceeds 1.
fn add_emission(material: &mut Value, emission: Vec3) {
    let peak = emission.max_element();
    if !(peak > 0.0) {
        return;
    }
    let strength = peak.max(1.0);
    material["emissiveFactor"] = arr(&(emission / strength).to_array());
    if strength > 1.0 {
        material["extensions"] = json!({
            "KHR_materials_emissive_strength": { "emissiveStrength": num(strength) }
        });
    }
}

pub(super) fn material_json(o: &Object) -> Value {
    let name = format!("{} material", o.name);
    match &o.material {
        Material::Diffuse {
            albedo,
            texture,
            cutout,
        } => {
            let c = albedo.clamp(Vec3::ZERO, Vec3::ONE);
            let mut pbr = json!({ "baseColorFactor": arr(&[c.x, c.y, c.z, 1.0]), "metallicFactor": 0.0, "roughnessFactor": 1.0 });
            if let Some(t) = texture {
                pbr["baseColorTexture"] = json!({ "index": t });
            }
            let emission = (o.emission != Vec3::ZERO).then_some(v3(o.emission));
            let mut m = json!({ "name": name, "pbrMetallicRoughness": pbr, "extras": wrap(&MaterialExtras::Diffuse { albedo: v3(*albedo), emission }) });
            if let Some(cutoff) = cutout.filter(|_| texture.is_some()) {
                m["alphaMode"] = json!("MASK");
                m["alphaCutoff"] = num(cutoff);
            }
            add_emission(&mut m, o.emission);
            m
        }
        Material::Metal { n, k } => {
            let k2 = *k * *k;
            let f0 = (((*n - 1.0) * (*n - 1.0) + k2) / ((*n + 1.0) * (*n + 1.0) + k2))
                .clamp(Vec3::ZERO, Vec3::ONE);
            json!({
                "name": name,
                "pbrMetallicRoughness": { "baseColorFactor": arr(&[f0.x, f0.y, f0.z, 1.0]), "metallicFactor": 1.0, "roughnessFactor": 0.0 },
                "extras": wrap(&MaterialExtras::Metal { n: v3(*n), k: v3(*k) }),
            })
        }
        Material::Glass { ior } => {
            let shown = if *ior >= 1.0 { *ior } else { 1.0 / *ior };
            json!({
                "name": name,
                "pbrMetallicRoughness": { "baseColorFactor": [1.0, 1.0, 1.0, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.0 },
                "extensions": {
                    "KHR_materials_transmission": { "transmissionFactor": 1.0 },
                    "KHR_materials_ior": { "ior": num(shown) },
                },
                "extras": wrap(&MaterialExtras::Glass { ior: *ior as f64 }),
            })
        }
    }
}

pub(super) fn encode_png(t: &Texture) -> Result<Vec<u8>, String> {
    use image::ImageEncoder;
    let mut out = Vec::new();
    image::codecs::png::PngEncoder::new(&mut out)
        .write_image(&t.rgba8, t.width, t.height, image::ExtendedColorType::Rgba8)
        .map_err(|e| format!("cannot encode texture \"{}\" as PNG: {e}", t.name))?;
    Ok(out)
}

/// Assembles a `.glb`: 12-byte header, JSON chunk padded with spaces, BIN chunk padded
/// with zeros (omitted when empty).
pub fn glb(mut json_text: Vec<u8>, mut bin: Vec<u8>) -> Vec<u8> {
    while !json_text.len().is_multiple_of(4) {
        json_text.push(b' ');
    }
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let total = 12 + 8 + json_text.len() + if bin.is_empty() { 0 } else { 8 + bin.len() };
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json_text.len() as u32).to_le_bytes());
    out.extend_from_slice(&0x4E4F_534Au32.to_le_bytes());
    out.extend_from_slice(&json_text);
    if !bin.is_empty() {
        out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
        out.extend_from_slice(&0x004E_4942u32.to_le_bytes());
        out.extend_from_slice(&bin);
    }
    out
}

/// The scene's exact data for `scenes[0].extras`: name, background, camera path, volumes
/// and medium.
fn scene_extras(scene: &Scene) -> SceneExtras {
    SceneExtras {
        version: EXTRAS_VERSION,
        name: scene.name.clone(),
        background: v3(scene.background),
        camera_path: scene
            .camera_path
            .keys
            .iter()
            .map(|(t, c)| CameraKeyExtras {
                time: *t as f64,
                camera: CameraExtras::from_camera(c),
            })
            .collect(),
        volumes: scene
            .volumes
            .iter()
            .map(|v| VolumeExtras {
                name: v.name.clone(),
                center: v3(v.center),
                radius: v.radius as f64,
                color: v3(v.color),
                density: v.density as f64,
                profile: Some(ProfileExtras::from_profile(&v.profile)),
                particle: v.particle,
                motion: motion_extras(&v.motion),
            })
            .collect(),
        medium: scene.medium.as_ref().map(MediumExtras::from_medium),
    }
}

/// The mesh an object is exported with: a deforming object as it is at time 0 (its morph is
/// not exported).
fn mesh_at_zero(o: &Object) -> Cow<'_, crate::Mesh> {
    match &o.morph {
        None => Cow::Borrowed(&o.mesh),
        Some(_) => Cow::Owned(crate::Mesh {
            positions: o.positions_at(0.0).into_owned(),
            normals: o.normals_at(0.0).into_owned(),
            ..o.mesh.clone()
        }),
    }
}

/// An object's node: its mesh, its transform (omitted when it is the identity) and its
/// exact data in `extras`.
fn object_node(o: &Object, mesh: usize) -> Value {
    let extras = ObjectExtras {
        roles: o.roles.names().iter().map(|s| s.to_string()).collect(),
        motion: motion_extras(&o.motion),
        building: o.building.map(|b| BuildingExtras {
            room_size: v3(b.room_size),
        }),
    };
    let mut node = json!({ "name": o.name, "mesh": mesh, "extras": wrap(&extras) });
    if o.transform != Mat4::IDENTITY {
        node["matrix"] = arr(&o.transform.to_cols_array());
    }
    node
}
