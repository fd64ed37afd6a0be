//! Real room geometry for the `interior/polygons` baseline: a facade with a window hole per
//! room cell and planes spanning the hull's inside (floors, ceilings, two wall families),
//! textured per room. These are the `city` scene's own generators (`scene::builtin::city`), so
//! the baseline draws exactly the rooms the reference traces.

pub use scene::builtin::city::{
    SLAB_HALF, WINDOW_SIDE, WINDOW_SILL, WINDOW_TOP, facade_with_windows, is_window, room_planes,
};
