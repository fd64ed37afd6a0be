//! The importer proper: the node tree visited into objects, materials, lights and a camera.

use super::*;

/// A material as imported: the model material, its default roles, and its base colour
/// texture as (glTF image index, texture-coordinate set).
pub(super) type ImportedMaterial = (Material, Roles, Option<(usize, u32)>);

/// An object whose diffuse texture is still a glTF image index.
pub(super) struct Pending {
    pub(super) object: usize,
    pub(super) image: usize,
}

pub(super) struct Importer<'a> {
    pub(super) doc: &'a gltf::Document,
    pub(super) buffers: Vec<Vec<u8>>,
    pub(super) base: Option<&'a Path>,
    pub(super) objects: Vec<Object>,
    pub(super) pending: Vec<Pending>,
    pub(super) lights: Vec<Light>,
    pub(super) camera: Option<FoundCamera>,
    /// What the importer supplied or repaired, one sentence each.
    pub(super) notes: Vec<String>,
    /// Triangles of the objects made so far.
    pub(super) triangles: usize,
    /// Triangle primitives left out because their alpha leaves nothing of them.
    pub(super) cut_out: usize,
}

/// The first camera: exact from the extras, or from the node (its target is placed once the
/// scene's bounds are known).
pub(super) enum FoundCamera {
    Exact(Camera),
    Derived {
        eye: Vec3,
        forward: Vec3,
        up: Vec3,
        fov_y_deg: f32,
        /// An orthographic camera's `ymag`.
        orthographic: Option<f32>,
    },
}

/// What a glTF camera projects with: a pinhole's `yfov` in degrees, or an orthographic view's
/// `ymag` (with `xmag`, which only a note uses).
pub(super) enum Lens {
    Pinhole { fov_y_deg: f32 },
    Orthographic { ymag: f32, xmag: f32 },
}

impl Lens {
    /// The lens of camera `c` of the file, or `None` when its type names no projection it
    /// has. The JSON is read directly: `gltf::Camera::projection` unwraps the projection
    /// named by `type`, which validation does not require to be present.
    pub(super) fn of(c: &gltf::json::Camera) -> Option<Lens> {
        use gltf::json::camera::Type;
        use gltf::json::validation::Checked::Valid;
        match c.type_ {
            Valid(Type::Perspective) => c.perspective.as_ref().map(|p| Lens::Pinhole {
                fov_y_deg: p.yfov.to_degrees(),
            }),
            // glTF: ymag must not be 0 and should not be negative; its size is the height.
            Valid(Type::Orthographic) => c.orthographic.as_ref().map(|o| Lens::Orthographic {
                ymag: o.ymag.abs(),
                xmag: o.xmag,
            }),
            _ => None,
        }
    }
    /// `(fov_y_deg, orthographic)` of the scene's camera: an orthographic camera keeps the
    /// default 45 degrees it does not use.
    fn projection(&self) -> (f32, Option<f32>) {
        match *self {
            Lens::Pinhole { fov_y_deg } => (fov_y_deg, None),
            Lens::Orthographic { ymag, .. } => (45.0, Some(ymag)),
        }
    }
}

impl Importer<'_> {
    pub(super) fn run(mut self, fallback_name: &str) -> Result<(Scene, Vec<String>), String> {
        let doc = self.doc;
        let gscene = doc.default_scene().or_else(|| doc.scenes().next());
        let roots: Vec<gltf::Node> = match &gscene {
            Some(s) => s.nodes().collect(),
            None => {
                let mut is_child = vec![false; doc.nodes().len()];
                for n in doc.nodes() {
                    for c in n.children() {
                        is_child[c.index()] = true;
                    }
                }
                doc.nodes().filter(|n| !is_child[n.index()]).collect()
            }
        };
        let scene_extras: Option<SceneExtras> = match &gscene {
            Some(s) => read_extras(s.extras(), &format!("scene {}", s.index()))?,
            None => None,
        };
        if let Some(x) = &scene_extras
            && x.version > EXTRAS_VERSION
        {
            return Err(format!(
                "the file uses extras schema version {}, newer than the supported {EXTRAS_VERSION}",
                x.version
            ));
        }

        // Depth-first, children in order; a node met twice means a cycle or a shared child.
        self.walk(roots)?;
        if self.objects.is_empty() && self.cut_out > 0 {
            return Err(format!(
                "every triangle primitive of the file ({}) is cut out by its alpha (MASK below \
                 its cutoff or BLEND of alpha 0): nothing to render",
                self.cut_out
            ));
        }
        if self.objects.is_empty() {
            return Err("the file contains no triangle geometry".into());
        }
        self.note_file();

        let textures = self.textures(scene_extras.is_some())?;

        let camera = placed_camera(self.camera.take(), &self.objects);
        let medium = scene_extras
            .as_ref()
            .and_then(|x| x.medium.as_ref().map(MediumExtras::medium));
        let (name, background, camera_path, volumes) = match scene_extras {
            Some(x) => (
                x.name,
                vec3(x.background),
                CameraPath {
                    keys: x
                        .camera_path
                        .iter()
                        .map(|k| (k.time as f32, k.camera.camera()))
                        .collect(),
                },
                x.volumes.iter().map(VolumeExtras::volume).collect(),
            ),
            None => (
                gscene
                    .as_ref()
                    .and_then(|s| s.name())
                    .unwrap_or(fallback_name)
                    .to_string(),
                Vec3::ZERO,
                CameraPath::default(),
                vec![],
            ),
        };
        let mut scene = Scene {
            name,
            objects: self.objects,
            textures,
            lights: self.lights,
            camera,
            camera_path,
            volumes,
            medium,
            background,
        };
        // A material met by several primitives is noted once.
        let mut notes: Vec<String> = Vec::new();
        for note in self.notes {
            if !notes.contains(&note) {
                notes.push(note);
            }
        }
        if scene.lights.is_empty() {
            notes.push(scene.add_default_lighting());
        }
        Ok((scene, notes))
    }

    /// Visits the node tree from `roots`, depth first and children in order, with each
    /// node's world matrix; a node reached twice is an error (a cycle or two parents).
    fn walk(&mut self, roots: Vec<gltf::Node<'_>>) -> Result<(), String> {
        let mut visited = vec![false; self.doc.nodes().len()];
        let mut stack: Vec<(gltf::Node, Option<Mat4>)> =
            roots.into_iter().rev().map(|n| (n, None)).collect();
        while let Some((node, parent)) = stack.pop() {
            if std::mem::replace(&mut visited[node.index()], true) {
                return Err(format!(
                    "node {} is reached twice: the node hierarchy has a cycle or a node with two parents",
                    node.index()
                ));
            }
            let local = node_matrix(&node)?;
            let world = match parent {
                Some(p) => p * local,
                None => local,
            };
            if !world.is_finite() {
                return Err(format!(
                    "node {} has a non-finite world transform (overflow)",
                    describe_node(&node)
                ));
            }
            self.visit(&node, world)?;
            let children: Vec<gltf::Node> = node.children().collect();
            stack.extend(children.into_iter().rev().map(|c| (c, Some(world))));
        }
        Ok(())
    }

    /// The scene's textures: the images used as base colour textures (every image, in our
    /// own files: `every_image`), in image order; the pending objects get their slots.
    fn textures(&mut self, every_image: bool) -> Result<Vec<Texture>, String> {
        let mut needed: BTreeSet<usize> = self.pending.iter().map(|p| p.image).collect();
        if every_image {
            needed.extend(0..self.doc.images().len());
        }
        let mut textures = Vec::new();
        let mut slot = BTreeMap::new();
        for image in self.doc.images().filter(|i| needed.contains(&i.index())) {
            slot.insert(image.index(), textures.len());
            textures.push(self.decode_image(&image)?);
        }
        for p in &self.pending {
            if let Material::Diffuse { texture, .. } = &mut self.objects[p.object].material {
                *texture = slot.get(&p.image).copied();
            }
        }
        Ok(textures)
    }

    pub(super) fn visit(&mut self, node: &gltf::Node, world: Mat4) -> Result<(), String> {
        if let Some(mesh) = node.mesh() {
            self.note_mesh(&mesh);
            let extras: Option<ObjectExtras> =
                read_extras(node.extras(), &format!("node {}", node.index()))?;
            let base_name = node
                .name()
                .or(mesh.name())
                .map(str::to_string)
                .unwrap_or_else(|| format!("node {}", node.index()));
            let triangle_prims = mesh
                .primitives()
                .filter(|p| triangle_mode(p.mode()))
                .count();
            for prim in mesh.primitives().filter(|p| triangle_mode(p.mode())) {
                let what = format!("mesh {} primitive {}", describe_mesh(&mesh), prim.index());
                let (material, default_roles, texture) = self.material(&prim.material())?;
                self.note_material(&prim.material(), &material);
                if alpha_coverage(&prim.material()) == Coverage::None {
                    self.cut_out += 1;
                    continue; // wholly cut out or transparent: nothing to render
                }
                let uv_set = match &texture {
                    Some((_, set)) => *set,
                    None => 0,
                };
                let object_mesh = self.primitive_mesh(&prim, uv_set, &what)?;
                if object_mesh.indices.is_empty() {
                    continue; // fewer than three vertices: nothing to render
                }
                let name = if triangle_prims > 1 {
                    format!("{base_name} #{}", prim.index())
                } else {
                    base_name.clone()
                };
                let emission = self.emission(&prim.material(), &material)?;
                let mut object =
                    Object::new(&name, object_mesh, material, world).with_emission(emission);
                object.roles = default_roles;
                if let Some(x) = &extras {
                    object.roles = roles_from(&x.roles, &name)?;
                    object.motion = motion_from(&x.motion);
                    object.building = x.building.as_ref().map(|b| Building {
                        room_size: vec3(b.room_size),
                    });
                }
                if let (Some((image, _)), Material::Diffuse { .. }) = (texture, &object.material) {
                    self.pending.push(Pending {
                        object: self.objects.len(),
                        image,
                    });
                }
                self.objects.push(object);
                // Checked as objects are made, not after: a file of many nodes sharing one big
                // mesh must not make the importer copy that mesh past the limit first.
                self.triangles += self.objects.last().map_or(0, |o| o.mesh.triangle_count());
                if self.triangles > crate::MAX_TRIANGLES {
                    return Err(format!(
                        "the scene has more than {} triangles (node {} brings it to {}); the \
                         renderers accept at most {}",
                        crate::MAX_TRIANGLES,
                        describe_node(node),
                        self.triangles,
                        crate::MAX_TRIANGLES
                    ));
                }
            }
        }
        if let Some(light) = node.light() {
            let (light, notes) = punctual_light(node, &light, world)?;
            self.lights.push(light);
            self.notes.extend(notes);
        }
        if node.skin().is_some() {
            self.notes.push(format!(
                "node {} is skinned: drawn in its bind pose (skins are ignored)",
                describe_node(node)
            ));
        }
        self.choose_camera(node, world)
    }

    /// The camera of camera node `node` with `lens`: exact from the extras while they agree
    /// with the node, else derived from it.
    pub(super) fn camera_at(
        &self,
        node: &gltf::Node,
        world: Mat4,
        lens: &Lens,
    ) -> Result<FoundCamera, String> {
        let eye = world.transform_point3(Vec3::ZERO);
        let forward = world.transform_vector3(Vec3::NEG_Z).normalize_or_zero();
        let up = world.transform_vector3(Vec3::Y).normalize_or_zero();
        if forward == Vec3::ZERO || up == Vec3::ZERO {
            return Err(format!(
                "camera node {} has a degenerate transform",
                describe_node(node)
            ));
        }
        let (fov_y_deg, orthographic) = lens.projection();
        if let Some(ymag) = orthographic.filter(|h| !(h.is_finite() && *h > 0.0)) {
            return Err(format!(
                "orthographic camera node {} has ymag {ymag}; it needs a height other than 0",
                describe_node(node)
            ));
        }
        // A node that carries other extras under our key is not an error here: the
        // camera is then derived from the node.
        let exact: Option<CameraExtras> =
            read_extras(node.extras(), &format!("node {}", node.index()))
                .ok()
                .flatten();
        let agrees = |c: &Camera| {
            let same_lens = match (c.orthographic, orthographic) {
                (None, None) => (c.fov_y_deg - fov_y_deg).abs() <= 1e-3 * c.fov_y_deg.abs(),
                (Some(a), Some(b)) => (a - b).abs() <= 1e-4 * a.abs(),
                _ => false,
            };
            close(c.eye, eye, 1e-4)
                && (c.target - c.eye).normalize_or_zero().dot(forward) > 1.0 - 1e-4
                && same_lens
        };
        let camera = match exact.map(|x| x.camera()) {
            Some(c) if agrees(&c) => FoundCamera::Exact(c),
            _ => FoundCamera::Derived {
                eye,
                forward,
                up,
                fov_y_deg,
                orthographic,
            },
        };
        Ok(camera)
    }

    /// The model material, its default roles and its base colour texture (image index and
    /// texture-coordinate set) if it is diffuse and has one.
    pub(super) fn material(&self, m: &gltf::Material) -> Result<ImportedMaterial, String> {
        let what = match m.index() {
            Some(i) => format!("material {i}"),
            None => "the default material".to_string(),
        };
        let pbr = m.pbr_metallic_roughness();
        let base = pbr.base_color_factor();
        let base_rgb = Vec3::new(base[0], base[1], base[2]);
        let texture = pbr
            .base_color_texture()
            .map(|info| (info.texture().source().index(), info.tex_coord()));
        let exact: Option<MaterialExtras> = read_extras(m.extras(), &what)?;
        let material = match exact {
            Some(MaterialExtras::Diffuse { albedo, .. }) => Material::Diffuse {
                albedo: vec3(albedo),
                texture: None,
                cutout: None,
            },
            Some(MaterialExtras::Metal { n, k }) => Material::Metal {
                n: vec3(n),
                k: vec3(k),
            },
            Some(MaterialExtras::Glass { ior }) => Material::Glass { ior: ior as f32 },
            None => {
                let transmission = m
                    .transmission()
                    .map(|t| t.transmission_factor())
                    .unwrap_or(0.0);
                if transmission > 0.5 {
                    Material::Glass {
                        ior: m.ior().unwrap_or(1.5),
                    }
                } else if pbr.metallic_factor() >= 0.5 && pbr.roughness_factor() <= 0.5 {
                    let s = base_rgb.clamp(Vec3::ZERO, Vec3::ONE).powf(0.5);
                    Material::Metal {
                        n: (Vec3::ONE - s) / (Vec3::ONE + s),
                        k: Vec3::ZERO,
                    }
                } else {
                    Material::Diffuse {
                        albedo: base_rgb,
                        texture: None,
                        cutout: None,
                    }
                }
            }
        };
        let roles = match material {
            Material::Diffuse { .. } => Roles::NONE,
            Material::Metal { .. } => Roles::REFLECTOR | Roles::CAUSTIC_CASTER,
            Material::Glass { .. } => Roles::REFRACTOR | Roles::CAUSTIC_CASTER,
        };
        let mut material = material;
        let texture = match &mut material {
            Material::Diffuse { cutout, .. } => {
                if let (Some(_), Coverage::Cutout(c)) = (texture, alpha_coverage(m)) {
                    *cutout = Some(c);
                }
                texture
            }
            _ => None,
        };
        Ok((material, roles, texture))
    }

    /// The radiance a diffuse material emits: the emissive factor times
    /// `KHR_materials_emissive_strength`, exact from the extras while they agree (the
    /// emissive texture is left out: [`Self::note_material`]); none for metal and glass.
    fn emission(&self, m: &gltf::Material, material: &Material) -> Result<Vec3, String> {
        if !matches!(material, Material::Diffuse { .. }) {
            return Ok(Vec3::ZERO);
        }
        let derived = Vec3::from(m.emissive_factor()) * m.emissive_strength().unwrap_or(1.0);
        let what = format!("material {}", m.index().map_or(-1, |i| i as i64));
        let exact = match read_extras::<MaterialExtras>(m.extras(), &what)? {
            Some(MaterialExtras::Diffuse {
                emission: Some(e), ..
            }) if close(vec3(e), derived, 1e-4) => Some(vec3(e)),
            _ => None,
        };
        Ok(exact.unwrap_or(derived))
    }

    pub(super) fn primitive_mesh(
        &mut self,
        prim: &gltf::Primitive,
        uv_set: u32,
        what: &str,
    ) -> Result<Mesh, String> {
        use gltf::accessor::Dimensions;
        use gltf::mesh::Semantic;
        let b = &self.buffers;
        let pos_acc = prim
            .get(&Semantic::Positions)
            .ok_or_else(|| format!("{what} has no POSITION attribute"))?;
        let positions: Vec<Vec3> =
            read_floats(&pos_acc, b, &format!("{what} POSITION"), Dimensions::Vec3)?
                .chunks_exact(3)
                .map(Vec3::from_slice)
                .collect();
        let n = positions.len();
        let normals: Option<Vec<Vec3>> = match prim.get(&Semantic::Normals) {
            Some(acc) => Some(
                read_floats(&acc, b, &format!("{what} NORMAL"), Dimensions::Vec3)?
                    .chunks_exact(3)
                    .map(Vec3::from_slice)
                    .collect(),
            ),
            None => None,
        };
        let uvs: Vec<Vec2> = match prim.get(&Semantic::TexCoords(uv_set)) {
            Some(acc) => read_floats(
                &acc,
                b,
                &format!("{what} TEXCOORD_{uv_set}"),
                Dimensions::Vec2,
            )?
            .chunks_exact(2)
            .map(Vec2::from_slice)
            .collect(),
            None => vec![Vec2::ZERO; n],
        };
        if normals.as_ref().is_some_and(|v| v.len() != n) || uvs.len() != n {
            return Err(format!("{what} has attributes of different lengths"));
        }
        let mut indices = match prim.indices() {
            Some(acc) => read_indices(&acc, b, &format!("{what} indices"))?,
            None => (0..n as u32).collect(),
        };
        if let Some(&bad) = indices.iter().find(|&&i| i as usize >= n) {
            return Err(format!(
                "{what} has index {bad}, out of range for its {n} vertices"
            ));
        }
        indices = match prim.mode() {
            gltf::mesh::Mode::TriangleStrip => (0..indices.len().saturating_sub(2))
                .flat_map(|i| {
                    if i % 2 == 0 {
                        [indices[i], indices[i + 1], indices[i + 2]]
                    } else {
                        [indices[i], indices[i + 2], indices[i + 1]]
                    }
                })
                .collect(),
            gltf::mesh::Mode::TriangleFan => (1..indices.len().saturating_sub(1))
                .flat_map(|i| [indices[i], indices[i + 1], indices[0]])
                .collect(),
            _ => indices,
        };
        if !indices.len().is_multiple_of(3) {
            return Err(format!(
                "{what} has {} indices, not a multiple of 3",
                indices.len()
            ));
        }
        Ok(match normals {
            Some(normals) => {
                let mut mesh = Mesh {
                    positions,
                    normals,
                    uvs,
                    indices,
                };
                let repaired = mesh.repair_normals();
                if repaired > 0 {
                    self.notes.push(format!(
                        "{what}: {repaired} zero-length or non-finite normals replaced by geometric normals"
                    ));
                }
                mesh
            }
            None => flat_shaded(&positions, &uvs, &indices),
        })
    }

    pub(super) fn decode_image(&self, image: &gltf::Image) -> Result<Texture, String> {
        let what = format!("image {}", image.index());
        // The image's JSON is read directly: `gltf::Image::source` unwraps `mimeType` and
        // `uri`, which validation does not require.
        let json = &self.doc.as_json().images[image.index()];
        let view = json
            .buffer_view
            .and_then(|v| self.doc.views().nth(v.value()));
        let bytes: Cow<[u8]> = match (view, &json.uri) {
            (Some(view), _) => Cow::Borrowed(view_bytes(&self.buffers, &view)?),
            (None, Some(uri)) => {
                Cow::Owned(read_uri(uri, self.base, &what, MAX_FILE_BYTES, false)?)
            }
            (None, None) => return Err(format!("{what} has neither a bufferView nor a uri")),
        };
        let reader = || {
            let reader = image::ImageReader::new(std::io::Cursor::new(&bytes[..]))
                .with_guessed_format()
                .map_err(|e| format!("{what} cannot be decoded: {e}"))?;
            match reader.format() {
                Some(image::ImageFormat::Png | image::ImageFormat::Jpeg) => Ok(reader),
                Some(other) => Err(format!(
                    "{what} is a {other:?} image; textures may be PNG or JPEG (glTF's core formats)"
                )),
                None => Err(format!(
                    "{what} is neither PNG nor JPEG, the texture formats the importer decodes"
                )),
            }
        };
        let (width, height) = reader()?
            .into_dimensions()
            .map_err(|e| format!("{what} cannot be decoded: {e}"))?;
        if width > MAX_TEXTURE_SIDE || height > MAX_TEXTURE_SIDE {
            return Err(format!(
                "{what} is {width}x{height} texels; textures may have at most {MAX_TEXTURE_SIDE} per side"
            ));
        }
        let mut reader = reader()?;
        let mut limits = image::Limits::default();
        limits.max_image_width = Some(MAX_TEXTURE_SIDE);
        limits.max_image_height = Some(MAX_TEXTURE_SIDE);
        limits.max_alloc = Some(MAX_IMAGE_DECODE_BYTES);
        reader.limits(limits);
        let decoded = reader
            .decode()
            .map_err(|e| format!("{what} cannot be decoded: {e}"))?;
        let rgba = decoded.to_rgba8();
        Ok(Texture {
            name: image.name().map(str::to_string).unwrap_or(what),
            width: rgba.width(),
            height: rgba.height(),
            rgba8: rgba.into_raw(),
        })
    }
}

pub(super) fn triangle_mode(mode: gltf::mesh::Mode) -> bool {
    use gltf::mesh::Mode::*;
    matches!(mode, Triangles | TriangleStrip | TriangleFan)
}

pub(super) fn describe_node(node: &gltf::Node) -> String {
    match node.name() {
        Some(n) => format!("{} (\"{n}\")", node.index()),
        None => node.index().to_string(),
    }
}

pub(super) fn describe_camera(camera: &gltf::Camera) -> String {
    match camera.name() {
        Some(n) => format!("{} (\"{n}\")", camera.index()),
        None => camera.index().to_string(),
    }
}

pub(super) fn describe_mesh(mesh: &gltf::Mesh) -> String {
    match mesh.name() {
        Some(n) => format!("{} (\"{n}\")", mesh.index()),
        None => mesh.index().to_string(),
    }
}

/// The node's local matrix; every number must be finite.
pub(super) fn node_matrix(node: &gltf::Node) -> Result<Mat4, String> {
    let bad = || {
        format!(
            "node {} has a non-finite transform (NaN or infinity)",
            describe_node(node)
        )
    };
    match node.transform() {
        gltf::scene::Transform::Matrix { matrix } => {
            let m = Mat4::from_cols_array_2d(&matrix);
            if m.is_finite() { Ok(m) } else { Err(bad()) }
        }
        gltf::scene::Transform::Decomposed {
            translation,
            rotation,
            scale,
        } => {
            let (t, r, s) = (
                Vec3::from(translation),
                glam::Vec4::from(rotation),
                Vec3::from(scale),
            );
            if !(t.is_finite() && r.is_finite() && s.is_finite()) {
                return Err(bad());
            }
            let q = Quat::from_vec4(r);
            let len = q.length();
            if !(len.is_finite() && len > 0.0) {
                return Err(format!(
                    "node {} has a zero or non-finite rotation quaternion",
                    describe_node(node)
                ));
            }
            let m = Mat4::from_scale_rotation_translation(s, q / len, t);
            if m.is_finite() { Ok(m) } else { Err(bad()) }
        }
    }
}

pub(super) fn roles_from(names: &[String], object: &str) -> Result<Roles, String> {
    names.iter().try_fold(Roles::NONE, |acc, n| {
        Roles::from_name(n)
            .map(|r| acc | r)
            .ok_or_else(|| format!("object \"{object}\" has an unknown role \"{n}\" in its extras"))
    })
}

pub(super) fn close(a: Vec3, b: Vec3, rel: f32) -> bool {
    (a - b).abs().max_element() <= rel * a.abs().max_element().max(b.abs().max_element()).max(1e-6)
}

/// Unwelds the triangles and gives each its face normal (the spec's rule for primitives
/// without normals).
pub(super) fn flat_shaded(positions: &[Vec3], uvs: &[Vec2], indices: &[u32]) -> Mesh {
    let mut m = Mesh::default();
    for (t, tri) in indices.chunks_exact(3).enumerate() {
        let [a, b, c] = [0, 1, 2].map(|k| positions[tri[k] as usize]);
        let normal = (b - a).cross(c - a).normalize_or(Vec3::Y);
        for &i in tri {
            m.positions.push(positions[i as usize]);
            m.uvs.push(uvs[i as usize]);
            m.normals.push(normal);
        }
        let base = 3 * t as u32;
        m.indices.extend([base, base + 1, base + 2]);
    }
    m
}

/// How much of a surface of material `m` its alpha leaves standing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Coverage {
    /// All of it: opaque, or a mask or blend whose constant alpha keeps everything.
    All,
    /// None: a mask whose constant alpha is below its cutoff, or a blend of alpha 0.
    None,
    /// Where the base colour texture's alpha is at least this value: a textured mask whose
    /// factor keeps some of it (glTF compares factor times texture alpha with the cutoff, so
    /// the texture's own threshold is the cutoff over the factor). Exact for a diffuse
    /// material ([`Material::Diffuse`]'s `cutout`); metal and glass read no texture and are
    /// rendered opaque, with a note.
    Cutout(f32),
    /// Some, which the importer does not render: a textured blend, or a blend between 0 and 1.
    /// Rendered opaque, with a note.
    Partial,
}

/// The coverage of material `m`'s alpha (glTF's `alphaMode`, `alphaCutoff` and the base
/// colour's alpha, times the base colour texture's where it has one).
pub(super) fn alpha_coverage(m: &gltf::Material) -> Coverage {
    use gltf::material::AlphaMode;
    let pbr = m.pbr_metallic_roughness();
    let alpha = pbr.base_color_factor()[3];
    let cutoff = m.alpha_cutoff().unwrap_or(0.5);
    let textured = pbr.base_color_texture().is_some();
    // A texture's alpha is at most 1: it can only lower the factor's.
    match m.alpha_mode() {
        AlphaMode::Opaque => Coverage::All,
        AlphaMode::Mask if alpha < cutoff => Coverage::None,
        AlphaMode::Blend if alpha <= 0.0 => Coverage::None,
        AlphaMode::Mask if textured && cutoff > 0.0 => Coverage::Cutout(cutoff / alpha),
        _ if textured && m.alpha_mode() == AlphaMode::Blend => Coverage::Partial,
        AlphaMode::Mask => Coverage::All,
        AlphaMode::Blend if alpha >= 1.0 => Coverage::All,
        AlphaMode::Blend => Coverage::Partial,
    }
}

/// A camera that sees the world-space bounds of `objects` (45 degrees, from +Z and a little
/// above).
pub(super) fn frame_objects(objects: &[Object]) -> Camera {
    let (lo, hi) = crate::world_bounds(objects);
    let (center, radius) = if lo.cmple(hi).all() {
        ((lo + hi) * 0.5, ((hi - lo).length() * 0.5).max(1e-3))
    } else {
        (Vec3::ZERO, 1.0)
    };
    let fov_y_deg = 45.0f32;
    let distance = radius / (fov_y_deg.to_radians() * 0.5).sin() * 1.05;
    Camera {
        eye: center + Vec3::new(0.0, 0.25, 1.0).normalize() * distance,
        target: center,
        up: Vec3::Y,
        fov_y_deg,
        orthographic: None,
    }
}

/// The scene camera from the first camera met: exact, or at the node looking at the centre
/// of the objects' bounds; else one that frames the objects.
fn placed_camera(camera: Option<FoundCamera>, objects: &[Object]) -> Camera {
    match camera {
        Some(FoundCamera::Exact(c)) => c,
        Some(FoundCamera::Derived {
            eye,
            forward,
            up,
            fov_y_deg,
            orthographic,
        }) => {
            let (lo, hi) = crate::world_bounds(objects);
            let d = ((lo + hi) * 0.5 - eye).length();
            let d = if d.is_finite() && d > 1e-3 { d } else { 1.0 };
            Camera {
                eye,
                target: eye + forward * d,
                up,
                fov_y_deg,
                orthographic,
            }
        }
        None => frame_objects(objects),
    }
}

impl VolumeExtras {
    fn volume(&self) -> Volume {
        let v = self;
        Volume {
            name: v.name.clone(),
            center: vec3(v.center),
            radius: v.radius as f32,
            color: vec3(v.color),
            density: v.density as f32,
            profile: v
                .profile
                .as_ref()
                .map_or(DensityProfile::UNIFORM, |p| p.profile()),
            particle: v.particle,
            motion: motion_from(&v.motion),
        }
    }
}
