//! A renderer's own objects uploaded alone, for a technique's pass in the renderer's frame
//! ([`HostedPass`]: `impostors::ImpostorPass`, `image_space_refraction::RefractorPass`,
//! `refractor_maps::RefractorMapsPass`, `height_maps::HeightMapPass`,
//! `interior_mapping::InteriorPass`): the technique draws the objects from this copy and asks
//! the renderer ([`gpu::DrawScene`]) for everything else.

use crate::{Camera, GpuScene, Material, Mesh, Object, Scene, Technique, TechniqueError};
use crate::{Frame, TechniqueResult};
use glam::{Mat4, Vec2, Vec3};
use gpu::{DrawScene, EyeView, HostedMesh, Objects, SceneView, TargetFormats, wgpu};

/// A technique that draws its objects over a frame that already holds everything else, asking
/// the frame's renderer for the views of the world it needs.
pub trait DrawOver: Technique {
    /// The objects of `objects` drawn into `color` and `depth` (a renderer's targets, holding
    /// its frame) as `view` sees them, with `host` drawing the world on request.
    fn draw_over(
        &mut self,
        frame: &mut Frame,
        hosted: (&GpuScene, &dyn DrawScene),
        view: &EyeView,
        color: &wgpu::TextureView,
        depth: &wgpu::TextureView,
    ) -> TechniqueResult<()>;
}

/// What a renderer's specular object is made of.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Surface {
    /// A dielectric with this index of refraction (air outside).
    Glass {
        /// Index of refraction relative to the surrounding air.
        ior: f32,
    },
    /// A conductor with this complex index of refraction per RGB channel.
    Metal {
        /// Real part `n`.
        n: Vec3,
        /// Imaginary part `k` (n = 0, k = 1 is a perfect mirror).
        k: Vec3,
    },
}

impl From<Surface> for Material {
    fn from(surface: Surface) -> Material {
        match surface {
            Surface::Glass { ior } => Material::Glass { ior },
            Surface::Metal { n, k } => Material::Metal { n, k },
        }
    }
}

/// One of the renderer's objects as a pass takes it: its triangles in its own frame, its
/// material, its index among the renderer's objects, and where it stands (an offset from
/// where its mesh puts it).
#[derive(Clone, Debug)]
pub struct HostedPiece<'a> {
    /// Its triangles in its own frame.
    pub mesh: &'a HostedMesh,
    /// What it is made of (glass or metal: the technique draws it).
    pub material: Material,
    /// Its index among the renderer's objects: the one the renderer's [`DrawScene`] leaves out
    /// of the views the technique asks for.
    pub host_index: usize,
    /// Where it stands: the offset from where its mesh puts it.
    pub position: Vec3,
}

/// Some of a renderer's objects drawn by technique `T` over the renderer's frame: the pass a
/// technique crate hands a user (`impostors::ImpostorPass` and the others wrap one each and
/// say how to make it).
pub struct HostedPass<T> {
    technique: T,
    objects: HostedObjects,
}

impl<T: DrawOver> HostedPass<T> {
    /// `technique` (already made for `formats`) prepared on the renderer's `objects`, each
    /// where its `position` puts it. Formats the device cannot draw into are refused.
    pub fn new(
        ctx: &gpu::Context,
        formats: TargetFormats,
        objects: &[HostedPiece],
        technique: T,
    ) -> TechniqueResult<Self> {
        let indices = objects.iter().map(|o| o.host_index).collect();
        Self::of_scene(ctx, formats, (objects_scene(objects)?, indices), technique)
    }

    /// `technique` prepared on `scene`, the renderer's objects as the technique needs them (with
    /// roles, a building's room layout, the lights that shade them), object `i` being the
    /// renderer's object `host_indices[i]`: for a pass whose objects are more than a mesh and a
    /// material (`interior_mapping::InteriorPass`).
    pub fn of_scene(
        ctx: &gpu::Context,
        formats: TargetFormats,
        (scene, host_indices): (Scene, Vec<usize>),
        mut technique: T,
    ) -> TechniqueResult<Self> {
        formats.check(ctx)?;
        let mut objects = HostedObjects::of_scene(ctx, &scene, host_indices)?;
        objects.prepare(ctx, &mut technique)?;
        Ok(Self { technique, objects })
    }

    /// Moves the pass's object `index` (in the order the pass was given them) by `offset` from
    /// where its mesh puts it, from the next frame on.
    ///
    /// # Panics
    ///
    /// If the pass holds no object `index`.
    pub fn set_position_of(&mut self, index: usize, offset: Vec3) {
        self.objects.set_offset(index, offset);
    }

    /// The technique, for its settings and figures.
    pub fn technique(&self) -> &T {
        &self.technique
    }

    /// Records the objects into `color` and `depth` as seen by `view`, asking `host` for the
    /// world around them, depth-tested against the renderer's frame.
    pub fn draw(
        &mut self,
        frame: &mut Frame,
        host: &dyn DrawScene,
        view: &EyeView,
        color: &wgpu::TextureView,
        depth: &wgpu::TextureView,
    ) -> TechniqueResult<()> {
        let (objects, host) = self.objects.for_frame(frame, host);
        let hosted: (&GpuScene, &dyn DrawScene) = (objects, &host);
        self.technique.draw_over(frame, hosted, view, color, depth)
    }
}

/// A technique crate's pass, the newtype `$pass(HostedPass<$technique>)` that says how to make
/// it, offering the `HostedPass`'s `draw` and `set_position_of` (`Deref` and `DerefMut` to it).
#[macro_export]
macro_rules! hosted_pass_deref {
    ($pass:ty, $technique:ty) => {
        impl std::ops::Deref for $pass {
            type Target = $crate::hosted::HostedPass<$technique>;
            fn deref(&self) -> &Self::Target {
                &self.0
            }
        }

        impl std::ops::DerefMut for $pass {
            fn deref_mut(&mut self) -> &mut Self::Target {
                &mut self.0
            }
        }
    };
}

/// The renderer's objects, uploaded alone (no lights: the maps the technique asks for hold
/// the renderer's lit world), and their indices among the renderer's objects.
pub struct HostedObjects {
    uploaded: GpuScene,
    /// The renderer's index of each uploaded object.
    host_indices: Vec<usize>,
    /// Each object's transform without its translation: what an offset places.
    linear: Vec<Mat4>,
    /// The offsets `set_offset` asked for, applied at the next frame.
    pending_offsets: Vec<Option<Vec3>>,
}

impl HostedObjects {
    /// `objects` uploaded, each where its `position` puts it.
    pub fn new(ctx: &gpu::Context, objects: &[HostedPiece]) -> TechniqueResult<Self> {
        let indices = objects.iter().map(|o| o.host_index).collect();
        Self::of_scene(ctx, &objects_scene(objects)?, indices)
    }

    /// `scene` uploaded, its object `i` the renderer's object `host_indices[i]`; an offset moves
    /// an object: its transform's translation becomes the offset.
    pub fn of_scene(
        ctx: &gpu::Context,
        scene: &Scene,
        host_indices: Vec<usize>,
    ) -> TechniqueResult<Self> {
        if scene.objects.is_empty() {
            return Err(TechniqueError::Unsupported(
                "a pass needs at least one of the renderer's objects to draw".into(),
            ));
        }
        if host_indices.len() != scene.objects.len() {
            return Err(TechniqueError::Unsupported(format!(
                "{} objects but {} renderer's indices",
                scene.objects.len(),
                host_indices.len()
            )));
        }
        let linear = scene
            .objects
            .iter()
            .map(|o| {
                let mut linear = o.transform;
                linear.w_axis = glam::Vec4::W;
                linear
            })
            .collect();
        Ok(Self {
            uploaded: GpuScene::new(ctx, scene)?,
            pending_offsets: vec![None; host_indices.len()],
            host_indices,
            linear,
        })
    }

    /// Prepares `technique` on the object (its maps, pipelines), recorded and submitted now;
    /// a validation error (a target format the device cannot render into, say) is a
    /// [`TechniqueError`], not wgpu's panic.
    pub fn prepare(
        &mut self,
        ctx: &gpu::Context,
        technique: &mut dyn Technique,
    ) -> TechniqueResult<()> {
        let uploaded = &mut self.uploaded;
        ctx.validated(|| {
            let mut encoder = ctx.device.create_command_encoder(&Default::default());
            let prepared = Frame::untimed(ctx, &mut encoder, |frame| {
                uploaded.set_time(frame, 0.0);
                technique.prepare(frame, uploaded)
            });
            ctx.queue.submit([encoder.finish()]);
            prepared
        })?
    }

    /// Moves object `index` by `offset` from where its mesh puts it (its rotation and scale
    /// kept), from the next frame on.
    ///
    /// # Panics
    ///
    /// If there is no object `index`.
    pub fn set_offset(&mut self, index: usize, offset: Vec3) {
        let count = self.pending_offsets.len();
        let Some(pending) = self.pending_offsets.get_mut(index) else {
            panic!("no object {index} to move: the pass holds {count}");
        };
        *pending = Some(offset);
    }

    /// The uploaded objects at their current offsets (recorded into `frame`), and the renderer
    /// as host with the objects' indices turned into the renderer's own.
    pub fn for_frame<'a>(
        &'a mut self,
        frame: &mut Frame,
        host: &'a dyn DrawScene,
    ) -> (&'a GpuScene, HostForObjects<'a>) {
        let placed: Vec<(usize, Mat4)> = (self.pending_offsets.iter_mut().enumerate())
            .filter_map(|(index, pending)| pending.take().map(|offset| (index, offset)))
            .map(|(index, offset)| (index, Mat4::from_translation(offset) * self.linear[index]))
            .collect();
        if !placed.is_empty() {
            self.uploaded.set_transforms(frame, &placed);
        }
        let indices = &self.host_indices;
        (&self.uploaded, HostForObjects { host, indices })
    }
}

/// The scene of a renderer's objects, each placed where its position puts it.
fn objects_scene(pieces: &[HostedPiece]) -> TechniqueResult<Scene> {
    let mut objects = Vec::new();
    for (i, piece) in pieces.iter().enumerate() {
        let mesh = piece.mesh;
        if mesh.positions.len() != mesh.normals.len() {
            return Err(TechniqueError::Unsupported(format!(
                "the renderer's object {} has {} positions but {} normals",
                piece.host_index,
                mesh.positions.len(),
                mesh.normals.len()
            )));
        }
        let mesh = Mesh {
            positions: mesh.positions.clone(),
            normals: mesh.normals.clone(),
            uvs: vec![Vec2::ZERO; mesh.positions.len()],
            indices: mesh.indices.clone(),
        };
        let placed = Mat4::from_translation(piece.position);
        let name = format!("hosted {i}");
        objects.push(Object::new(&name, mesh, piece.material.clone(), placed));
    }
    Ok(Scene {
        name: "hosted objects".into(),
        objects,
        ..empty_scene()
    })
}

/// A scene with nothing in it, no light and a black background: what a pass's own objects are
/// added to (the renderer draws the rest, and its maps hold the renderer's lit world).
pub fn empty_scene() -> Scene {
    Scene {
        name: "hosted".into(),
        objects: Vec::new(),
        textures: Vec::new(),
        lights: Vec::new(),
        camera: Camera {
            eye: Vec3::new(0.0, 0.0, 3.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_y_deg: 45.0,
            orthographic: None,
        },
        camera_path: Default::default(),
        volumes: Vec::new(),
        medium: None,
        background: Vec3::ZERO,
    }
}

/// The renderer as host of its objects: their indices in the upload turned into the
/// renderer's own in every list a technique passes.
pub struct HostForObjects<'a> {
    host: &'a dyn DrawScene,
    indices: &'a [usize],
}

impl DrawScene for HostForObjects<'_> {
    fn draw_scene(&self, frame: &mut Frame, view: &SceneView) {
        // The upload holds the pass's objects only: a list names some of them.
        let renamed = |list: &[usize]| -> Vec<usize> {
            list.iter()
                .filter_map(|&i| self.indices.get(i).copied())
                .collect()
        };
        let (only, all_but);
        let objects = match view.objects {
            Objects::All => Objects::All,
            Objects::Only(list) => {
                only = renamed(list);
                Objects::Only(&only)
            }
            Objects::AllBut(list) => {
                all_but = renamed(list);
                Objects::AllBut(&all_but)
            }
        };
        let view = SceneView {
            objects,
            view_proj: view.view_proj,
            eye: view.eye,
            color: view.color,
            color_format: view.color_format,
            depth: view.depth,
        };
        self.host.draw_scene(frame, &view);
    }
}
