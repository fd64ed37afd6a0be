//! The CPU reference renderer: the ground truth. (Being written.)
