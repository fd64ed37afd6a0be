//! What a technique asks of the renderer that hosts it: its world drawn from another view.
//!
//! A distance impostor needs the surroundings of its object in the six faces of a cube map,
//! an image-space refractor the room around it: views the eye never sees. The technique does
//! not own the world, so it asks: [`DrawScene::draw_scene`] draws these objects, or everything
//! but these, with this view, into these targets. The harness's scene (`scene::GpuScene`)
//! implements it with the shared raster pass; a user's renderer implements it with its own
//! pipelines, and the technique never sees its vertex layout, materials or lights.

use crate::Frame;
use glam::{Mat4, Vec3};

/// The distance a host writes in alpha where a view sees no surface (the scene's
/// `BACKGROUND_DISTANCE`): "farther than anything", which the searches treat as the
/// background.
pub const BACKGROUND_DISTANCE: f32 = 60000.0;

/// Which of the host's objects a view draws, by the host's own object indices (the ones the
/// host gave the technique for its specular objects).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Objects<'a> {
    /// Every opaque object.
    All,
    /// Only these.
    Only(&'a [usize]),
    /// Every opaque object but these (an impostor's own object is not in its map).
    AllBut(&'a [usize]),
}

impl Objects<'_> {
    /// Whether the object of index `object` is drawn.
    pub fn includes(&self, object: usize) -> bool {
        match self {
            Objects::All => true,
            Objects::Only(list) => list.contains(&object),
            Objects::AllBut(list) => !list.contains(&object),
        }
    }
}

/// One view of the host's world into targets the technique owns.
pub struct SceneView<'a> {
    /// World to clip space (wgpu's: depth in [0, 1]).
    pub view_proj: Mat4,
    /// The view's centre of projection, from which alpha's distance is measured.
    pub eye: Vec3,
    /// The objects to draw.
    pub objects: Objects<'a>,
    /// The colour target (mip level 0 of one layer), of `color_format`.
    pub color: &'a wgpu::TextureView,
    /// The colour target's format: the technique's choice, `Rgba16Float` (the maps of the
    /// impostors and of image-space refraction) or [`crate::HDR_FORMAT`]; a host draws into
    /// both (`scene::GpuScene` does).
    pub color_format: wgpu::TextureFormat,
    /// The depth target, [`crate::DEPTH_FORMAT`].
    pub depth: &'a wgpu::TextureView,
}

/// A renderer's object as it hands it to a technique that draws it (a glass or metal object):
/// its triangles in the object's own frame.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct HostedMesh {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Unit vertex normals, outward.
    pub normals: Vec<Vec3>,
    /// Triangles, three vertex indices each.
    pub indices: Vec<u32>,
}

/// A renderer's camera for one frame, as a technique's pass in its frame takes it: world to
/// view (right-handed, looking down -z), view to clip (wgpu's clip space, depth in [0, 1],
/// not reversed), and the size of its targets in pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EyeView {
    /// World to view (`glam::camera::rh::view::look_at_mat4`).
    pub view: Mat4,
    /// View to clip (`glam::camera::rh::proj::directx::perspective`).
    pub projection: Mat4,
    /// Width of the colour and depth targets, in pixels.
    pub width: u32,
    /// Height of the colour and depth targets, in pixels.
    pub height: u32,
}

impl EyeView {
    /// World to clip.
    pub fn view_proj(&self) -> Mat4 {
        self.projection * self.view
    }

    /// The eye's position in the world.
    pub fn eye(&self) -> Vec3 {
        self.view.inverse().w_axis.truncate()
    }

    /// The eye's (forward, right, up) unit axes in the world.
    pub fn basis(&self) -> (Vec3, Vec3, Vec3) {
        let world = self.view.inverse();
        (
            -world.z_axis.truncate().normalize(),
            world.x_axis.truncate().normalize(),
            world.y_axis.truncate().normalize(),
        )
    }
}

/// A renderer that can draw its world for a technique.
///
/// The contract, which the techniques' maps rely on: clear the colour to the background's
/// radiance with alpha [`BACKGROUND_DISTANCE`], and the depth to 1; draw the opaque (diffuse) surfaces of
/// `view.objects` with depth test `Less`, writing linear radiance in rgb and the surface's
/// distance from `view.eye` in alpha. Specular objects are the techniques' to draw; a host
/// leaves them out.
pub trait DrawScene {
    /// Records the draw of `view` into `frame`'s encoder.
    fn draw_scene(&self, frame: &mut Frame, view: &SceneView);
}

/// Draws the host's `objects` into the six faces of `cube` as seen from `center` (near plane
/// `near`, far plane `far`): how an impostor or a room probe is made.
pub fn draw_scene_cube(
    frame: &mut Frame,
    host: &dyn DrawScene,
    cube: &crate::cube::CubeTarget,
    center: Vec3,
    (near, far): (f32, f32),
    objects: Objects,
) {
    for index in 0..6 {
        let view = SceneView {
            view_proj: crate::cube::cube_face_view_proj(index, center, near, far),
            eye: center,
            objects,
            color: &cube.face_views[index],
            color_format: cube.format,
            depth: &cube.depth_face_views[index],
        };
        host.draw_scene(frame, &view);
    }
}
