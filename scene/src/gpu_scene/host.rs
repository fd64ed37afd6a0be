//! The uploaded scene as the host a technique asks for views of its world
//! ([`gpu::DrawScene`]): the shared raster pass, so every map a technique asks for is the one
//! it made before the trait existed.

use super::{GpuScene, ObjectFilter, RasterTarget};
use crate::Frame;
use gpu::{DrawScene, Objects, SceneView};

impl DrawScene for GpuScene {
    /// The shared raster pass (diffuse surfaces, the reference's shading, distance from the
    /// eye in alpha) of `view.objects` into `view`'s targets, cleared first; specular objects
    /// are left out, as the trait asks.
    fn draw_scene(&self, frame: &mut Frame, view: &SceneView) {
        let target = RasterTarget {
            color: view.color,
            depth: view.depth,
            format: view.color_format,
            clear: true,
        };
        let filter = object_filter(view.objects);
        self.raster(frame, &target, view.view_proj, view.eye, &filter, false);
    }
}

/// The scene's filter of a host's object list.
fn object_filter(objects: Objects) -> ObjectFilter {
    match objects {
        Objects::All => ObjectFilter::All,
        Objects::Only(list) => ObjectFilter::Only(list.to_vec()),
        Objects::AllBut(list) => ObjectFilter::Except(list.to_vec()),
    }
}
