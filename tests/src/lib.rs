//! Tests that cross crates (`tests/`): every registered technique on every built-in scene,
//! every declared image check against the reference, the foundation's claims, and the
//! repository's own rules. Their helpers are the workspace's `testkit`.
