//! A renderer's own object uploaded alone, for a technique's pass in the renderer's frame
//! (`impostors::ImpostorPass`, `image_space_refraction::RefractorPass`): the technique draws
//! the object from this copy and asks the renderer ([`gpu::DrawScene`]) for everything else.

use crate::{Camera, GpuScene, Material, Mesh, Object, Scene, Technique, TechniqueError};
use crate::{Frame, TechniqueResult};
use glam::{Mat4, Vec2, Vec3};
use gpu::{DrawScene, HostedMesh, Objects, SceneView};

/// The renderer's object, uploaded alone (no lights: the maps the technique asks for hold
/// the renderer's lit world), and its index among the renderer's objects.
pub struct HostedObject {
    uploaded: GpuScene,
    host_index: usize,
    /// The offset `set_offset` asked for, applied at the next frame.
    pending_offset: Option<Vec3>,
}

impl HostedObject {
    /// `mesh` of `material`, the renderer's object `host_index`, uploaded.
    pub fn new(
        ctx: &gpu::Context,
        mesh: &HostedMesh,
        material: Material,
        host_index: usize,
    ) -> TechniqueResult<Self> {
        let scene = object_scene(mesh, material)?;
        Ok(Self {
            uploaded: GpuScene::new(ctx, &scene)?,
            host_index,
            pending_offset: None,
        })
    }

    /// [`HostedObject::new`], with `technique` prepared on it.
    pub fn prepared(
        ctx: &gpu::Context,
        (mesh, material, host_index): (&HostedMesh, Material, usize),
        technique: &mut dyn Technique,
    ) -> TechniqueResult<Self> {
        let mut object = Self::new(ctx, mesh, material, host_index)?;
        object.prepare(ctx, technique)?;
        Ok(object)
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
            let mut timer = gpu::GpuTimer::off();
            let mut frame = Frame {
                gpu: ctx,
                encoder: &mut encoder,
                timer: &mut timer,
            };
            uploaded.set_time(&mut frame, 0.0);
            let prepared = technique.prepare(&mut frame, uploaded);
            ctx.queue.submit([encoder.finish()]);
            prepared
        })?
    }

    /// Moves the object by `offset` from where its mesh puts it, from the next frame on.
    pub fn set_offset(&mut self, offset: Vec3) {
        self.pending_offset = Some(offset);
    }

    /// The uploaded object at its current offset (recorded into `frame`), and the renderer as
    /// host with the object's index turned into the renderer's own.
    pub fn for_frame<'a>(
        &'a mut self,
        frame: &mut Frame,
        host: &'a dyn DrawScene,
    ) -> (&'a GpuScene, HostForObject<'a>) {
        if let Some(offset) = self.pending_offset.take() {
            let placed = Mat4::from_translation(offset);
            self.uploaded.set_transform(frame, 0, placed);
        }
        let index = self.host_index;
        (&self.uploaded, HostForObject { host, index })
    }
}

/// The one-object scene of a renderer's object.
fn object_scene(mesh: &HostedMesh, material: Material) -> TechniqueResult<Scene> {
    if mesh.positions.len() != mesh.normals.len() {
        return Err(TechniqueError::Unsupported(format!(
            "the renderer's object has {} positions but {} normals",
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
    Ok(Scene {
        name: "hosted object".into(),
        objects: vec![Object::new("hosted", mesh, material, Mat4::IDENTITY)],
        textures: Vec::new(),
        lights: Vec::new(),
        camera: Camera {
            eye: Vec3::new(0.0, 0.0, 3.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_y_deg: 45.0,
        },
        camera_path: Default::default(),
        volumes: Vec::new(),
        medium: None,
        background: Vec3::ZERO,
    })
}

/// The renderer as host of the object: its index in the one-object upload (0) turned into the
/// renderer's own in every list a technique passes.
pub struct HostForObject<'a> {
    host: &'a dyn DrawScene,
    index: usize,
}

impl DrawScene for HostForObject<'_> {
    fn draw_scene(&self, frame: &mut Frame, view: &SceneView) {
        // The upload holds one object, index 0: a list names it or nothing.
        let renamed = |list: &[usize]| -> Vec<usize> {
            list.iter()
                .filter(|&&i| i == 0)
                .map(|_| self.index)
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
