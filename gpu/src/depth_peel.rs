//! Depth peeling: N layers of depth + normal of a triangle set seen from a camera.
