//! Image error metrics against the reference. (Being written.)
