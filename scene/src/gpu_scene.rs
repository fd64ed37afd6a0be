//! GPU upload and the shared raster pass. (Being written.)
pub struct GpuScene {}
pub struct ObjectFilter {}
pub struct RasterTarget {}
