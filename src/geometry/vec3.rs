//! Vec3 arithmetic: a few plain functions on `[f64; 3]` rather than a vector type (nalgebra's
//! Vector3 or a newtype). Every stage passes Vec3 as plain data (Tick, Block, the postcard FMU
//! state), these run in the hottest loops (path evaluation every tick, the look-ahead at 1 M
//! blocks/s) and compile to the same three multiply-adds; a wrapper would change every record
//! for no gain.

/// A point or vector in machine axes X, Y, Z (m).
pub type Vec3 = [f64; 3];

pub fn add(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
pub fn sub(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
pub fn scale(a: Vec3, k: f64) -> Vec3 {
    [a[0] * k, a[1] * k, a[2] * k]
}
pub fn dot(a: Vec3, b: Vec3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
pub fn norm(a: Vec3) -> f64 {
    dot(a, a).sqrt()
}
pub fn cross(a: Vec3, b: Vec3) -> Vec3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
/// a/|a|, zero for a zero vector.
pub fn unit(a: Vec3) -> Vec3 {
    let n = norm(a);
    if n > 0.0 {
        scale(a, 1.0 / n)
    } else {
        [0.0; 3]
    }
}

/// The unit vector of axis i.
pub fn basis(i: usize) -> Vec3 {
    let mut e = [0.0; 3];
    e[i] = 1.0;
    e
}
